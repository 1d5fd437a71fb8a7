#pragma once
// Fully connected layer, as a pair of kernels (llm.c style).
//   inp (B, IN), weight (OUT, IN) as in PyTorch, bias (OUT) or null, out (B, OUT)
#include <cstdint>

#include "core/kernels/gemm.h"

namespace nns {

template <class T>
void linear_forward(T* out, const T* inp, const T* weight, const T* bias, int64_t B, int64_t IN, int64_t OUT) {
  // out = inp * weight^T
  gemm<T>(false, true, B, OUT, IN, T(1), inp, IN, weight, IN, T(0), out, OUT);
  if (bias)
    for (int64_t b = 0; b < B; ++b)
      for (int64_t o = 0; o < OUT; ++o) out[b * OUT + o] += bias[o];
}

// Accumulates into dinp, dweight, dbias (any may be null to skip it).
template <class T>
void linear_backward(T* dinp, T* dweight, T* dbias, const T* dout, const T* inp, const T* weight, int64_t B, int64_t IN,
                     int64_t OUT) {
  if (dinp) gemm<T>(false, false, B, IN, OUT, T(1), dout, OUT, weight, IN, T(1), dinp, IN);
  if (dweight) gemm<T>(true, false, OUT, IN, B, T(1), dout, OUT, inp, IN, T(1), dweight, IN);
  if (dbias)
    for (int64_t b = 0; b < B; ++b)
      for (int64_t o = 0; o < OUT; ++o) dbias[o] += dout[b * OUT + o];
}

}  // namespace nns
