#pragma once
// AVX-512 versions of the direct paths of gemm_small.h (same contracts).
#include <immintrin.h>

#include <cstdint>

#include "core/kernels/bf16.h"

namespace nns::gemm_detail {

inline __mmask16 tail_mask(int64_t n) { return n >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << n) - 1u); }

inline void store_scaled(float* c, float value, float alpha, float beta) {
  *c = beta == 0.0f ? alpha * value : alpha * value + beta * *c;
}

// Dot products A B^T: two rows of A by four rows of B per pass, 8 vector accumulators
// (enough to cover the FMA latency), lanes folded by _mm512_reduce_add_ps at the end.
// kRoundA: A's values are rounded to bf16 as they are loaded (gemm.h's bf16 skinny path).
template <bool kRoundA = false>
inline void gemm_dot_avx512(int64_t M, int64_t N, int64_t K, float alpha, const float* A, int64_t lda, const float* B,
                            int64_t ldb, float beta, float* C, int64_t ldc) {
  for (int64_t i = 0; i < M; i += 2) {
    const int rows = M - i >= 2 ? 2 : 1;
    const float* a0 = A + i * lda;
    const float* a1 = rows == 2 ? a0 + lda : a0;
    for (int64_t j = 0; j < N; j += 4) {
      const int cols = N - j >= 4 ? 4 : int(N - j);
      const float* b[4];
      for (int q = 0; q < 4; ++q) b[q] = B + (j + (q < cols ? q : 0)) * ldb;
      __m512 s[2][4];
      for (int r = 0; r < 2; ++r)
        for (int q = 0; q < 4; ++q) s[r][q] = _mm512_setzero_ps();
      for (int64_t k = 0; k < K; k += 16) {
        const __mmask16 m = tail_mask(K - k);
        const __m512 x0 = maybe_round_to_bf16_ps<kRoundA>(_mm512_maskz_loadu_ps(m, a0 + k));
        const __m512 x1 = maybe_round_to_bf16_ps<kRoundA>(_mm512_maskz_loadu_ps(m, a1 + k));
#pragma GCC unroll 4
        for (int q = 0; q < 4; ++q) {
          const __m512 y = _mm512_maskz_loadu_ps(m, b[q] + k);
          s[0][q] = _mm512_fmadd_ps(x0, y, s[0][q]);
          s[1][q] = _mm512_fmadd_ps(x1, y, s[1][q]);
        }
      }
      for (int r = 0; r < rows; ++r)
        for (int q = 0; q < cols; ++q)
          store_scaled(C + (i + r) * ldc + j + q, _mm512_reduce_add_ps(s[r][q]), alpha, beta);
    }
  }
}

// Rows of C as sums of K scaled rows of B: four rows of C by 64 columns per pass, so
// each load of B feeds four FMAs.
inline void gemm_rows_avx512(bool trans_a, int64_t M, int64_t N, int64_t K, float alpha, const float* A, int64_t lda,
                             const float* B, int64_t ldb, float beta, float* C, int64_t ldc) {
  constexpr int R = 4, V = 4;
  const __m512 va = _mm512_set1_ps(alpha), vb = _mm512_set1_ps(beta);
  for (int64_t j0 = 0; j0 < N; j0 += 16 * V) {
    __mmask16 mask[V];
    for (int v = 0; v < V; ++v) mask[v] = N - j0 - 16 * v <= 0 ? 0 : tail_mask(N - j0 - 16 * v);
    for (int64_t i0 = 0; i0 < M; i0 += R) {
      const int rows = M - i0 >= R ? R : int(M - i0);
      __m512 acc[R][V];
      for (int r = 0; r < R; ++r)
        for (int v = 0; v < V; ++v) acc[r][v] = _mm512_setzero_ps();
      for (int64_t k = 0; k < K; ++k) {
        const float* b = B + k * ldb + j0;
        __m512 y[V];
#pragma GCC unroll 4
        for (int v = 0; v < V; ++v) y[v] = _mm512_maskz_loadu_ps(mask[v], b + 16 * v);
#pragma GCC unroll 4
        for (int r = 0; r < R; ++r) {
          const int64_t ii = i0 + (r < rows ? r : 0);
          const __m512 x = _mm512_set1_ps(trans_a ? A[k * lda + ii] : A[ii * lda + k]);
#pragma GCC unroll 4
          for (int v = 0; v < V; ++v) acc[r][v] = _mm512_fmadd_ps(x, y[v], acc[r][v]);
        }
      }
      for (int r = 0; r < rows; ++r) {
        float* c = C + (i0 + r) * ldc + j0;
        for (int v = 0; v < V; ++v) {
          __m512 out = _mm512_mul_ps(va, acc[r][v]);
          if (beta != 0.0f)
            out = _mm512_fmadd_ps(va, acc[r][v], _mm512_mul_ps(vb, _mm512_maskz_loadu_ps(mask[v], c + 16 * v)));
          _mm512_mask_storeu_ps(c + 16 * v, mask[v], out);
        }
      }
    }
  }
}

}  // namespace nns::gemm_detail
