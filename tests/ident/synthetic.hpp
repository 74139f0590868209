// Test helper: measured-looking friction records generated with gmslab's own GMS model.
//
// Motion: a sequence of smooth moves (raised-cosine velocity bumps of 4 to 40 mm/s peak, both
// directions, some reversing directly, most after rests of 0.05 to 1.2 s), 500 Hz sampling.
// Force: GMS (reference shape scaled to Fc = 10 N, Fs = 15 N, x_ba 2..20 um) plus 50 N s/m viscous,
// stepped along the true motion with 8 sub-steps per sample (finer than the fit uses), plus one
// undeclared effect in a physical form (not the fit's regressor where they differ), Gaussian
// force noise and encoder quantisation of x.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>

#include "core/friction/gms.hpp"
#include "core/ident/effects.hpp"
#include "core/io/csv.hpp"

namespace gmslab::synth {

struct SynthOptions {
  std::optional<ident::Effect> effect;
  double noise = 0.05;      // force noise standard deviation [N]
  double quantum = 50e-9;   // encoder step [m]
  double rate = 500.0;      // sampling [Hz]
  unsigned seed = 1;        // motion and noise variant
  int moves = 12;           // number of moves
  // Measurement and transmission effects (any combination, on top of `effect`):
  double ripple_rel = 0.0;  // friction level x (1 + ripple_rel sin(2 pi x / ripple_L + 0.7))
  double ripple_L = 1.3e-3; // [m]
  double time_shift = 0.0;  // the force channel lags the position channel by this [s]
  double filter_T = 0.0;    // first-order low-pass on the force channel [s]
  double backlash = 0.0;    // lost motion between encoder and contact [m]
  double dir_rel = 0.0;     // friction level x (1 + dir_rel sgn F): level differs per direction
  double level = 1.0;       // every force (friction, viscous, effects, noise) scaled by this
};

inline GmsParams synth_gms() {
  GmsParams g = GmsParams::reference(false);
  g.S = {15.0, 10.0, 2e-3, 2.0};
  for (auto& k : g.k) k *= 10.0;  // element break-away 2, 5, 10, 20 um at 10 N
  g.C = 2000.0;
  g.sigma2 = 50.0;
  return g;
}

inline MeasuredRecord synthesize(const SynthOptions& o) {
  using ident::Effect;
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::normal_distribution<double> N(0.0, 1.0);
  // Moves: duration, peak velocity (signed), rest before.
  struct Move { double rest, dur, vpk; };
  std::vector<Move> moves;
  const double peaks[] = {0.004, 0.01, 0.02, 0.04};
  double dir = 1.0;
  for (int i = 0; i < o.moves; ++i) {
    const double vpk = peaks[static_cast<int>(U(rng) * 4) % 4] * (0.8 + 0.4 * U(rng));
    const double rest = U(rng) < 0.25 ? 0.0 : 0.05 + 1.15 * U(rng);
    moves.push_back({rest, 0.4 + 0.5 * U(rng), dir * vpk});
    dir = -dir;
  }
  const double h = 1.0 / o.rate;
  const int sub = 8;
  GmsParams gp = synth_gms();
  const double viscous = gp.sigma2;  // added outside, so level effects scale friction only
  gp.sigma2 = 0.0;
  auto model = std::make_unique<GmsModel>(gp.to_params());
  std::vector<double> state(model->state_size(), 0.0);
  MeasuredRecord r;
  std::vector<double> noise;
  r.source = "synthetic";
  r.force_column = "F_N";
  double t = 0.0, x = 0.0, xc = 0.0;  // motor (encoder) and contact positions
  const double x_lo = -0.01, per = 2.5e-3;
  auto vel = [&](const Move& m, double tl) {
    if (tl < m.rest) return 0.0;
    const double s = (tl - m.rest) / m.dur;
    return s >= 1.0 ? 0.0 : m.vpk * 0.5 * (1 - std::cos(2 * std::numbers::pi * s));
  };
  auto acc = [&](const Move& m, double tl) {
    if (tl < m.rest) return 0.0;
    const double s = (tl - m.rest) / m.dur;
    return s >= 1.0 ? 0.0 : m.vpk * std::numbers::pi / m.dur * std::sin(2 * std::numbers::pi * s);
  };
  for (const auto& m : moves) {
    const double x_start = x;
    const int n = static_cast<int>(std::lround((m.rest + m.dur) * o.rate));
    for (int i = 0; i < n; ++i) {
      const double tl = i * h;
      double ff = 0.0;
      for (int s = 0; s < sub; ++s) {
        const double ts = tl + (s + 0.5) * h / sub;
        const double v = vel(m, ts);
        // Dwell stiction: the break-away level grows with the rest before the move (by up to
        // 2.6 N = 17 % of Fs after 1.2 s) and fades over the first 50 um of travel. (With three
        // times that rise the loop still names the effect, but its linear term leaves about twice
        // the noise level on validation.)
        if (o.effect == Effect::DwellStiction && m.rest > 0.0) {
          GmsParams g2 = gp;
          g2.S.Fs += 1.0 * std::log(1.0 + m.rest / 0.1) * std::exp(-std::abs(x - x_start) / 50e-6);
          model = std::make_unique<GmsModel>(g2.to_params());
        }
        // The contact follows the motor within a dead band of width `backlash`.
        const double xn = x + v * h / sub;
        const double xcn = std::clamp(xc, xn - 0.5 * o.backlash, xn + 0.5 * o.backlash);
        ff = model->step(state, {o.backlash > 0 ? (xcn - xc) / (h / sub) : v, h / sub, 0.0, 0.0});
        x = xn, xc = o.backlash > 0 ? xcn : xn;
      }
      t += h;
      const double v = vel(m, tl + h), a = acc(m, tl + h);
      double F = ff;
      double Fn = 100.0;
      const double F_visc = viscous * v;
      switch (o.effect.value_or(Effect::Offset)) {
        case Effect::Inertia: if (o.effect) F += 3.0 * a; break;
        case Effect::Offset: if (o.effect) F += 1.5; break;
        case Effect::DirectionAsymmetry: F += (v > 0 ? 0.0 : -40.0 * v); break;
        case Effect::PositionPeriodic: F += 0.8 * std::sin(2 * std::numbers::pi * x / per + 0.3); break;
        case Effect::PositionDependent: F *= 1.0 + 0.3 * (x - x_lo) / 0.05 - 0.15; break;
        case Effect::TimeDrift: F *= 1.0 + 0.012 * t; break;
        case Effect::VelocityExtra: F += 1500.0 * v * std::abs(v); break;
        case Effect::DwellStiction: break;
        default: break;  // measurement effects: not generated here (random_records.hpp has them)
        case Effect::NormalLoad:
          Fn = 100.0 * (1.0 + 0.3 * std::sin(2 * std::numbers::pi * 0.37 * t));
          F *= Fn / 100.0;
          break;
      }
      if (o.dir_rel != 0.0) F += o.dir_rel * std::abs(ff);
      if (o.ripple_rel != 0.0) F += o.ripple_rel * ff * std::sin(2 * std::numbers::pi * xc / o.ripple_L + 0.7);
      r.t.push_back(t);
      r.x.push_back(o.quantum > 0 ? o.quantum * std::round(x / o.quantum) : x);
      r.F.push_back((F + F_visc) * o.level);
      noise.push_back(o.noise * o.level * N(rng));
      if (o.effect == Effect::NormalLoad) r.Fn.push_back(Fn + 0.1 * N(rng));
    }
  }
  const std::size_t n = r.t.size();
  if (o.time_shift != 0.0) {  // F(t - tau), Catmull-Rom interpolation of the clean force
    std::vector<double> F = r.F;
    for (std::size_t k = 0; k < n; ++k) {
      const double u = static_cast<double>(k) - o.time_shift * o.rate;
      const auto i = static_cast<long>(std::floor(u));
      const double w = u - static_cast<double>(i);
      auto at = [&](long j) { return F[static_cast<std::size_t>(std::clamp<long>(j, 0, static_cast<long>(n) - 1))]; };
      const double p0 = at(i - 1), p1 = at(i), p2 = at(i + 1), p3 = at(i + 2);
      r.F[k] = p1 + 0.5 * w * (p2 - p0 + w * (2 * p0 - 5 * p1 + 4 * p2 - p3 + w * (3 * (p1 - p2) + p3 - p0)));
    }
  }
  if (o.filter_T > 0.0) {
    double s = r.F.front();
    for (std::size_t k = 0; k < n; ++k) s = r.F[k] + (s - r.F[k]) * std::exp(-h / o.filter_T), r.F[k] = s;
  }
  for (std::size_t k = 0; k < n; ++k) r.F[k] += noise[k];
  return r;
}

}  // namespace gmslab::synth
