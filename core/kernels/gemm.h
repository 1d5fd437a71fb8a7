#pragma once
// GEMM entry point used by every layer. Row-major:
//   C := alpha * op(A) * op(B) + beta * C   (op = optional transpose)
// beta = 0 assigns (C is not read), beta = 1 accumulates — this is how kernel pairs
// express the gradient contract of core/autograd.h.
//
// float goes to the packed BLIS-style kernel (gemm_packed.h) unless a direct path fits the
// shape better (gemm_small.h: tiny; gemm_skinny.h: a few columns of C), split between the pool's
// threads in whole micro-tiles of C so that results are bitwise identical for any
// thread count; double (gradient checks) goes to the simple generic loops. The naive
// gemm_reference stays beside them for the tests.
#include <algorithm>
#include <cstdint>
#include <type_traits>

#include "core/kernels/gemm_generic.h"
#include "core/kernels/gemm_packed.h"
#include "core/kernels/gemm_reference.h"
#include "core/kernels/gemm_skinny.h"
#include "core/kernels/gemm_small.h"
#include "core/thread_pool.h"

namespace nns {

namespace gemm_detail {

// Below this many multiply-adds (~10 us on one core) a second thread costs more than
// it saves: waking a worker and waiting for the slower half.
inline constexpr int64_t kParallelMinMacs = int64_t(1) << 20;

inline void scale_c(int64_t M, int64_t N, float beta, float* C, int64_t ldc) {
  for (int64_t i = 0; i < M; ++i)
    for (int64_t j = 0; j < N; ++j) C[i * ldc + j] = beta == 0.0f ? 0.0f : beta * C[i * ldc + j];
}

inline void sgemm(bool trans_a, bool trans_b, int64_t M, int64_t N, int64_t K, float alpha,
                  const float* A, int64_t lda, const float* B, int64_t ldb, float beta, float* C,
                  int64_t ldc) {
  if (M <= 0 || N <= 0) return;
  if (K <= 0 || alpha == 0.0f) {
    scale_c(M, N, beta, C, ldc);
    return;
  }
  if (use_gemm_dot(trans_a, trans_b, M, N, K))
    return gemm_dot(M, N, K, alpha, A, lda, B, ldb, beta, C, ldc);
  if (use_gemm_rows(trans_b, M, N, K)) {
    // Column blocks of 64 are computed independently: any split gives the same bits.
    parallel_for(
        N,
        [&](int64_t j0, int64_t j1) {
          gemm_rows(trans_a, M, j1 - j0, K, alpha, A, lda, B + j0, ldb, beta, C + j0, ldc);
        },
        std::max<int64_t>(64, kParallelMinMacs / std::max<int64_t>(1, M * K)), 64);
    return;
  }
  if (use_gemm_nn_skinny(trans_a, trans_b, M, N, K))
    return gemm_nn_skinny(M, N, K, alpha, A, lda, B, ldb, beta, C, ldc, kParallelMinMacs);
  if (use_gemm_tn_skinny(trans_a, trans_b, M, N, K))
    return gemm_tn_skinny(M, N, K, alpha, A, lda, B, ldb, beta, C, ldc, kParallelMinMacs);
  const MatView a{A, lda, trans_a}, b{B, ldb, trans_b};
  ThreadPool& pool = ThreadPool::global();
  const int nt = pool.threads();
  if (nt == 1 || M * N * K < kParallelMinMacs) {
    gemm_packed(a, b, M, N, K, alpha, beta, C, ldc);
    return;
  }
  // Cut along the dimension whose largest per-thread share (in whole tiles) is smaller.
  const int64_t tiles_m = (M + kMR - 1) / kMR, tiles_n = (N + kNR - 1) / kNR;
  const int64_t share_m = (tiles_m + nt - 1) / nt * kMR * N;
  const int64_t share_n = (tiles_n + nt - 1) / nt * kNR * M;
  const bool split_n = share_n <= share_m;
  pool.run([&](int w, int nw) {
    const int64_t tiles = split_n ? tiles_n : tiles_m, tile = split_n ? kNR : kMR;
    const int64_t extent = split_n ? N : M;
    const int64_t b0 = std::min(extent, tiles * w / nw * tile);
    const int64_t b1 = std::min(extent, tiles * (w + 1) / nw * tile);
    if (b0 >= b1) return;
    if (split_n)
      gemm_packed(a, MatView{b.ptr(0, b0), ldb, trans_b}, M, b1 - b0, K, alpha, beta, C + b0, ldc);
    else
      gemm_packed(MatView{a.ptr(b0, 0), lda, trans_a}, b, b1 - b0, N, K, alpha, beta,
                  C + b0 * ldc, ldc);
  });
}

}  // namespace gemm_detail

template <class T>
void gemm(bool trans_a, bool trans_b, int64_t M, int64_t N, int64_t K, T alpha, const T* A,
          int64_t lda, const T* B, int64_t ldb, T beta, T* C, int64_t ldc) {
  if constexpr (std::is_same_v<T, float>)
    gemm_detail::sgemm(trans_a, trans_b, M, N, K, alpha, A, lda, B, ldb, beta, C, ldc);
  else
    gemm_detail::gemm_generic(trans_a, trans_b, M, N, K, alpha, A, lda, B, ldb, beta, C, ldc);
}

}  // namespace nns
