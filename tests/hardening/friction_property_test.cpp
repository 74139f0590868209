// Property tests with random parameters and inputs (fixed seeds), for every model in the registry:
//   - bounded force: |F| <= break-away level + viscous and damping parts, from each model's
//     equations (GMS: |F_i| <= alpha_i Fs, dz_i/dt = v in stick, dF_i/dt = C(alpha_i d - F_i/S) in
//     slip; bristle models: |sigma0 z| <= Fs, |dz/dt| <= 2|v|);
//   - passivity: a closed displacement cycle from the virgin state never creates energy,
//     sum F dx >= 0 (the friction may store energy elastically, it may not give out more than it
//     took);
//   - a stuck mass does not drift (1e6 steps here; 1e9 in bench/bench_long_run.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "core/friction/gms.hpp"
#include "core/sim/simulation.hpp"

namespace gmslab {
namespace {

double log_uniform(std::mt19937& rng, double lo, double hi) {
  return std::exp(std::uniform_real_distribution<double>(std::log(lo), std::log(hi))(rng));
}

// The model's defaults with every value scaled by a random factor in [1/3, 3] (kept inside its
// range); retried until the cross-field checks pass. Weights (alpha) are renormalised.
ModelParams random_params(const ModelInfo& info, std::mt19937& rng) {
  for (int attempt = 0; attempt < 1000; ++attempt) {
    ModelParams p = info.defaults();
    auto scale = [&](double& x, const ParamSpec& s) {
      const double y = x * log_uniform(rng, 1.0 / 3.0, 3.0);
      if (s.allowed(y)) x = y;
    };
    for (std::size_t i = 0; i < p.scalars.size(); ++i) scale(p.scalars[i], info.scalars[i]);
    const std::size_t n = p.elements.empty() ? 0 : 1 + rng() % 8;
    if (n > 0) {
      const auto proto = p.elements;
      p.elements.clear();
      for (std::size_t r = 0; r < n; ++r) {
        auto row = proto[r % proto.size()];
        for (std::size_t c = 0; c < row.size(); ++c) scale(row[c], info.columns[c]);
        p.elements.push_back(row);
      }
      if (const auto a = info.column_index("alpha"); a >= 0) {
        double sum = 0.0;
        for (const auto& row : p.elements) sum += row[a];
        for (auto& row : p.elements) row[a] /= sum;
      }
    }
    if (validate(p).empty()) return p;
  }
  ADD_FAILURE() << "no valid random parameters for " << info.tag;
  return info.defaults();
}

std::string describe(const ModelParams& p) {
  std::ostringstream o;
  o.precision(17);
  o << p.model << " scalars";
  for (double x : p.scalars) o << ' ' << x;
  o << ", elements";
  for (const auto& row : p.elements) {
    o << " [";
    for (double x : row) o << ' ' << x;
    o << " ]";
  }
  return o.str();
}

double scalar_or(const ModelParams& p, const ModelInfo& info, const char* key, double fallback) {
  return info.scalar_index(key) >= 0 ? p.scalar(key) : fallback;
}

// Upper bound of |F| at sliding velocity v from the model's equations (see the file comment).
// Leuven: |F_h| <= sum W_i and |dz/dt| <= |v| (1 + (sum W_i / Fc)^n), since F_h may exceed S(v)
// when S drops with speed.
double force_bound(const FrictionModel& m, const ModelParams& p, double v) {
  const ModelInfo& info = m.info();
  double fh = m.break_away(), dz = 2.0;
  if (const auto w = info.column_index("W"); w >= 0) {
    double sum_w = 0.0;
    for (const auto& row : p.elements) sum_w += row[w];
    fh = std::max(fh, sum_w);
    if (info.scalar_index("n") >= 0) dz = 1.0 + std::pow(sum_w / p.scalar("Fc"), p.scalar("n"));
  }
  double b = fh + scalar_or(p, info, "sigma2", 0.0) * std::abs(v) +
             dz * scalar_or(p, info, "sigma1", 0.0) * std::abs(v);
  if (info.tag == "gms") {
    const GmsParams g = GmsParams::from(p);
    for (std::size_t i = 0; i < g.alpha.size(); ++i) {
      const double slip_rate = g.C * g.alpha[i] * (1.0 + g.S.Fs / g.S.Fc) / g.k[i];
      b += g.sigma[i] * std::max(std::abs(v), slip_rate);
    }
  }
  return b;
}

TEST(FrictionProperty, ForceStaysBoundedByBreakAwayPlusViscousAndDampingParts) {
  std::mt19937 rng(6);
  for (const auto& info : model_registry()) {
    SCOPED_TRACE(std::string(info.tag));
    for (int set = 0; set < 25; ++set) {
      const ModelParams p = random_params(info, rng);
      const auto m = build_model(p);
      std::vector<double> state(m->state_size());
      m->reset(state);
      const double vmax = log_uniform(rng, 1e-6, 1.0), h = log_uniform(rng, 1e-6, 1e-2);
      double v = 0.0, worst = 0.0;
      for (int step = 0; step < 2000; ++step) {
        if (step % 50 == 0)
          v = (rng() % 5 == 0) ? 0.0 : std::uniform_real_distribution<double>(-vmax, vmax)(rng);
        const double f = m->step(state, {v, h, 0.0, 0.0});
        ASSERT_TRUE(std::isfinite(f));
        worst = std::max(worst, std::abs(f) / force_bound(*m, p, v));
        for (std::size_t i = 0; i < m->element_count(); ++i) {
          if (info.column_index("alpha") >= 0) {
            ASSERT_LE(std::abs(m->element(state, i).force),
                      p.elements[i][info.column_index("alpha")] * m->break_away() * (1 + 1e-12));
          }
        }
      }
      ASSERT_LE(worst, 1.0 + 1e-12) << "set " << set << ", vmax " << vmax << " m/s, h " << h
                                    << " s, " << describe(p);
    }
  }
}

// Leuven was once checked at its defaults only: its RK4 sub-steps were sized for |F_h/s| = 1, so
// after a velocity jump (|F_h/s| up to Fs/Fc) the state equation went unstable and gave out energy.
// Fixed in core/friction/leuven.cpp (sub-steps from the local relaxation rate); regression tests in
// tests/models/leuven_step_test.cpp. Every model now runs the random sets.
TEST(FrictionProperty, ClosedDisplacementCycleNeverCreatesEnergy) {
  std::mt19937 rng(7);
  for (const auto& info : model_registry()) {
    SCOPED_TRACE(std::string(info.tag));
    for (int set = 0; set < 25; ++set) {
      const ModelParams p = set == 0 ? info.defaults() : random_params(info, rng);
      const auto m = build_model(p);
      std::vector<double> state(m->state_size());
      m->reset(state);
      // A cycle 0 -> y1 -> y2 -> ... -> 0 through random turning points, run three times at a
      // random rate, 200 steps per leg at least.
      const double amp = log_uniform(rng, 1e-7, 1e-3), rate = log_uniform(rng, 1e-6, 1e-1);
      std::vector<double> pts;
      for (int k = 0; k < 2 + static_cast<int>(rng() % 5); ++k)
        pts.push_back(std::uniform_real_distribution<double>(-amp, amp)(rng));
      pts.push_back(0.0);
      double x = 0.0, work = 0.0, scale = 0.0;
      for (int cycle = 0; cycle < 3; ++cycle) {
        for (const double target : pts) {
          const double dist = std::abs(target - x);
          const int n = std::max(200, static_cast<int>(dist / rate / 1e-3));
          const double h = std::max(dist / rate / n, 1e-9), x0 = x;
          for (int s = 1; s <= n; ++s) {
            const double x1 = x0 + (target - x0) * s / n;
            const double f = m->step(state, {(x1 - x) / h, h, 0.0, 0.0});
            work += f * (x1 - x);  // the force that acts over this step, times the displacement
            scale += std::abs(f * (x1 - x));
            x = x1;
          }
          x = target;
        }
        ASSERT_GE(work, -1e-9 * scale - 1e-18)
            << "set " << set << ", cycle " << cycle << ": the friction gave out " << -work
            << " J over a closed cycle (amplitude " << amp << " m, rate " << rate << " m/s), "
            << describe(p);
      }
    }
  }
}

TEST(FrictionProperty, StuckMassDoesNotDriftOverAMillionSteps) {
  // 0.1 N on the GMS reference set: every element stays elastic (x = F / sum k = 0.476 um, below
  // the first break at alpha_1 Fs / k_1 = 2 um). After the micro-damped vibration settles (1 s,
  // ~90 decay times of 2 m / sum sigma = 11 ms), the mass must sit at F / sum k and stay there.
  //
  // FINDING (reported): it does not stay exactly. A residual velocity of ~3e-18 m/s survives the
  // decay because its increments k_i v h (~2e-18 N) are below half an ulp of the element forces
  // (~0.035 N, ulp 7e-18 N): the friction force stops changing while x creeps on at 3e-18 m/s
  // (3e-14 m over the 1e9 steps of bench_long_run). Far below anything physical, but unbounded in
  // time; this test pins it at the rounding level so that any real drift fails.
  Scenario s;
  s.name = "stuck mass";
  s.friction = GmsParams::reference(true).to_params();
  s.drive.kind = Drive::Kind::Force;
  s.drive.signal = Signal::constant(0.1);
  s.run = {1e-5, 10.0, 10000};
  const Trace tr = simulate(s);
  const double x_eq = 0.1 / 210000.0;
  const std::size_t settled = tr.size() / 10;
  double drift = 0.0;
  for (std::size_t i = settled; i < tr.size(); ++i) {
    ASSERT_NEAR(tr.x[i], x_eq, 1e-9 * x_eq) << "t = " << tr.t[i];
    ASSERT_LT(std::abs(tr.v[i]), 1e-16) << "t = " << tr.t[i];  // rounding level only
    drift = std::max(drift, std::abs(tr.x[i] - tr.x[settled]));
  }
  // 9 s at the rounding-level residual velocity: below 1e-15 m (a femtometre).
  EXPECT_LE(drift, 1e-15) << "largest move after settling: " << drift << " m";
}

}  // namespace
}  // namespace gmslab
