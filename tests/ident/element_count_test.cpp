// The element count the credit keeps (ablation.hpp, 6): an element is dropped only while the data
// do not need it, so a drop leaves the model predicting the held-out record about as well as the
// generating truth does. Random truths with many elements (5-8, break-away displacements 1.6x
// apart or more, so neighbours are distinguishable) from the independent integrator
// (random_records.hpp), the element count given as the truth's, no rounds (the base fit and the
// credit); the floor is the truth along the record's own samples (records::floor_rms).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "core/ident/loop.hpp"
#include "tests/ident/random_records.hpp"

using namespace gmslab;
using namespace gmslab::ident;
using namespace gmslab::records;

// Bounds chosen on seeds 61001-61006 (the same draws at 4000 samples): no drop there took a model
// across 1.2x the floor; five of six ended within 1.2x, the sixth (61006) at 1.89x from a base fit
// that itself kept 7 of its 8 elements (the grid's weights), no drop of the credit. On these test
// seeds a drop allowed up to the floor's full variance takes seed 62002 from 1.10x to 1.26x the
// floor (6 of 7 elements, z 1.5).
TEST(IdentElementCount, ElementsTheRecordNeedsAreKept) {
  DrawRanges R;
  R.n_lo = 5, R.n_hi = 8;
  int within = 0, total = 0;
  for (unsigned seed = 62001; seed <= 62006; ++seed) {
    Truth tr = draw_truth(seed, R);
    auto [gt, gv] = synthesize_pair(tr, seed, 4000);
    const Dataset train = prepare_dataset(gt.record);
    const Dataset val = prepare_dataset(gv.record);
    const double floor = floor_rms(tr, gv);
    FitSpec spec;
    spec.elements = tr.elements();
    LoopOptions lo;
    lo.max_rounds = 0;
    const IdentReport rep = identify(train, val, spec, lo);
    const double ratio = rep.rms_after_validation / floor;
    const double before = rep.ablation.rms_validation_all_elements / floor;
    std::printf(
        "seed %u: N %zu, kept %zu, validation %.4g N (before the element test %.4g N), "
        "floor %.4g N: %.3fx\n",
        seed, tr.elements(), rep.final_fit().spec.elements, rep.rms_after_validation,
        rep.ablation.rms_validation_all_elements, floor, ratio);
    for (const auto& e : rep.ablation.elements) std::printf("  %s\n", e.verdict.c_str());
    ASSERT_TRUE(rep.ablation.ran) << "seed " << seed;
    EXPECT_TRUE(rep.effects_added.empty()) << "seed " << seed;
    // A drop never takes a model that predicts within 1.2x the floor beyond it.
    if (before <= 1.2) {
      EXPECT_LE(ratio, 1.2) << "seed " << seed << ": " << rep.final_fit().spec.elements << " of "
                            << tr.elements() << " elements kept, " << before << "x before";
    }
    within += ratio <= 1.2;
    ++total;
  }
  EXPECT_GE(within, total - 1);
}
