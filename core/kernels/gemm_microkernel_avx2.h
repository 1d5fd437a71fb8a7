#pragma once
// AVX2 + FMA SGEMM micro-kernel (same contract as gemm_microkernel_avx512.h).
// 16 ymm registers: MR x NR = 6 x 16 keeps 12 accumulators, 2 B vectors and one
// broadcast, the classic Haswell-class shape.
#include <immintrin.h>

#include <cstdint>

namespace nns::gemm_detail {

template <int MR, int NV>
struct Avx2Kernel {
  static constexpr int mr = MR;
  static constexpr int nr = NV * 8;

  static void run(int64_t kc, const float* __restrict a, const float* __restrict b, float* __restrict c, int64_t ldc,
                  float alpha, float beta, int m, int n) {
    __m256 acc[MR][NV];
#pragma GCC unroll 16
    for (int r = 0; r < MR; ++r)
#pragma GCC unroll 4
      for (int v = 0; v < NV; ++v) acc[r][v] = _mm256_setzero_ps();

    for (int64_t k = 0; k < kc; ++k) {
      __m256 bv[NV];
#pragma GCC unroll 4
      for (int v = 0; v < NV; ++v) bv[v] = _mm256_load_ps(b + v * 8);
#pragma GCC unroll 16
      for (int r = 0; r < MR; ++r) {
        __m256 ar = _mm256_broadcast_ss(a + r);
#pragma GCC unroll 4
        for (int v = 0; v < NV; ++v) acc[r][v] = _mm256_fmadd_ps(ar, bv[v], acc[r][v]);
      }
      a += MR;
      b += nr;
    }

    __m256i mask[NV];
#pragma GCC unroll 4
    for (int v = 0; v < NV; ++v) {
      const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
      mask[v] = _mm256_cmpgt_epi32(_mm256_set1_epi32(n - v * 8), lane);
    }
    const __m256 va = _mm256_set1_ps(alpha), vb = _mm256_set1_ps(beta);
#pragma GCC unroll 16
    for (int r = 0; r < MR; ++r) {
      if (r >= m) break;
      float* cr = c + r * ldc;
#pragma GCC unroll 4
      for (int v = 0; v < NV; ++v) {
        __m256 out;
        if (beta == 0.0f) {
          out = _mm256_mul_ps(va, acc[r][v]);
        } else {
          __m256 old = _mm256_maskload_ps(cr + v * 8, mask[v]);
          out = _mm256_fmadd_ps(va, acc[r][v], beta == 1.0f ? old : _mm256_mul_ps(vb, old));
        }
        _mm256_maskstore_ps(cr + v * 8, mask[v], out);
      }
    }
  }
};

}  // namespace nns::gemm_detail
