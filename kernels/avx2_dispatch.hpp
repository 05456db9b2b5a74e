#pragma once
// Run-time dispatch to AVX2 code paths (kernels/copy_basis_greedy.cpp,
// kernels/self_organizing_map.cpp). The build stays portable (no -march): a path
// is compiled for AVX2 with __attribute__((target("avx2"))) where GGK_AVX2_DISPATCH
// is 1 (x86-64, GCC or Clang), and taken only where cpu_has_avx2() says the CPU
// runs it. The target never includes FMA, and the build turns contraction off
// (-ffp-contract=off, cmake/GgkTarget.cmake) for whatever -march it is given: every
// such path does a rounded multiply then a rounded add, as the portable path does,
// so both give the same bits (tests/kernels/fma_target_greedy_test.cpp checks it
// with both compiled for -march=haswell).

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define GGK_AVX2_DISPATCH 1
#include <immintrin.h>
#else
#define GGK_AVX2_DISPATCH 0
#endif

namespace ggk::kernels {

// True when this CPU runs the AVX2 paths (checked once; thread-safe).
inline bool cpu_has_avx2() {
#if GGK_AVX2_DISPATCH
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
#else
  return false;
#endif
}

}  // namespace ggk::kernels
