#pragma once
// Direct SGEMM paths for shapes where packing costs more than the arithmetic, such as
// the NNAO MLP (batch 16, 3844 inputs, 4 units): forward is 64 dot products of length
// 3844, its gradients are sums of a few scaled rows. Packing would copy the whole
// 3844-wide operand to use it once; these loops read it in place.
//
// Both paths are single-threaded (the work is a few microseconds, less than waking a
// worker) and their summation order depends only on the shape, never on threads.
#include <cstdint>
#include <vector>

#include "core/kernels/bf16.h"

#if defined(__AVX512F__)
#include "core/kernels/gemm_small_avx512.h"
#endif

namespace nns::gemm_detail {

inline constexpr int kLanes = 16;

// C := alpha * A B^T + beta * C with A (M x K) and B (N x K) both read along K.
// 16 partial sums per dot product, folded in a fixed order. kRoundA: A's values are
// rounded to bf16 as they are read (gemm.h's bf16 skinny path).
template <bool kRoundA = false>
inline void gemm_dot(int64_t M, int64_t N, int64_t K, float alpha, const float* A, int64_t lda, const float* B,
                     int64_t ldb, float beta, float* C, int64_t ldc) {
#if defined(__AVX512F__)
  return gemm_dot_avx512<kRoundA>(M, N, K, alpha, A, lda, B, ldb, beta, C, ldc);
#endif
  const int64_t Kv = K / kLanes * kLanes;
  std::vector<float> rounded(kRoundA ? size_t(K) : 0);
  for (int64_t i = 0; i < M; ++i) {
    const float* a = A + i * lda;
    if constexpr (kRoundA) {
      for (int64_t k = 0; k < K; ++k) rounded[size_t(k)] = round_to_bf16(a[k]);
      a = rounded.data();
    }
    int64_t j = 0;
    // Four columns at a time so each load of A feeds four dot products.
    for (; j + 4 <= N; j += 4) {
      const float* b0 = B + j * ldb;
      const float* b1 = b0 + ldb;
      const float* b2 = b1 + ldb;
      const float* b3 = b2 + ldb;
      float s0[kLanes] = {}, s1[kLanes] = {}, s2[kLanes] = {}, s3[kLanes] = {};
      for (int64_t k = 0; k < Kv; k += kLanes)
        for (int l = 0; l < kLanes; ++l) {
          s0[l] += a[k + l] * b0[k + l];
          s1[l] += a[k + l] * b1[k + l];
          s2[l] += a[k + l] * b2[k + l];
          s3[l] += a[k + l] * b3[k + l];
        }
      float t[4] = {};
      for (int l = 0; l < kLanes; ++l) {
        t[0] += s0[l];
        t[1] += s1[l];
        t[2] += s2[l];
        t[3] += s3[l];
      }
      for (int64_t k = Kv; k < K; ++k) {
        t[0] += a[k] * b0[k];
        t[1] += a[k] * b1[k];
        t[2] += a[k] * b2[k];
        t[3] += a[k] * b3[k];
      }
      for (int q = 0; q < 4; ++q) {
        float& c = C[i * ldc + j + q];
        c = beta == 0.0f ? alpha * t[q] : alpha * t[q] + beta * c;
      }
    }
    for (; j < N; ++j) {
      const float* b = B + j * ldb;
      float s[kLanes] = {};
      for (int64_t k = 0; k < Kv; k += kLanes)
        for (int l = 0; l < kLanes; ++l) s[l] += a[k + l] * b[k + l];
      float t = 0;
      for (int l = 0; l < kLanes; ++l) t += s[l];
      for (int64_t k = Kv; k < K; ++k) t += a[k] * b[k];
      float& c = C[i * ldc + j];
      c = beta == 0.0f ? alpha * t : alpha * t + beta * c;
    }
  }
}

// C := alpha * op(A) B + beta * C for a short K: each row of C is a sum of K rows of B
// scaled by op(A)[i][k]. Column blocks of 64 keep the K rows of B in L1 across i.
inline void gemm_rows(bool trans_a, int64_t M, int64_t N, int64_t K, float alpha, const float* A, int64_t lda,
                      const float* B, int64_t ldb, float beta, float* C, int64_t ldc) {
#if defined(__AVX512F__)
  return gemm_rows_avx512(trans_a, M, N, K, alpha, A, lda, B, ldb, beta, C, ldc);
#endif
  constexpr int64_t kBlock = 64;
  for (int64_t j0 = 0; j0 < N; j0 += kBlock) {
    const int64_t nb = N - j0 < kBlock ? N - j0 : kBlock;
    for (int64_t i = 0; i < M; ++i) {
      float acc[kBlock] = {};
      for (int64_t k = 0; k < K; ++k) {
        const float a = trans_a ? A[k * lda + i] : A[i * lda + k];
        const float* b = B + k * ldb + j0;
        if (nb == kBlock)
          for (int64_t j = 0; j < kBlock; ++j) acc[j] += a * b[j];
        else
          for (int64_t j = 0; j < nb; ++j) acc[j] += a * b[j];
      }
      float* c = C + i * ldc + j0;
      if (beta == 0.0f)
        for (int64_t j = 0; j < nb; ++j) c[j] = alpha * acc[j];
      else
        for (int64_t j = 0; j < nb; ++j) c[j] = alpha * acc[j] + beta * c[j];
    }
  }
}

// The shapes the direct paths win on (measured on Zen 5 against the packed kernel).
inline bool use_gemm_dot(bool trans_a, bool trans_b, int64_t M, int64_t N, int64_t K) {
  return !trans_a && trans_b && M * N <= 256;
}
inline bool use_gemm_rows(bool trans_b, int64_t M, int64_t N, int64_t K) { return !trans_b && K <= 32 && M <= 32; }

}  // namespace nns::gemm_detail
