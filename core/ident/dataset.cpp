#include "core/ident/dataset.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>

#include <Eigen/Dense>

#include "core/error.hpp"
#include "core/io/measured_file.hpp"

namespace gmslab::ident {

std::size_t Dataset::used() const {
  std::size_t n = 0;
  for (auto u : use) n += u;
  return n;
}

namespace {
bool to_double(std::string_view s, double& out) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(out);
}
}  // namespace

std::vector<TimeWindow> parse_masks(std::string_view spec, std::string_view what) {
  std::vector<TimeWindow> out;
  std::size_t start = 0;
  while (start <= spec.size()) {
    auto c = spec.find(',', start);
    if (c == std::string_view::npos) c = spec.size();
    const auto item = spec.substr(start, c - start);
    start = c + 1;
    if (item.empty()) continue;
    const auto colon = item.find(':');
    TimeWindow w;
    if (colon == std::string_view::npos || !to_double(item.substr(0, colon), w.t0) ||
        !to_double(item.substr(colon + 1), w.t1) || !(w.t1 > w.t0))
      throw InputError(std::string(what) + ": '" + std::string(item) +
                       "': expected T0:T1 in seconds with T1 > T0, e.g. 1.5:2.0,7:7.25");
    out.push_back(w);
  }
  return out;
}

std::vector<TimeWindow> edge_windows(const std::vector<double>& t, const std::vector<double>& code,
                                     double before, double after) {
  std::vector<TimeWindow> out;
  for (std::size_t k = 1; k < t.size() && k < code.size(); ++k)
    if (code[k] != code[k - 1]) out.push_back({t[k] - before, t[k] + after});
  return out;
}

std::vector<TimeWindow> parse_edge_masks(std::string_view spec, const MeasuredRecord& r,
                                         std::string_view what, std::string* note) {
  if (spec.empty()) return {};
  const auto c1 = spec.find(':');
  const auto c2 = c1 == std::string_view::npos ? c1 : spec.find(':', c1 + 1);
  double before = 0, after = 0;
  if (c1 == 0 || c2 == std::string_view::npos || !to_double(spec.substr(c1 + 1, c2 - c1 - 1), before) ||
      !to_double(spec.substr(c2 + 1), after))
    throw InputError(std::string(what) + " '" + std::string(spec) +
                     "': expected COLUMN:BEFORE:AFTER in seconds, e.g. pulse_code:0.005:0.060");
  if (!(before >= 0 && after >= 0))
    throw InputError(std::string(what) + " '" + std::string(spec) + "': BEFORE and AFTER must be >= 0 s");
  const std::string column(spec.substr(0, c1));
  const auto* col = r.extra_column(column);
  if (!col) {
    if (note) {
      std::string have;
      for (const auto& [name, values] : r.extra) have += (have.empty() ? "" : ", ") + name;
      *note = std::string(what) + ": no column '" + column + "' in " +
              std::filesystem::path(r.source).filename().string() + ", so none are masked there (its other columns: " +
              (have.empty() ? "none" : have) + ")";
    }
    return {};
  }
  return edge_windows(r.t, *col, before, after);
}

Dataset load_dataset(const RecordSpec& spec, std::string* note) {
  CsvColumns cols = spec.columns.empty() ? CsvColumns{} : parse_column_map(spec.columns);
  cols.force = spec.force;
  const auto rec = load_measured(spec.path, cols);
  auto windows = parse_masks(spec.mask, spec.mask_what);
  const auto e = parse_edge_masks(spec.mask_edges, rec, spec.edges_what, note);
  windows.insert(windows.end(), e.begin(), e.end());
  return prepare_dataset(rec, windows);
}

namespace {

// The derivative of order `order` at each sample of a least-squares polynomial of degree
// `Degree` over 2 half + 1 samples centred on it (shifted inwards at the ends).
template <int Degree>
std::vector<double> local_polynomial_derivative(const std::vector<double>& t,
                                                const std::vector<double>& y, std::ptrdiff_t half,
                                                int order) {
  using Vec = Eigen::Matrix<double, Degree + 1, 1>;
  const auto n = static_cast<std::ptrdiff_t>(t.size());
  std::vector<double> s(t.size(), 0.0);
  const double factorial = order == 2 ? 2.0 : 1.0;
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const std::ptrdiff_t lo = std::clamp<std::ptrdiff_t>(k - half, 0, n - 1 - 2 * half);
    const std::ptrdiff_t hi = lo + 2 * half;
    const double scale = std::max(std::abs(t[hi] - t[k]), std::abs(t[lo] - t[k]));
    if (!(scale > 0)) continue;
    Eigen::Matrix<double, Degree + 1, Degree + 1> G = decltype(G)::Zero();
    Vec b = Vec::Zero();
    for (auto j = lo; j <= hi; ++j) {
      const double u = (t[j] - t[k]) / scale;
      Vec p;
      p(0) = 1.0;
      for (int i = 1; i <= Degree; ++i) p(i) = p(i - 1) * u;
      G.noalias() += p * p.transpose();
      b.noalias() += p * (y[j] - y[k]);
    }
    const Vec c = G.ldlt().solve(b);
    s[k] = std::isfinite(c(order)) ? factorial * c(order) / std::pow(scale, order) : 0.0;
  }
  return s;
}

}  // namespace

std::vector<double> local_derivative(const std::vector<double>& t, const std::vector<double>& y,
                                     int w) {
  const auto n = static_cast<std::ptrdiff_t>(t.size());
  if (n < 5) return local_slope(t, y, w);
  const std::ptrdiff_t half = std::min<std::ptrdiff_t>(std::max(w, 2), (n - 1) / 2);
  return local_polynomial_derivative<3>(t, y, half, 1);
}

std::vector<double> local_cubic_value(const std::vector<double>& t, const std::vector<double>& y,
                                      int w) {
  const auto n = static_cast<std::ptrdiff_t>(t.size());
  if (n < 5) return y;
  const std::ptrdiff_t half = std::min<std::ptrdiff_t>(std::max(w, 2), (n - 1) / 2);
  std::vector<double> s = local_polynomial_derivative<3>(t, y, half, 0);
  for (std::size_t k = 0; k < s.size(); ++k) s[k] += y[k];
  return s;
}

std::vector<double> local_second_derivative(const std::vector<double>& t,
                                            const std::vector<double>& y, int w) {
  const auto n = static_cast<std::ptrdiff_t>(t.size());
  const std::ptrdiff_t half = std::max(w, 2);
  if (n < 2 * half + 1) return local_slope(t, local_derivative(t, y, w), w);
  return local_polynomial_derivative<4>(t, y, half, 2);
}

std::vector<double> local_slope(const std::vector<double>& t, const std::vector<double>& y, int w) {
  const auto n = static_cast<std::ptrdiff_t>(t.size());
  std::vector<double> s(t.size(), 0.0);
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const auto lo = std::max<std::ptrdiff_t>(0, k - w);
    const auto hi = std::min<std::ptrdiff_t>(n - 1, k + w);
    double mt = 0.0, my = 0.0;
    for (auto j = lo; j <= hi; ++j) {
      mt += t[j] - t[k];
      my += y[j];
    }
    const double m = static_cast<double>(hi - lo + 1);
    mt /= m;
    my /= m;
    double stt = 0.0, sty = 0.0;
    for (auto j = lo; j <= hi; ++j) {
      const double dt = t[j] - t[k] - mt;
      stt += dt * dt;
      sty += dt * (y[j] - my);
    }
    s[k] = stt > 0.0 ? sty / stt : 0.0;
  }
  return s;
}

void set_path(Dataset& d, const PathRule& rule) {
  const std::size_t n = d.size();
  d.sub.clear(), d.sv.clear(), d.sh.clear();
  double q = 0;  // the encoder step (smallest non-zero position step)
  for (std::size_t k = 1; k < n; ++k) {
    const double dx = std::abs(d.x[k] - d.x[k - 1]);
    if (dx > 0 && (q == 0 || dx < q)) q = dx;
  }
  std::vector<std::uint32_t> sub(n + 1, 0);
  std::vector<double> sv, sh;
  for (std::size_t k = 0; k < n; ++k) {
    sub[k] = static_cast<std::uint32_t>(sv.size());
    if (k == 0 || !(d.h[k] > 0)) continue;
    const double h = d.h[k], x0 = d.x[k - 1], x1 = d.x[k], m0 = d.v[k - 1] * h, m1 = d.v[k] * h;
    auto cubic = [&](double s) {
      const double s2 = s * s, s3 = s2 * s;
      return (2 * s3 - 3 * s2 + 1) * x0 + (s3 - 2 * s2 + s) * m0 + (3 * s2 - 2 * s3) * x1 + (s3 - s2) * m1;
    };
    double dev = 0;
    for (double s : {0.25, 0.5, 0.75}) dev = std::max(dev, std::abs(cubic(s) - (x0 + s * (x1 - x0))));
    const bool reversal = d.v[k - 1] * d.v[k] < 0 && std::abs(m0) + std::abs(m1) > 0.25 * q;
    // The speed changing within the step (starts, stops, the Stribeck range): the
    // frozen-velocity step would put the whole change at one end.
    const bool speed_change =
        std::abs(d.v[k] - d.v[k - 1]) > rule.speed_change * std::max(std::abs(d.v[k]), std::abs(d.v[k - 1])) &&
        std::abs(x1 - x0) > q;
    const bool curved = dev > 0.05 * std::abs(x1 - x0) && dev > 0.25 * q;
    int parts = rule.other_parts;
    if (reversal) parts = rule.reversal_parts;
    else if (speed_change || curved) parts = std::max(parts, rule.curved_parts);
    if (parts <= 1) continue;
    double prev = x0;
    for (int j = 1; j <= parts; ++j) {
      const double p = j == parts ? x1 : cubic(static_cast<double>(j) / parts);
      sv.push_back((p - prev) / (h / parts));
      sh.push_back(h / parts);
      prev = p;
    }
  }
  sub[n] = static_cast<std::uint32_t>(sv.size());
  if (!sv.empty()) d.sub = std::move(sub), d.sv = std::move(sv), d.sh = std::move(sh);
}

Dataset decimated(const Dataset& d, std::size_t every, const PathRule& rule) {
  if (every <= 1) return d;
  Dataset s;
  s.source = d.source;
  s.has_v = d.has_v, s.has_Fn = d.has_Fn;
  for (std::size_t k = 0; k < d.size(); k += every) {
    s.t.push_back(d.t[k]), s.x.push_back(d.x[k]), s.v.push_back(d.v[k]), s.a.push_back(d.a[k]);
    s.F.push_back(d.F[k]), s.use.push_back(d.use[k]);
    if (d.has_Fn) s.Fn.push_back(d.Fn[k]);
  }
  const std::size_t n = s.size();
  s.h.assign(n, 0.0);
  s.vstep.assign(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) {
    s.h[k] = s.t[k] - s.t[k - 1];
    s.vstep[k] = (s.x[k] - s.x[k - 1]) / s.h[k];
  }
  set_path(s, rule);
  return s;
}

Dataset prepare_dataset(const MeasuredRecord& r, const std::vector<TimeWindow>& masks,
                        std::size_t edge) {
  Dataset d;
  d.source = r.source;
  d.t = r.t;
  d.x = r.x;
  d.F = r.F;
  d.Fn = r.Fn;
  d.has_Fn = !r.Fn.empty();
  d.has_v = !r.v.empty();
  const std::size_t n = r.size();
  d.v = d.has_v ? r.v : local_derivative(d.t, d.x, 3);
  d.a = d.has_v ? local_slope(d.t, d.v, 3) : local_second_derivative(d.t, d.x, 4);
  d.h.assign(n, 0.0);
  d.vstep.assign(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) {
    d.h[k] = d.t[k] - d.t[k - 1];
    d.vstep[k] = (d.x[k] - d.x[k - 1]) / d.h[k];
  }
  set_path(d, PathRule{});
  d.use.assign(n, 1);
  const std::size_t e = std::min(edge, n / 10);
  for (std::size_t k = 0; k < e; ++k) d.use[k] = d.use[n - 1 - k] = 0;
  for (const auto& w : masks)
    for (std::size_t k = 0; k < n; ++k)
      if (d.t[k] >= w.t0 && d.t[k] <= w.t1) d.use[k] = 0;
  if (d.used() < kMinSamples)
    throw InputError(d.source + ": only " + std::to_string(d.used()) +
                     " samples are left after masking; at least " + std::to_string(kMinSamples) +
                     " are needed (check --mask)");
  return d;
}

Dataset within_encoder_step(const Dataset& d, double q, const PathRule& rule) {
  Dataset s = d;
  if (!(q > 0) || d.size() < 5) return s;
  const std::vector<double> xs = local_cubic_value(d.t, d.x, 3);
  for (std::size_t k = 0; k < d.size(); ++k)
    s.x[k] = std::clamp(xs[k], d.x[k] - 0.5 * q, d.x[k] + 0.5 * q);
  if (!d.has_v) {
    s.v = local_derivative(s.t, s.x, 3);
    s.a = local_second_derivative(s.t, s.x, 4);
  }
  for (std::size_t k = 1; k < s.size(); ++k) s.vstep[k] = (s.x[k] - s.x[k - 1]) / s.h[k];
  set_path(s, rule);
  return s;
}

std::pair<Dataset, Dataset> split_holdout(const Dataset& d, double fraction, int blocks) {
  Dataset train = d, val = d;
  const int every = std::max(2, static_cast<int>(std::lround(1.0 / fraction)));
  const double t0 = d.t.front(), span = d.t.back() - d.t.front();
  for (std::size_t k = 0; k < d.size(); ++k) {
    const int b = std::min(blocks - 1, static_cast<int>((d.t[k] - t0) / span * blocks));
    const bool held = b % every == every - 1;
    train.use[k] = d.use[k] && !held;
    val.use[k] = d.use[k] && held;
  }
  val.source = d.source + " (hold-out)";
  if (train.used() < kMinSamples || val.used() < kMinSamples)
    throw InputError(d.source + ": too few samples to hold out a validation part (" +
                     std::to_string(train.used()) + " training, " + std::to_string(val.used()) +
                     " validation; at least " + std::to_string(kMinSamples) +
                     " each); give a longer record or a separate --validate file");
  return {std::move(train), std::move(val)};
}

void check_identifiable(const Dataset& d, std::string_view role, bool need_reversal) {
  const std::string who = std::string(role) + " record " + d.source;
  const std::size_t n = d.used();
  if (n < kMinSamples)
    throw InputError(who + ": " + std::to_string(n) + " samples are used after masking; at least " +
                     std::to_string(kMinSamples) + " are needed (check the masks and the hold-out)");
  double xl = 1e300, xh = -1e300, vmax = 0.0;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.use[k] && std::isfinite(d.x[k]) && std::isfinite(d.v[k])) {
      xl = std::min(xl, d.x[k]), xh = std::max(xh, d.x[k]);
      vmax = std::max(vmax, std::abs(d.v[k]));
    }
  if (!(xh > xl) || !(vmax > 0.0))
    throw InputError(who + ": the position does not change over the used samples; identification "
                     "needs motion, with reversals of direction");
  if (!need_reversal) return;
  // Direction changes between moving samples (|v| above 5 % of the largest speed).
  int last = 0, reversals = 0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    if (std::abs(d.v[k]) < 0.05 * vmax) continue;
    const int s = d.v[k] > 0 ? 1 : -1;
    if (last != 0 && s != last) ++reversals;
    last = s;
  }
  if (reversals == 0)
    throw InputError(who + ": the motion never reverses direction, so friction cannot be told from "
                     "a constant force; record back-and-forth motion (at least one reversal)");
}

}  // namespace gmslab::ident
