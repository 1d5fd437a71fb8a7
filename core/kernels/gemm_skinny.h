#pragma once
// SGEMM paths for a C with a handful of columns (N <= 16) and a long other side: the
// U-Net's innermost convolutions, whose outputs are 1x1 .. 4x4 pixels (N = pixels) while
// the weight matrix is 512 x 8192 (16 MB). The packed kernel copies the whole weight
// matrix (transposing it, for the input gradient) to use it for N columns; these paths
// stream it once.
//   gemm_nn_skinny, C = alpha A B + beta C, N <= 4: B^T is copied (N x K, small) and
//     every C element is a dot product of a row of A with a row of B^T (gemm_dot).
//   gemm_tn_skinny, C = alpha A^T B + beta C, N <= 16: A (K x M) is read row by row; a
//     block of 64 rows of C by 4 of its columns is accumulated in 16 registers.
// Both split M between threads in aligned blocks; each element of C is summed over k in
// an order fixed by the shape, so 1 and 2 threads agree bitwise.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/kernels/bf16.h"
#include "core/kernels/gemm_small.h"
#include "core/thread_pool.h"

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace nns::gemm_detail {

inline bool use_gemm_nn_skinny(bool trans_a, bool trans_b, int64_t M, int64_t N, int64_t K) {
  return !trans_a && !trans_b && N <= 4 && K >= 256 && M >= 16;
}
inline bool use_gemm_tn_skinny(bool trans_a, bool trans_b, int64_t M, int64_t N, int64_t K) {
  return trans_a && !trans_b && N <= 16 && K >= 16 && M >= 256;
}

// Rows [m0, m1) of C = alpha A^T B + beta C for the N <= kNB columns of B and C given,
// in blocks of 16*kV rows held in kV*kNB registers. Narrower blocks (one cache line of
// each row of A per k) measured 4x slower: rows of A are 32 KB apart, so every line is
// a TLB miss of its own.
template <int kV, int kNB>
void gemm_tn_skinny_rows(int64_t m0, int64_t m1, int64_t N, int64_t K, float alpha, const float* A, int64_t lda,
                         const float* B, int64_t ldb, float beta, float* C, int64_t ldc) {
  constexpr int kMB = 16 * kV;
  int bcol[kNB];  // columns past N repeat column 0 and are not stored
  for (int q = 0; q < kNB; ++q) bcol[q] = q < N ? q : 0;
  for (int64_t i0 = m0; i0 < m1; i0 += kMB) {
    const int mb = int(std::min<int64_t>(kMB, m1 - i0));
    alignas(64) float acc[kNB][kMB];
#if defined(__AVX512F__)
    __mmask16 mask[kV];
    for (int v = 0; v < kV; ++v) mask[v] = mb - 16 * v <= 0 ? 0 : tail_mask(mb - 16 * v);
    __m512 s[kNB][kV];
    for (int q = 0; q < kNB; ++q)
      for (int v = 0; v < kV; ++v) s[q][v] = _mm512_setzero_ps();
    for (int64_t k = 0; k < K; ++k) {
      const float* a = A + k * lda + i0;
      const float* b = B + k * ldb;
      __m512 x[kV];
      for (int v = 0; v < kV; ++v) x[v] = _mm512_maskz_loadu_ps(mask[v], a + 16 * v);
      for (int q = 0; q < kNB; ++q) {
        const __m512 y = _mm512_set1_ps(b[bcol[q]]);
        for (int v = 0; v < kV; ++v) s[q][v] = _mm512_fmadd_ps(x[v], y, s[q][v]);
      }
    }
    for (int q = 0; q < kNB; ++q)
      for (int v = 0; v < kV; ++v) _mm512_store_ps(acc[q] + 16 * v, s[q][v]);
#else
    for (int q = 0; q < kNB; ++q) std::fill(acc[q], acc[q] + kMB, 0.0f);
    for (int64_t k = 0; k < K; ++k) {
      const float* a = A + k * lda + i0;
      for (int q = 0; q < kNB; ++q) {
        const float y = B[k * ldb + bcol[q]];
        for (int i = 0; i < mb; ++i) acc[q][i] += a[i] * y;
      }
    }
#endif
    for (int i = 0; i < mb; ++i)
      for (int q = 0; q < N; ++q) {
        float& c = C[(i0 + i) * ldc + q];
        c = beta == 0.0f ? alpha * acc[q][i] : alpha * acc[q][i] + beta * c;
      }
  }
}

// dst[k * W + i] = round_to_bf16(A[k * lda + i]) for k < K, i < w <= W: a strip of A's
// columns for gemm_tn_skinny's bf16 path. The rows are a page or more apart (a TLB miss
// each): prefetching kAhead rows ahead keeps several in flight.
template <int W>
inline void round_strip_bf16(float* __restrict dst, const float* __restrict A, int64_t lda, int64_t K, int w) {
#if defined(__AVX512F__)
  constexpr int64_t kAhead = 8;
  static_assert(W % 16 == 0, "whole vectors");
  __mmask16 mask[W / 16];
  for (int v = 0; v < W / 16; ++v) mask[v] = w - 16 * v <= 0 ? 0 : tail_mask(w - 16 * v);
  for (int64_t k = 0; k < K; ++k) {
    const float* a = A + k * lda;
    if (k + kAhead < K)
      for (int v = 0; v < W / 16; ++v)
        _mm_prefetch(reinterpret_cast<const char*>(a + kAhead * lda + 16 * v), _MM_HINT_T0);
    for (int v = 0; v < W / 16; ++v)
      _mm512_storeu_ps(dst + k * W + 16 * v, round_to_bf16_ps(_mm512_maskz_loadu_ps(mask[v], a + 16 * v)));
  }
#else
  for (int64_t k = 0; k < K; ++k)
    for (int i = 0; i < w; ++i) dst[k * W + i] = round_to_bf16(A[k * lda + i]);
#endif
}

// kRoundA: A's values are rounded to bf16 (gemm.h's bf16 path for these shapes: A is the
// large operand, and a rounded copy of all of it cost more than the product), one strip
// of 64 of its columns at a time into an L2-sized scratch that the column groups then
// read. Rounding in the loads instead measured 2x the fp32 time (Ice Lake VM): the extra
// instructions between the loads, a TLB miss each, left fewer of them in flight.
template <bool kRoundA = false>
inline void gemm_tn_skinny(int64_t M, int64_t N, int64_t K, float alpha, const float* A, int64_t lda, const float* B,
                           int64_t ldb, float beta, float* C, int64_t ldc, int64_t min_macs) {
  constexpr int64_t kStrip = 64;
  parallel_for(
      M,
      [&](int64_t m0, int64_t m1) {
        std::vector<float> strip(kRoundA ? size_t(K * kStrip) : 0);
        // Groups of 4 columns; past the first the rows of A come from L2 (measured 1.3x
        // the packed kernel at N = 16, 2-2.6x at N <= 4).
        for (int64_t i0 = m0; i0 < m1; i0 += kStrip) {
          const int64_t i1 = std::min(m1, i0 + kStrip);
          if constexpr (kRoundA) {
            round_strip_bf16<kStrip>(strip.data(), A + i0, lda, K, int(i1 - i0));
            for (int64_t j0 = 0; j0 < N; j0 += 4)
              gemm_tn_skinny_rows<4, 4>(0, i1 - i0, std::min<int64_t>(4, N - j0), K, alpha, strip.data(), kStrip,
                                        B + j0, ldb, beta, C + i0 * ldc + j0, ldc);
            continue;
          }
          for (int64_t j0 = 0; j0 < N; j0 += 4)
            gemm_tn_skinny_rows<4, 4>(i0, i1, std::min<int64_t>(4, N - j0), K, alpha, A, lda, B + j0, ldb, beta, C + j0,
                                      ldc);
        }
      },
      std::max<int64_t>(kStrip, min_macs / std::max<int64_t>(1, N * K)), kStrip);
}

template <bool kRoundA = false>
inline void gemm_nn_skinny(int64_t M, int64_t N, int64_t K, float alpha, const float* A, int64_t lda, const float* B,
                           int64_t ldb, float beta, float* C, int64_t ldc, int64_t min_macs) {
  std::vector<float> bt(size_t(N * K));  // B^T, N x K: at most 4 rows
  for (int64_t k = 0; k < K; ++k)
    for (int64_t j = 0; j < N; ++j) bt[size_t(j * K + k)] = B[k * ldb + j];
  parallel_for(
      M,
      [&](int64_t m0, int64_t m1) {
        gemm_dot<kRoundA>(m1 - m0, N, K, alpha, A + m0 * lda, lda, bt.data(), K, beta, C + m0 * ldc, ldc);
      },
      std::max<int64_t>(16, min_macs / std::max<int64_t>(1, N * K)), 16);
}

}  // namespace nns::gemm_detail
