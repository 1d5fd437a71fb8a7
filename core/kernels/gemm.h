#pragma once
// GEMM entry point used by every layer. Row-major:
//   C := alpha * op(A) * op(B) + beta * C   (op = optional transpose)
// beta = 0 assigns (C is not read), beta = 1 accumulates — this is how kernel pairs
// express the gradient contract of core/autograd.h.
// TODO(kernels): float goes to the packed BLIS-style kernel; other types to a generic
// blocked loop. For now both use the reference.
#include "core/kernels/gemm_reference.h"

namespace nns {

template <class T>
void gemm(bool trans_a, bool trans_b, int64_t M, int64_t N, int64_t K, T alpha, const T* A,
          int64_t lda, const T* B, int64_t ldb, T beta, T* C, int64_t ldc) {
  gemm_reference(trans_a, trans_b, M, N, K, alpha, A, lda, B, ldb, beta, C, ldc);
}

}  // namespace nns
