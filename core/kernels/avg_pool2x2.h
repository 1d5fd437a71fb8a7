#pragma once
// 2x2 mean pooling with stride 2 (Deep Shading's U-Net down path) as a kernel pair.
//   inp, dinp (P, H, W) with P = N*C planes; out, dout (P, H/2, W/2).
// Odd sizes floor like PyTorch's AvgPool2d(2): the last row / column is ignored.
#include <cstdint>

#include "core/thread_pool.h"

namespace nns {

template <class T>
void avg_pool2x2_forward(T* out, const T* inp, int64_t P, int64_t H, int64_t W) {
  const int64_t Ho = H / 2, Wo = W / 2;
  parallel_for(
      P * Ho,
      [&](int64_t r0, int64_t r1) {
        for (int64_t r = r0; r < r1; ++r) {
          const int64_t p = r / Ho, i = r % Ho;
          const T* a = inp + (p * H + 2 * i) * W;
          const T* b = a + W;
          T* o = out + r * Wo;
          for (int64_t j = 0; j < Wo; ++j) o[j] = T(0.25) * ((a[2 * j] + a[2 * j + 1]) + (b[2 * j] + b[2 * j + 1]));
        }
      },
      Wo >= 4096 ? 1 : 4096 / (Wo + 1));
}

// Accumulates dout / 4 into each of the four inputs of a window.
template <class T>
void avg_pool2x2_backward(T* dinp, const T* dout, int64_t P, int64_t H, int64_t W) {
  const int64_t Ho = H / 2, Wo = W / 2;
  parallel_for(
      P * Ho,
      [&](int64_t r0, int64_t r1) {
        for (int64_t r = r0; r < r1; ++r) {
          const int64_t p = r / Ho, i = r % Ho;
          T* a = dinp + (p * H + 2 * i) * W;
          T* b = a + W;
          const T* g = dout + r * Wo;
          for (int64_t j = 0; j < Wo; ++j) {
            const T q = T(0.25) * g[j];
            a[2 * j] += q;
            a[2 * j + 1] += q;
            b[2 * j] += q;
            b[2 * j + 1] += q;
          }
        }
      },
      Wo >= 4096 ? 1 : 4096 / (Wo + 1));
}

}  // namespace nns
