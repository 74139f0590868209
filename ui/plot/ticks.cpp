#include "ui/plot/ticks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace gmslab::ui {

Ticks nice_ticks(double lo, double hi, int target) {
  Ticks t;
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo)) return t;
  if (target < 2) target = 2;
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10.0 * mag;
  for (const double m : {1.0, 2.0, 2.5, 5.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  if (!(step > 0.0) || !std::isfinite(step)) return t;
  t.step = step;
  const double first = std::ceil(lo / step - 1e-9);
  const double last = std::floor(hi / step + 1e-9);
  if (last - first > 1000.0) return t;  // only when step underflows relative to lo
  for (double k = first; k <= last; k += 1.0) {
    double v = k * step;
    if (std::fabs(v) < step * 1e-9) v = 0.0;  // no "-0" and no 1e-17 at the origin
    t.values.push_back(v);
  }
  // A range just short of two steps of the rounded-up step would get one tick, which cannot
  // show a scale: ask for more until at least two land in the range.
  if (t.values.size() < 2 && target < 12) return nice_ticks(lo, hi, target + 1);
  return t;
}

std::string format_tick(double value, double step, double magnitude) {
  if (value == 0.0) return "0";
  char buf[48];
  const double av = std::fabs(value);
  const double mag = magnitude > 0.0 ? magnitude : av;
  if (mag >= 1e5 || mag < 1e-3) {
    // Scientific: enough mantissa digits to separate neighbours.
    const int exp10 = static_cast<int>(std::floor(std::log10(av)));
    const int digits = std::max(0, exp10 - static_cast<int>(std::floor(std::log10(step))) + 1);
    std::snprintf(buf, sizeof buf, "%.*e", std::min(digits, 6), value);
    // Trim mantissa zeros: "1.50e-05" -> "1.5e-05".
    std::string s = buf;
    const auto e = s.find('e');
    std::string mant = s.substr(0, e), ex = s.substr(e);
    if (mant.find('.') != std::string::npos) {
      while (mant.back() == '0') mant.pop_back();
      if (mant.back() == '.') mant.pop_back();
    }
    return mant + ex;
  }
  // Decimals needed to write the step exactly (0.25 -> 2, 0.5 -> 1, 20 -> 0).
  int decimals = 0;
  for (double scaled = step; decimals < 9; ++decimals, scaled *= 10.0)
    if (std::fabs(scaled - std::round(scaled)) < 1e-6 * std::max(1.0, scaled)) break;
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  std::string s = buf;
  return s;
}

}  // namespace gmslab::ui
