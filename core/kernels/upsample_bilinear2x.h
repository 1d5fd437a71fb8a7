#pragma once
// Bilinear x2 upsampling (Deep Shading's U-Net up path) as a kernel pair, matching
// PyTorch's nn.Upsample(scale_factor=2, mode='bilinear', align_corners=False):
// output pixel o samples input coordinate (o + 0.5) / 2 - 0.5, clamped at 0, so
//   out[2k]   = 0.25 * in[k-1] + 0.75 * in[k]   (k = 0: in[0])
//   out[2k+1] = 0.75 * in[k]   + 0.25 * in[k+1] (k = last: in[last])
// along each axis, separably.
//   inp, dinp (P, H, W) with P = N*C planes; out, dout (P, 2H, 2W).
#include <cstdint>

#include "core/thread_pool.h"

namespace nns {

namespace detail {
// The two source taps and weights of output index o along an axis of length n.
struct BilinearTap {
  int64_t i0, i1;
  double w0, w1;
};
inline BilinearTap bilinear2x_tap(int64_t o, int64_t n) {
  const int64_t k = o / 2;
  if (o % 2 == 0) {
    if (k == 0) return {0, 0, 1.0, 0.0};
    return {k - 1, k, 0.25, 0.75};
  }
  return {k, k + 1 < n ? k + 1 : n - 1, 0.75, 0.25};
}
}  // namespace detail

template <class T>
void upsample_bilinear2x_forward(T* out, const T* inp, int64_t P, int64_t H, int64_t W) {
  const int64_t Ho = 2 * H, Wo = 2 * W;
  parallel_for(
      P * Ho,
      [&](int64_t r0, int64_t r1) {
        for (int64_t r = r0; r < r1; ++r) {
          const int64_t p = r / Ho, oy = r % Ho;
          const auto ty = detail::bilinear2x_tap(oy, H);
          const T* a = inp + (p * H + ty.i0) * W;
          const T* b = inp + (p * H + ty.i1) * W;
          const T wa = T(ty.w0), wb = T(ty.w1);
          T* o = out + r * Wo;
          for (int64_t ox = 0; ox < Wo; ++ox) {
            const auto tx = detail::bilinear2x_tap(ox, W);
            const T top = wa * a[tx.i0] + wb * b[tx.i0];
            const T bot = wa * a[tx.i1] + wb * b[tx.i1];
            o[ox] = T(tx.w0) * top + T(tx.w1) * bot;
          }
        }
      },
      Wo >= 4096 ? 1 : 4096 / (Wo + 1));
}

// The transpose of the forward: each output gradient is scattered to its four taps.
// Parallel over planes (a plane's input rows receive from several output rows).
template <class T>
void upsample_bilinear2x_backward(T* dinp, const T* dout, int64_t P, int64_t H, int64_t W) {
  const int64_t Ho = 2 * H, Wo = 2 * W;
  parallel_for(
      P,
      [&](int64_t p0, int64_t p1) {
        for (int64_t p = p0; p < p1; ++p)
          for (int64_t oy = 0; oy < Ho; ++oy) {
            const auto ty = detail::bilinear2x_tap(oy, H);
            T* a = dinp + (p * H + ty.i0) * W;
            T* b = dinp + (p * H + ty.i1) * W;
            const T wa = T(ty.w0), wb = T(ty.w1);
            const T* g = dout + (p * Ho + oy) * Wo;
            for (int64_t ox = 0; ox < Wo; ++ox) {
              const auto tx = detail::bilinear2x_tap(ox, W);
              const T g0 = T(tx.w0) * g[ox], g1 = T(tx.w1) * g[ox];
              a[tx.i0] += wa * g0;
              b[tx.i0] += wb * g0;
              a[tx.i1] += wa * g1;
              b[tx.i1] += wb * g1;
            }
          }
      },
      Wo * Ho >= 4096 ? 1 : 4096 / (Wo * Ho + 1));
}

}  // namespace nns
