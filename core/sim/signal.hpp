// gmslab core: time signals that drive a scenario (displacement, velocity, force or the position of
// a pulling point). A Signal keeps the form it was written in (so presets round-trip) and a
// compiled piecewise-linear table where that form is a polyline.
//
// Kinds and their JSON fields (units are those of the driven quantity, Y, per second where noted):
//   constant          value                                      y = value
//   ramp              value, slope [Y/s]                         y = value + slope t
//   sine              offset, amplitude, frequency [Hz], phase [rad]
//                                                                y = offset + amplitude sin(2 pi f t + phase)
//   piecewise_linear  points [[t, y], ...] (t increasing)         linear between, held after the end
//   turning_points    start, rate [Y/s] (> 0), points [y1, y2, ...]
//                                                                from start to each point in turn at |rate|
//   triangle          low, high, rate [Y/s] (> 0), cycles        low -> high -> low, `cycles` times
//   sequence          segments [{from [s], signal}, ...]          the last segment whose from <= t, in
//                                                                local time t - from
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace gmslab {

struct Signal {
  enum class Kind { Constant, Ramp, Sine, PiecewiseLinear, TurningPoints, Triangle, Sequence };
  struct Segment;

  Kind kind = Kind::Constant;
  double value = 0.0;      // constant, ramp: value at t = 0
  double slope = 0.0;      // ramp [Y/s]
  double offset = 0.0;     // sine
  double amplitude = 0.0;  // sine
  double frequency = 0.0;  // sine [Hz]
  double phase = 0.0;      // sine [rad]
  double start = 0.0;      // turning_points: initial value
  double rate = 0.0;       // turning_points, triangle [Y/s]
  double low = 0.0, high = 0.0;  // triangle
  int cycles = 0;                // triangle
  std::vector<double> points;    // turning_points: the turning values
  std::vector<double> pt, py;    // piecewise_linear: breakpoints (given or compiled)
  std::vector<Segment> segments;  // sequence

  static Signal constant(double value);
  static Signal ramp(double value, double slope);
  static Signal sine(double offset, double amplitude, double frequency, double phase = 0.0);
  static Signal piecewise_linear(std::vector<double> t, std::vector<double> y);
  static Signal turning_points(double start, double rate, std::vector<double> points);
  static Signal triangle(double low, double high, double rate, int cycles);
  static Signal sequence(std::vector<Segment> segments);

  double operator()(double t) const;  // value at t
  double rate_at(double t) const;     // time derivative at t (right derivative at corners)
  // End of the interesting part (last breakpoint), 0 for periodic or constant signals.
  double natural_end() const;
  // Recompute the compiled table of turning_points / triangle from their fields.
  void compile();
  bool operator==(const Signal&) const;
};

struct Signal::Segment {
  double from = 0.0;  // start time [s]
  Signal signal;      // evaluated at local time t - from
  bool operator==(const Segment&) const = default;
};

const char* to_string(Signal::Kind k);

}  // namespace gmslab
