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
//
// Strided convolutions (the U-Net's every layer has stride 2) would make every tap a
// strided gather or scatter. Instead an input row is split once into its `stride`
// phases (phase f holds columns f, f+s, f+2s, ...): tap kj of output column ow reads
// column ow*s + kj*d - p, which is element ow + q of phase f for fixed q and f, so each
// tap becomes one contiguous copy (im2col) or one contiguous add (col2im).
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/kernels/conv_geometry.h"
#include "core/thread_pool.h"

namespace nns {

// The outputs o in [lo, hi) of a tap at offset `off` (= -pad + k*dil) with stride s that
// read an input index o*s + off inside [0, in).
inline void tap_range(int64_t off, int64_t s, int64_t in, int64_t out, int64_t& lo, int64_t& hi) {
  lo = off >= 0 ? 0 : (-off + s - 1) / s;
  hi = off >= in ? 0 : (in - 1 - off) / s + 1;
  hi = std::min(hi, out);
  lo = std::min(lo, hi);
}

// Where the valid part of tap kj starts: its first output column and its offset into the
// phase buffer (phase index * phase length + element).
struct TapSpan {
  int64_t lo, hi, phase_at;
};
inline TapSpan tap_span(const ConvGeometry& g, int64_t kj, int64_t phase_len) {
  TapSpan t;
  const int64_t off = kj * g.dil_w - g.pad_w;
  tap_range(off, g.stride_w, g.W, g.W_out, t.lo, t.hi);
  const int64_t iw0 = t.lo * g.stride_w + off;  // >= 0 whenever lo < hi
  t.phase_at = t.lo < t.hi ? iw0 % g.stride_w * phase_len + iw0 / g.stride_w : 0;
  return t;
}

// phases[f*len + j] = row[j*s + f]; restrict pointers let the compiler vectorize.
template <class T>
inline void split_phases(T* __restrict phases, const T* __restrict row, int64_t W, int64_t s, int64_t len) {
  if (s == 2) {
    for (int64_t j = 0; j < W / 2; ++j) phases[j] = row[2 * j], phases[len + j] = row[2 * j + 1];
    if (W % 2) phases[W / 2] = row[W - 1];
    return;
  }
  for (int64_t f = 0; f < s; ++f)
    for (int64_t j = 0; j * s + f < W; ++j) phases[f * len + j] = row[j * s + f];
}

// row[j*s + f] += phases[f*len + j].
template <class T>
inline void merge_phases_add(T* __restrict row, const T* __restrict phases, int64_t W, int64_t s, int64_t len) {
  if (s == 2) {
    for (int64_t j = 0; j < W / 2; ++j) row[2 * j] += phases[j], row[2 * j + 1] += phases[len + j];
    if (W % 2) row[W - 1] += phases[W / 2];
    return;
  }
  for (int64_t f = 0; f < s; ++f)
    for (int64_t j = 0; j * s + f < W; ++j) row[j * s + f] += phases[f * len + j];
}

template <class T>
inline void add_into(T* __restrict dst, const T* __restrict src, int64_t n) {
  for (int64_t i = 0; i < n; ++i) dst[i] += src[i];
}

// The spans of all kw taps, computed once per call (integer divisions are not free).
inline std::vector<TapSpan> tap_spans(const ConvGeometry& g, int64_t phase_len) {
  std::vector<TapSpan> spans(size_t(g.kw));
  for (int64_t kj = 0; kj < g.kw; ++kj) spans[size_t(kj)] = tap_span(g, kj, phase_len);
  return spans;
}

template <class T>
void im2col(T* col, const T* inp, const ConvGeometry& g, int64_t oh0, int64_t oh1) {
  const int64_t Wo = g.W_out, ld = (oh1 - oh0) * Wo, s = g.stride_w;
  const int64_t len = (g.W + s - 1) / s;
  const std::vector<TapSpan> spans = tap_spans(g, s == 1 ? 0 : len);
  // Below a few thousand elements the pool's wake-up costs more than the copy.
  parallel_for(
      g.cin_g() * g.kh,
      [&](int64_t b, int64_t e) {
        std::vector<T> phases(size_t(s == 1 ? 0 : s * len));
        for (int64_t cr = b; cr < e; ++cr) {  // cr = c*kh + ki
          const int64_t c = cr / g.kh, ki = cr % g.kh;
          for (int64_t oh = oh0; oh < oh1; ++oh) {
            T* dst0 = col + cr * g.kw * ld + (oh - oh0) * Wo;  // tap kj's row is dst0 + kj*ld
            const int64_t ih = oh * g.stride_h - g.pad_h + ki * g.dil_h;
            if (ih < 0 || ih >= g.H) {
              for (int64_t kj = 0; kj < g.kw; ++kj) std::fill(dst0 + kj * ld, dst0 + kj * ld + Wo, T(0));
              continue;
            }
            const T* row = inp + c * g.in_plane() + ih * g.W;
            const T* ph = row;
            if (s > 1) {
              split_phases(phases.data(), row, g.W, s, len);
              ph = phases.data();
            }
            for (int64_t kj = 0; kj < g.kw; ++kj) {
              const TapSpan& t = spans[size_t(kj)];
              T* dst = dst0 + kj * ld;
              std::fill(dst, dst + t.lo, T(0));
              std::memcpy(dst + t.lo, ph + t.phase_at, sizeof(T) * size_t(t.hi - t.lo));
              std::fill(dst + t.hi, dst + Wo, T(0));
            }
          }
        }
      },
      std::max<int64_t>(1, 4096 / std::max<int64_t>(1, g.kw * ld)));
}

// inp += col2im(col). Split over channels: each channel's plane receives its taps in an
// order fixed by the shape, so the sums do not depend on the thread count.
template <class T>
void col2im_add(T* inp, const T* col, const ConvGeometry& g, int64_t oh0, int64_t oh1) {
  const int64_t Wo = g.W_out, ld = (oh1 - oh0) * Wo, s = g.stride_w;
  const int64_t len = (g.W + s - 1) / s;
  const std::vector<TapSpan> spans = tap_spans(g, s == 1 ? 0 : len);
  parallel_for(
      g.cin_g(),
      [&](int64_t c0, int64_t c1) {
        std::vector<T> phases(size_t(s == 1 ? 0 : s * len));
        for (int64_t c = c0; c < c1; ++c)
          for (int64_t ki = 0; ki < g.kh; ++ki) {
            if (s == 1) {  // no phases: each tap adds straight into the rows (measured faster)
              for (int64_t kj = 0; kj < g.kw; ++kj) {
                const TapSpan& t = spans[size_t(kj)];
                const T* src = col + ((c * g.kh + ki) * g.kw + kj) * ld + t.lo;
                for (int64_t oh = oh0; oh < oh1; ++oh, src += Wo) {
                  const int64_t ih = oh * g.stride_h - g.pad_h + ki * g.dil_h;
                  if (ih >= 0 && ih < g.H) add_into(inp + c * g.in_plane() + ih * g.W + t.phase_at, src, t.hi - t.lo);
                }
              }
              continue;
            }
            for (int64_t oh = oh0; oh < oh1; ++oh) {
              const int64_t ih = oh * g.stride_h - g.pad_h + ki * g.dil_h;
              if (ih < 0 || ih >= g.H) continue;
              T* row = inp + c * g.in_plane() + ih * g.W;
              std::fill(phases.begin(), phases.end(), T(0));
              T* ph = phases.data();
              const T* src0 = col + (c * g.kh + ki) * g.kw * ld + (oh - oh0) * Wo;
              for (int64_t kj = 0; kj < g.kw; ++kj) {
                const TapSpan& t = spans[size_t(kj)];
                add_into(ph + t.phase_at, src0 + kj * ld + t.lo, t.hi - t.lo);
              }
              merge_phases_add(row, phases.data(), g.W, s, len);
            }
          }
      },
      std::max<int64_t>(1, 4096 / std::max<int64_t>(1, g.kh * g.kw * ld)));
}

}  // namespace nns
