// The pattern search after the credit (descend_to_minimum, core/ident/loop_stages.cpp) on fits
// moved off their minimum: gmslab's own GMS trace of the Fig. 2C drive with parameters drawn at
// random (break-away ratio inside the search range), the base fit made, then two shape
// coordinates moved by +-0.005 of the unit box (five of the optimum test's steps). From there the
// search must come back to a point the optimum test verifies, having recovered most of what the
// move cost (another nearby minimum is allowed; a point short of one is not).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "core/ident/loop.hpp"
#include "core/ident/loop_stages.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/assembly.hpp"
#include "tests/ident/own_trace.hpp"

using namespace gmslab;
using namespace gmslab::ident;

namespace {

struct Record {
  Dataset train, val;
  FitSpec spec;
};

Record gms_record(unsigned seed) {
  Scenario sc = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig2c_periodic_1hz.json");
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const double Fc = std::pow(3.0, U(rng));
  sc.friction.set_scalar("Fc", Fc);
  sc.friction.set_scalar("Fs", (2.0 + 0.8 * U(rng)) * Fc);
  sc.friction.set_scalar("Vs", 1e-3 * std::pow(2.0, U(rng)));
  sc.friction.set_scalar("C", 200.0 * Fc * std::pow(3.0, U(rng)));
  sc.friction.set_scalar("sigma2", 0.4 * Fc * std::pow(3.0, U(rng)));
  auto [train, val] = own::own_records(sc, rng, "descend_test");
  Record r{std::move(train), std::move(val), {}};
  r.spec.model = sc.friction.model;
  r.spec.elements = sc.friction.elements.size();
  return r;
}

}  // namespace

TEST(Descend, AFitMovedOffItsMinimumComesBackToAVerifiedOne) {
  int n = 0, tested = 0, verified = 0;
  for (unsigned seed : {3601u, 3602u, 3603u, 3604u, 3605u}) {
    const Record rec = gms_record(seed);
    LoopOptions o;
    o.max_rounds = 0;
    detail::LoopState s(rec.train, rec.val, rec.spec, o);
    detail::screen_record(s);
    detail::choose_path(s);
    const FitResult base = s.cur;
    ASSERT_FALSE(base.u.empty());
    // Two coordinates moved by 0.005 towards the middle of the box (never onto an end).
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> pick(0, base.u.size() - 1);
    std::vector<double> u = base.u;
    for (int k = 0; k < 2; ++k) {
      const std::size_t i = pick(rng);
      u[i] += u[i] < 0.5 ? 0.005 : -0.005;
    }
    s.cur = refit_linear(base.spec, s.full(), s.c, u);
    const double moved = s.cur.rms_train;
    ++n;
    if (!(moved > 1.001 * base.rms_train)) {
      std::printf("seed %u: the move raised the RMS by %.3g %% only; counted, not tested\n", seed,
                  100 * (moved / base.rms_train - 1));
      continue;
    }
    s.cur_val = rms_on(s.cur, s.val(), s.c);
    s.rep.stages.push_back(s.cur);
    detail::descend_to_minimum(s);
    detail::finish_report(s);
    std::printf("seed %u: base %.6g N, moved %.6g N, after the search %.6g N, %s\n", seed,
                base.rms_train, moved, s.cur.rms_train,
                s.rep.optimum.verified ? "verified" : s.rep.optimum.reason.c_str());
    verified += s.rep.optimum.verified;
    ++tested;
    // At least 80 % of what the move cost is recovered (98.4-100 % on seeds 3701-3706).
    EXPECT_GE(moved - s.cur.rms_train, 0.8 * (moved - base.rms_train)) << "seed " << seed;
  }
  std::printf("%d of %d moved fits brought back to a verified minimum (%d records)\n", verified,
              tested, n);
  // The search is bounded (100 runs per shape parameter): at least 4 of 5 come back (6 of 6 on
  // seeds 3701-3706 with this budget, 5 of 6 with 60 runs).
  EXPECT_GE(tested, 4) << "too few moves mattered: the test shows little";
  EXPECT_GE(5 * verified, 4 * tested);
}
