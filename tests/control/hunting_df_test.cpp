// scratch exploration
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "core/control/hunting.hpp"
#include "core/control/loop_simulation.hpp"
#include "core/error.hpp"
#include "core/friction/model.hpp"

using namespace gmslab;
using namespace gmslab::control;

namespace {
struct Measured {
  bool hunting = false;
  double amplitude = 0, period = 0, u3u1 = 0, drift = 0;
};
// The steady cycle over the last `frac` of the run.
Measured measure(const LoopTrace& tr, double frac) {
  Measured m;
  const std::size_t n = tr.t.size(), i0 = static_cast<std::size_t>((1 - frac) * (n - 1));
  double lo = 1e300, hi = -1e300;
  for (std::size_t i = i0; i < n; ++i) lo = std::min(lo, tr.x[i]), hi = std::max(hi, tr.x[i]);
  const double amp = 0.5 * (hi - lo), mid = 0.5 * (hi + lo);
  std::vector<std::size_t> ups;
  bool below = tr.x[i0] < mid;
  for (std::size_t i = i0 + 1; i < n; ++i) {
    if (below && tr.x[i] > mid + 0.25 * amp) ups.push_back(i), below = false;
    else if (!below && tr.x[i] < mid - 0.25 * amp) below = true;
  }
  if (ups.size() < 3 || amp < 1e-9) return m;
  m.hunting = true;
  m.amplitude = amp;
  m.period = (tr.t[ups.back()] - tr.t[ups.front()]) / (ups.size() - 1);
  // harmonics of u over whole cycles between the first and last up-crossing
  const double w = 2 * std::numbers::pi / m.period;
  std::complex<double> U1, U3;
  for (std::size_t i = ups.front(); i < ups.back(); ++i) {
    const double th = w * tr.t[i];
    U1 += tr.u[i] * std::polar(1.0, -th);
    U3 += tr.u[i] * std::polar(1.0, -3 * th);
  }
  m.u3u1 = std::abs(U3) / std::abs(U1);
  return m;
}
}  // namespace

TEST(HuntingDf, Explore) {
  struct Case { const char* model; double m, c, Kc, z; };
  for (Case k : {Case{"stribeck", 1, 3, 1000, 5}, Case{"coulomb", 1, 3, 1000, 5}, Case{"lugre", 1, 3, 1000, 5},
                 Case{"gms", 1, 3, 1000, 5}, Case{"stribeck", 1, 10, 1000, 5}, Case{"stribeck", 1, 10, 300, 2},
                 Case{"gms", 0.2, 1, 300, 2}, Case{"coulomb", 5, 10, 3000, 1}}) {
    Scenario s;
    s.plant = {k.m, 0.0, k.c};
    s.friction = model_info(k.model).defaults();
    const LeadCompensator C{k.Kc, k.z, 0.0};
    std::printf("%s m=%g c=%g Kc=%g z=%g\n", k.model, k.m, k.c, k.Kc, k.z);
    for (DriveWave wv : {DriveWave::Sine, DriveWave::Triangle}) {
      HuntingOptions o;
      o.wave = wv;
      const auto t0 = std::chrono::steady_clock::now();
      const HuntingReport r = predict_hunting(s.plant, s.friction, C, o);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      std::printf("  %s: evals=%d (%.1f ms) %s\n", to_string(wv), r.evaluations, ms, r.note.c_str());
      for (const auto& c : r.cycles)
        std::printf("    cycle A=%.4g N w=%.4g T=%.4g s amp=%.4g mm X1=%.4g mm wave=%.3f %s %s\n", c.force_amplitude,
                    c.frequency, c.period, c.amplitude * 1e3, c.first_harmonic * 1e3, c.waveform_error,
                    c.stable ? "stable" : "unstable", c.converged ? "conv" : "NOCONV");
    }
    LoopConfig cfg;
    cfg.C = C;
    cfg.reference = Signal::constant(0.01);
    cfg.dt = 1e-5;
    cfg.duration = 30.0;
    cfg.record_every = 10;
    try {
      const LoopTrace tr = simulate_loop(s, cfg);
      const Measured m = measure(tr, 0.4);
      double mx = 0;
      for (std::size_t i = tr.t.size() / 2; i < tr.t.size(); ++i) mx = std::max(mx, std::abs(tr.u[i] - k.Kc * (tr.r[i] - tr.x[i])));
      std::printf("  simulated u_I peak %.4g N\n", mx);
      {
      const LoopTrace tr = simulate_loop(s, cfg);
      double mx = 0;
      for (std::size_t i = tr.t.size() / 2; i < tr.t.size(); ++i) mx = std::max(mx, std::abs(tr.u[i] - k.Kc * (tr.r[i] - tr.x[i])));
      std::printf("  simulated u_I peak %.4g N\n", mx);
    }
    std::printf("  simulated: hunting %d amp=%.4g mm T=%.4g s u3/u1=%.3f\n", m.hunting, m.amplitude * 1e3, m.period,
                  m.u3u1);
    } catch (const std::exception& e) {
      std::printf("  simulated: %s\n", e.what());
    }
  }
}
TEST(HuntingDf, ExploreP) {
  Scenario s;
  s.plant = {1.0, 0.0, 3.0};
  s.friction = model_info("stribeck").defaults();
  const auto m = build_model(s.friction);
  const auto sp = integral_split(LeadCompensator{1000, 5, 0.0});
  std::printf("R=%g d=%g cst=%g a=%g\n", sp->R, sp->fast.d, sp->fast.cst, sp->fast.a);
  for (double w : {3.0, 4.0})
    for (double A = 0.95; A < 1.3; A += 0.02) {
      HuntingOptions o;
      o.periods = 6;
      o.wave = DriveWave::Triangle;
      const PlantHarmonics ph = plant_harmonics(s.plant, *m, sp->fast, A, w, o);
      std::printf("w=%g A=%g |P|=%.4g arg %.1f deg R|P|/w=%.4g settle=%.3g pp=%.4g mm\n", w, A, std::abs(ph.P),
                  std::arg(ph.P) * 180 / 3.14159, sp->R * std::abs(ph.P) / w, ph.settle, ph.half_pp * 1e3);
    }
}
TEST(HuntingDf, ExploreWave) {
  Scenario s;
  s.plant = {1.0, 0.0, 3.0};
  s.friction = model_info("stribeck").defaults();
  std::printf("stribeck Fs %g Fc %g Vs %g sigma2 %g\n", s.friction.scalar("Fs"), s.friction.scalar("Fc"), s.friction.scalar("Vs"), s.friction.scalar("sigma2"));
  const LeadCompensator C{1000, 5, 0.0};
  LoopConfig cfg;
  cfg.C = C;
  cfg.reference = Signal::constant(0.01);
  cfg.dt = 1e-5;
  cfg.duration = 30.0;
  cfg.record_every = 100;
  const LoopTrace tr = simulate_loop(s, cfg);
  const Measured m = measure(tr, 0.4);
  const std::size_t n = tr.t.size();
  const double T = m.period;
  std::size_t i0 = n - static_cast<std::size_t>(T / (tr.t[1] - tr.t[0])) - 1;
  for (std::size_t i = i0; i < n; i += 30)
    std::printf("t=%.3f x-r=%.4f mm uI=%.4f N u=%.4f v=%.4f mm/s\n", tr.t[i] - tr.t[i0], (tr.x[i] - tr.r[i]) * 1e3, tr.u[i] - 1000 * (tr.r[i] - tr.x[i]), tr.u[i], tr.v[i]*1e3);
}
