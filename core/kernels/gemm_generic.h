#pragma once
// GEMM for scalar types other than float (double, used by the gradient checks): plain
// loops ordered so the innermost one runs along contiguous memory where it can. Not
// fast, but an order of magnitude quicker than the i-j-k reference on big gradient
// checks. Same contract as gemm(): beta == 0 never reads C.
#include <cstdint>

namespace nns::gemm_detail {

template <class T>
void gemm_generic(bool trans_a, bool trans_b, int64_t M, int64_t N, int64_t K, T alpha, const T* A, int64_t lda,
                  const T* B, int64_t ldb, T beta, T* C, int64_t ldc) {
  for (int64_t i = 0; i < M; ++i) {
    T* c = C + i * ldc;
    if (trans_b) {
      // op(B) rows are strided; rows of B are contiguous along k: dot products.
      for (int64_t j = 0; j < N; ++j) {
        const T* b = B + j * ldb;
        T acc = 0;
        for (int64_t k = 0; k < K; ++k) acc += (trans_a ? A[k * lda + i] : A[i * lda + k]) * b[k];
        c[j] = alpha * acc + (beta == T(0) ? T(0) : beta * c[j]);
      }
    } else {
      // Rows of op(B) are contiguous: accumulate scaled rows into C's row.
      if (beta == T(0))
        for (int64_t j = 0; j < N; ++j) c[j] = T(0);
      else if (beta != T(1))
        for (int64_t j = 0; j < N; ++j) c[j] *= beta;
      for (int64_t k = 0; k < K; ++k) {
        const T a = alpha * (trans_a ? A[k * lda + i] : A[i * lda + k]);
        const T* b = B + k * ldb;
        for (int64_t j = 0; j < N; ++j) c[j] += a * b[j];
      }
    }
  }
}

}  // namespace nns::gemm_detail
