#include "core/simd_path.hpp"

#include <atomic>
#include <cstdlib>
#include <cstring>

namespace gmslab {

namespace {
std::atomic<bool> g_baseline{false}, g_vector_elements{false};
// GMSLAB_SIMD=baseline: the process computes as on a CPU without AVX2 (with
// GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA for libm's variants too).
const bool g_cpu_avx2 = [] {
  const char* env = std::getenv("GMSLAB_SIMD");
  if (env && std::strcmp(env, "baseline") == 0) return false;
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") != 0;
}();
}  // namespace

void set_simd_path(SimdPath p) {
  g_baseline.store(p.baseline, std::memory_order_relaxed);
  g_vector_elements.store(p.vector_elements, std::memory_order_relaxed);
}
SimdPath simd_path() {
  return {g_baseline.load(std::memory_order_relaxed), g_vector_elements.load(std::memory_order_relaxed)};
}
bool use_avx2() { return g_cpu_avx2 && !g_baseline.load(std::memory_order_relaxed); }

}  // namespace gmslab
