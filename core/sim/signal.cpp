#include "core/sim/signal.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gmslab {

Signal Signal::constant(double value) {
  Signal s;
  s.kind = Kind::Constant;
  s.value = value;
  return s;
}

Signal Signal::ramp(double value, double slope) {
  Signal s;
  s.kind = Kind::Ramp;
  s.value = value;
  s.slope = slope;
  return s;
}

Signal Signal::sine(double offset, double amplitude, double frequency, double phase) {
  Signal s;
  s.kind = Kind::Sine;
  s.offset = offset;
  s.amplitude = amplitude;
  s.frequency = frequency;
  s.phase = phase;
  return s;
}

Signal Signal::piecewise_linear(std::vector<double> t, std::vector<double> y) {
  Signal s;
  s.kind = Kind::PiecewiseLinear;
  s.pt = std::move(t);
  s.py = std::move(y);
  return s;
}

Signal Signal::turning_points(double start, double rate, std::vector<double> points) {
  Signal s;
  s.kind = Kind::TurningPoints;
  s.start = start;
  s.rate = rate;
  s.points = std::move(points);
  s.compile();
  return s;
}

Signal Signal::triangle(double low, double high, double rate, int cycles) {
  Signal s;
  s.kind = Kind::Triangle;
  s.low = low;
  s.high = high;
  s.rate = rate;
  s.cycles = cycles;
  s.compile();
  return s;
}

Signal Signal::sequence(std::vector<Segment> segments) {
  Signal s;
  s.kind = Kind::Sequence;
  s.segments = std::move(segments);
  return s;
}

void Signal::compile() {
  if (kind == Kind::TurningPoints) {
    pt = {0.0};
    py = {start};
    for (double p : points) {
      pt.push_back(pt.back() + std::abs(p - py.back()) / rate);
      py.push_back(p);
    }
  } else if (kind == Kind::Triangle) {
    pt = {0.0};
    py = {low};
    const double half = (high - low) / rate;
    for (int c = 0; c < cycles; ++c) {
      pt.push_back(pt.back() + half);
      py.push_back(high);
      pt.push_back(pt.back() + half);
      py.push_back(low);
    }
  }
}

namespace {
// Index of the segment [pt[i], pt[i+1]) containing t, or -1 before / size-1 after.
std::ptrdiff_t locate(const std::vector<double>& pt, double t) {
  const auto it = std::upper_bound(pt.begin(), pt.end(), t);
  return (it - pt.begin()) - 1;
}
}  // namespace

double Signal::operator()(double t) const {
  switch (kind) {
    case Kind::Constant:
      return value;
    case Kind::Ramp:
      return value + slope * t;
    case Kind::Sine:
      return offset + amplitude * std::sin(2.0 * std::numbers::pi * frequency * t + phase);
    case Kind::PiecewiseLinear:
    case Kind::TurningPoints:
    case Kind::Triangle: {
      if (pt.empty()) return 0.0;
      const auto i = locate(pt, t);
      if (i < 0) return py.front();
      if (static_cast<std::size_t>(i) + 1 >= pt.size()) return py.back();
      const double w = (t - pt[i]) / (pt[i + 1] - pt[i]);
      return py[i] + w * (py[i + 1] - py[i]);
    }
    case Kind::Sequence: {
      for (auto it = segments.rbegin(); it != segments.rend(); ++it)
        if (t >= it->from) return it->signal(t - it->from);
      return segments.empty() ? 0.0 : segments.front().signal(0.0);
    }
  }
  return 0.0;
}

double Signal::rate_at(double t) const {
  switch (kind) {
    case Kind::Constant:
      return 0.0;
    case Kind::Ramp:
      return slope;
    case Kind::Sine: {
      const double w = 2.0 * std::numbers::pi * frequency;
      return amplitude * w * std::cos(w * t + phase);
    }
    case Kind::PiecewiseLinear:
    case Kind::TurningPoints:
    case Kind::Triangle: {
      const auto i = locate(pt, t);
      if (i < 0 || static_cast<std::size_t>(i) + 1 >= pt.size()) return 0.0;
      return (py[i + 1] - py[i]) / (pt[i + 1] - pt[i]);
    }
    case Kind::Sequence: {
      for (auto it = segments.rbegin(); it != segments.rend(); ++it)
        if (t >= it->from) return it->signal.rate_at(t - it->from);
      return 0.0;
    }
  }
  return 0.0;
}

double Signal::natural_end() const {
  switch (kind) {
    case Kind::PiecewiseLinear:
    case Kind::TurningPoints:
    case Kind::Triangle:
      return pt.empty() ? 0.0 : pt.back();
    case Kind::Sequence: {
      double end = 0.0;
      for (const auto& s : segments) end = std::max(end, s.from + s.signal.natural_end());
      return end;
    }
    default:
      return 0.0;
  }
}

bool Signal::operator==(const Signal& o) const {
  return kind == o.kind && value == o.value && slope == o.slope && offset == o.offset &&
         amplitude == o.amplitude && frequency == o.frequency && phase == o.phase &&
         start == o.start && rate == o.rate && low == o.low && high == o.high &&
         cycles == o.cycles && points == o.points && pt == o.pt && py == o.py &&
         segments == o.segments;
}

const char* to_string(Signal::Kind k) {
  switch (k) {
    case Signal::Kind::Constant: return "constant";
    case Signal::Kind::Ramp: return "ramp";
    case Signal::Kind::Sine: return "sine";
    case Signal::Kind::PiecewiseLinear: return "piecewise_linear";
    case Signal::Kind::TurningPoints: return "turning_points";
    case Signal::Kind::Triangle: return "triangle";
    case Signal::Kind::Sequence: return "sequence";
  }
  return "?";
}

}  // namespace gmslab
