// gmslab core: which compiled variant the vectorised loops take (the GMS element step, the
// ripple periodogram). Each is compiled twice: for AVX2 and for the x86-64 baseline (SSE2). The
// two sum in another order (vector width 4 against 2), so their last bits differ; which one runs
// is chosen per call from the CPU (AVX2 where it has it) unless a test asks for the baseline to
// see what a machine without AVX2 computes. The GMS path runner (the identification's element
// simulation) takes the branchy scalar element loop up to GmsModel::kScalarElements elements and
// the vector loop above; a test may ask for the vector loop at every count (another summation
// order for the same elements). A process-wide switch by nature, like the CPU itself; results
// never depend on it beyond the last bits (tests/ident/stability_test.cpp).
#pragma once

namespace gmslab {

struct SimdPath {
  bool baseline = false;         // the baseline variants on any CPU
  bool vector_elements = false;  // the GMS path runner's vector element loop at every count
};

void set_simd_path(SimdPath p);
SimdPath simd_path();
// True when the AVX2 variants are to run: the CPU has AVX2 and the baseline is not asked for.
bool use_avx2();

}  // namespace gmslab
