// Conformance suite: every registered friction model must satisfy these, whatever its equations.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "tests/models/model_protocols.hpp"

namespace gmslab {
namespace {

using testing::all_tags;
using testing::drive_positions;

class Conformance : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    params_ = model_info(GetParam()).defaults();
    model_ = build_model(params_);
  }
  std::vector<double> virgin() const {
    std::vector<double> s(model_->state_size(), 1e9);  // garbage that reset must clear
    model_->reset(s);
    return s;
  }
  ModelParams params_;
  std::unique_ptr<FrictionModel> model_;
};

TEST_P(Conformance, DefaultsAreValidAndDescribeEveryParameter) {
  const auto& info = model_info(GetParam());
  EXPECT_TRUE(validate(params_).empty());
  EXPECT_EQ(params_.model, GetParam());
  for (const auto& specs : {info.scalars, info.columns})
    for (const auto& s : specs) {
      EXPECT_FALSE(s.key.empty());
      EXPECT_FALSE(s.symbol.empty()) << s.key;
      EXPECT_FALSE(s.unit.empty()) << s.key;
      EXPECT_FALSE(s.help.empty()) << s.key;
      EXPECT_LT(s.lo, s.hi) << s.key;
    }
  EXPECT_FALSE(info.equation.empty());
  EXPECT_FALSE(info.citation.empty());
}

// Sliding at constant v long enough for every transient to die gives the static curve F_ss(v).
TEST_P(Conformance, SteadySlidingGivesSteadyStateCurve) {
  for (double v : {1e-4, 1e-3, 5e-3, 0.05}) {
    for (double sign : {1.0, -1.0}) {
      auto s = virgin();
      const double T = std::max(0.5, 5e-3 / v), h = T / 100000.0;
      double f = 0.0;
      for (int k = 0; k < 100000; ++k) f = model_->step(s, {sign * v, h, 0.0, 0.0});
      const double fss = model_->steady_state(sign * v);
      EXPECT_NEAR(f, fss, 1e-6 + 1e-6 * std::abs(fss)) << "v = " << sign * v;
    }
  }
}

// The steady-state curve is odd, and F(-x(t)) = -F(x(t)) for any motion from the virgin state.
TEST_P(Conformance, OddSymmetry) {
  const double h = 1e-4;
  std::vector<double> x;
  for (int k = 0; k <= 40000; ++k) {  // presliding wiggles on a sliding sweep, 4 s
    const double t = k * h;
    x.push_back(2e-3 * std::sin(2 * std::numbers::pi * 0.5 * t) +
                8e-6 * std::sin(2 * std::numbers::pi * 7.0 * t));
  }
  std::vector<double> xm(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) xm[k] = -x[k];
  auto s1 = virgin(), s2 = virgin();
  const auto a = drive_positions(*model_, s1, x, h);
  const auto b = drive_positions(*model_, s2, xm, h);
  for (std::size_t k = 0; k < a.force.size(); ++k)
    ASSERT_NEAR(a.force[k], -b.force[k], 1e-9 * (1.0 + std::abs(a.force[k]))) << "step " << k;
  for (double v : {1e-5, 1e-3, 0.1}) EXPECT_DOUBLE_EQ(model_->steady_state(-v), -model_->steady_state(v));
}

// Passivity: over closed displacement cycles (presliding and sliding amplitudes, slow and fast)
// the work done on the friction is never negative, cycle by cycle, from the virgin state on.
TEST_P(Conformance, PassiveOverClosedDisplacementCycles) {
  for (double amp : {3e-6, 12e-6, 1e-3}) {
    for (double freq : {0.5, 20.0}) {
      auto s = virgin();
      const int per_cycle = 4000;
      const double h = 1.0 / (freq * per_cycle);
      for (int cycle = 0; cycle < 3; ++cycle) {
        std::vector<double> x;
        for (int k = 0; k <= per_cycle; ++k)
          x.push_back(amp * std::sin(2 * std::numbers::pi * k / per_cycle));
        const auto d = drive_positions(*model_, s, x, h);
        EXPECT_GE(d.work, -1e-12) << "amplitude " << amp << " m, " << freq << " Hz, cycle "
                                  << cycle;
      }
    }
  }
}

TEST_P(Conformance, ZeroForceAtRestFromVirginState) {
  auto s = virgin();
  const auto before = s;
  EXPECT_EQ(model_->step(s, {0.0, 1e-3, 0.0, 0.0}), 0.0);  // prescribed: not moving
  EXPECT_EQ(model_->step(s, {0.0, 1e-3, 0.0, 1.0}), 0.0);  // a 1 kg body, no other force
  EXPECT_EQ(s, before);
  EXPECT_EQ(model_->steady_state(0.0), 0.0);
}

TEST_P(Conformance, JsonRoundTripKeepsEveryValue) {
  ModelParams p = params_;
  for (auto& x : p.scalars) x = std::nextafter(x, 1e300);  // not just the defaults' short decimals
  if (!validate(p).empty()) p = params_;  // a cross-field check may forbid the nudge
  const nlohmann::json j = to_json(p);
  JsonReader r(j, "roundtrip.json", "friction");
  EXPECT_EQ(model_params_from_json(r), p);
}

// Every scalar and element value: NaN, infinity and out-of-range values are rejected by
// validate(), build_model() and the JSON loader, each naming the key and the allowed range.
TEST_P(Conformance, RejectsInvalidParametersNamingTheKey) {
  const auto& info = model_info(GetParam());
  auto bad_values = [](const ParamSpec& s) {
    std::vector<double> b{std::nan(""), HUGE_VAL, -HUGE_VAL, s.lo_open ? s.lo : s.lo - 1.0,
                          s.hi * 2.0 + 1.0};
    return b;
  };
  for (std::size_t i = 0; i < info.scalars.size(); ++i) {
    const auto& spec = info.scalars[i];
    for (double bad : bad_values(spec)) {
      ModelParams p = params_;
      p.scalars[i] = bad;
      const auto problems = validate(p);
      ASSERT_EQ(problems.size(), 1u) << spec.key << " = " << bad;
      EXPECT_NE(problems[0].find("friction." + std::string(spec.key)), std::string::npos)
          << problems[0];
      EXPECT_NE(problems[0].find(spec.range_text()), std::string::npos) << problems[0];
      EXPECT_THROW(build_model(p), InputError);
      nlohmann::json j = to_json(params_);
      j[std::string(spec.key)] = bad;
      JsonReader r(j, "bad.json", "friction");
      try {
        model_params_from_json(r);
        ADD_FAILURE() << "JSON with " << spec.key << " = " << bad << " was accepted";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(std::string(spec.key)), std::string::npos)
            << e.what();
      }
    }
  }
  for (std::size_t c = 0; c < info.columns.size(); ++c) {
    const auto& spec = info.columns[c];
    for (double bad : bad_values(spec)) {
      ModelParams p = params_;
      p.elements.back()[c] = bad;
      const auto problems = validate(p);
      ASSERT_FALSE(problems.empty()) << spec.key << " = " << bad;
      const std::string where =
          "elements[" + std::to_string(p.elements.size() - 1) + "]." + std::string(spec.key);
      EXPECT_NE(problems[0].find(where), std::string::npos) << problems[0];
      EXPECT_THROW(build_model(p), InputError);
    }
  }
}

TEST_P(Conformance, RejectsWrongElementCount) {
  const auto& info = model_info(GetParam());
  ModelParams p = params_;
  if (info.columns.empty()) {
    p.elements.push_back({1.0});
  } else {
    p.elements.clear();
  }
  EXPECT_FALSE(validate(p).empty());
  EXPECT_THROW(build_model(p), InputError);
}

INSTANTIATE_TEST_SUITE_P(EveryModel, Conformance, ::testing::ValuesIn(all_tags()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace gmslab
