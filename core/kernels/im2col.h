#pragma once
// im2col and its mirror col2im, for one image and one group, over a block of output rows.
//
// Why blocks of rows: the full column matrix of a layer is kh*kw times larger than its
// input (16x for the U-Net's 4x4 kernels, 16 MB for one 64-channel 128x128 image), so
// the convolution kernels lower a few output rows at a time into a reused buffer that
// stays small (see conv_rows_per_block in core/kernels/conv2d.h).
//
//   inp  (C_in/groups, H, W)                  one image, one group
//   col  (C_in/groups * kh * kw, R * W_out)   R = oh1 - oh0 output rows
// col[(c*kh + ki)*kw + kj][(oh - oh0)*W_out + ow] = inp[c][oh*sh - ph + ki*dh][ow*sw - pw + kj*dw]
// (0 outside the input). col2im_add is the adjoint: it adds col back into inp.
#include <algorithm>
#include <cstdint>
#include <cstring>

#include "core/kernels/conv_geometry.h"
#include "core/thread_pool.h"

namespace nns {

// Strided gather and scatter-add of one row segment. Separate functions with restrict
// pointers: without the no-alias promise the compiler keeps them scalar (stride 2 is
// the U-Net's every layer).
template <class T>
inline void gather_strided(T* __restrict dst, const T* __restrict src, int64_t n, int64_t s) {
  if (s == 2)
    for (int64_t i = 0; i < n; ++i) dst[i] = src[2 * i];
  else
    for (int64_t i = 0; i < n; ++i) dst[i] = src[i * s];
}
template <class T>
inline void scatter_add_strided(T* __restrict dst, const T* __restrict src, int64_t n, int64_t s) {
  if (s == 1)
    for (int64_t i = 0; i < n; ++i) dst[i] += src[i];
  else if (s == 2)
    for (int64_t i = 0; i < n; ++i) dst[2 * i] += src[i];
  else
    for (int64_t i = 0; i < n; ++i) dst[i * s] += src[i];
}

// The outputs o in [lo, hi) of a tap at offset `off` (= -pad + k*dil) with stride s that
// read an input index o*s + off inside [0, in).
inline void tap_range(int64_t off, int64_t s, int64_t in, int64_t out, int64_t& lo, int64_t& hi) {
  lo = off >= 0 ? 0 : (-off + s - 1) / s;
  hi = off >= in ? 0 : (in - 1 - off) / s + 1;
  hi = std::min(hi, out);
  lo = std::min(lo, hi);
}

template <class T>
void im2col(T* col, const T* inp, const ConvGeometry& g, int64_t oh0, int64_t oh1) {
  const int64_t rows = g.col_rows(), R = oh1 - oh0, Wo = g.W_out, ld = R * Wo;
  // Below a few thousand elements the pool's wake-up costs more than the copy.
  parallel_for(rows, [&](int64_t r0, int64_t r1) {
    for (int64_t r = r0; r < r1; ++r) {
      const int64_t c = r / (g.kh * g.kw), ki = r / g.kw % g.kh, kj = r % g.kw;
      const T* x = inp + c * g.in_plane();
      T* dst = col + r * ld;
      int64_t lo, hi;
      tap_range(kj * g.dil_w - g.pad_w, g.stride_w, g.W, Wo, lo, hi);
      const int64_t iw0 = lo * g.stride_w - g.pad_w + kj * g.dil_w;
      for (int64_t oh = oh0; oh < oh1; ++oh, dst += Wo) {
        const int64_t ih = oh * g.stride_h - g.pad_h + ki * g.dil_h;
        if (ih < 0 || ih >= g.H || lo == hi) {
          std::fill(dst, dst + Wo, T(0));
          continue;
        }
        std::fill(dst, dst + lo, T(0));
        const T* src = x + ih * g.W + iw0;
        if (g.stride_w == 1)
          std::memcpy(dst + lo, src, sizeof(T) * size_t(hi - lo));
        else
          gather_strided(dst + lo, src, hi - lo, g.stride_w);
        std::fill(dst + hi, dst + Wo, T(0));
      }
    }
  }, std::max<int64_t>(1, 4096 / std::max<int64_t>(1, ld)));
}

// inp += col2im(col). Split over channels: each channel's plane receives its taps in a
// fixed order, so the sums do not depend on the thread count.
template <class T>
void col2im_add(T* inp, const T* col, const ConvGeometry& g, int64_t oh0, int64_t oh1) {
  const int64_t R = oh1 - oh0, Wo = g.W_out, ld = R * Wo, kk = g.kh * g.kw;
  parallel_for(g.cin_g(), [&](int64_t c0, int64_t c1) {
    for (int64_t c = c0; c < c1; ++c) {
      T* x = inp + c * g.in_plane();
      for (int64_t ki = 0; ki < g.kh; ++ki)
        for (int64_t kj = 0; kj < g.kw; ++kj) {
          const T* src = col + (c * kk + ki * g.kw + kj) * ld;
          int64_t lo, hi;
          tap_range(kj * g.dil_w - g.pad_w, g.stride_w, g.W, Wo, lo, hi);
          const int64_t iw0 = lo * g.stride_w - g.pad_w + kj * g.dil_w;
          for (int64_t oh = oh0; oh < oh1; ++oh, src += Wo) {
            const int64_t ih = oh * g.stride_h - g.pad_h + ki * g.dil_h;
            if (ih < 0 || ih >= g.H) continue;
            scatter_add_strided(x + ih * g.W + iw0, src + lo, hi - lo, g.stride_w);
          }
        }
    }
  }, std::max<int64_t>(1, 4096 / std::max<int64_t>(1, kk * ld)));
}

}  // namespace nns
