#pragma once
// Direct (loop) convolution for layers with very few output channels per group, such as
// PatchGAN's final 512 -> 1 layer. Lowering those to GEMM fills a 14-row micro-tile with
// one useful row and writes an im2col buffer 16x the input for a few million
// multiply-adds (measured: 2 GFLOP/s, 55 ms per pix2pix iteration, ~2 ms here). Each tap
// is a row update that stays in L1: with stride 1 over whole zero-padded rows at once,
// with other strides one output row at a time.
//
// Same shapes and contract as the GEMM passes in core/kernels/conv2d.h (which dispatch
// here), so conv_transpose2d gets the same path when its in-channels are few.
// Threads: every output element (out, dinp plane, dweight entry) is produced by one
// worker in an order fixed by the shape, so 1 and 2 threads agree bitwise.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/kernels/conv_geometry.h"
#include "core/kernels/im2col.h"
#include "core/thread_pool.h"

namespace nns {

// Output channels per group at or below which the direct loops replace im2col + GEMM.
// One is the case that matters (a score map); the loops are written for any count and
// tests/core/test_conv_direct.cpp checks them up to 3, but small multi-channel layers
// keep the GEMM path that the layer tests exercise.
inline constexpr int64_t kConvDirectMaxCout = 1;
inline bool conv_use_direct(const ConvGeometry& g) { return g.cout_g() <= kConvDirectMaxCout; }

namespace conv_direct_detail {
// The output columns [lo, hi) of tap kj that read inside the input row, and its offset.
struct Tap {
  int64_t lo, hi, off;
};
inline std::vector<Tap> taps(const ConvGeometry& g) {
  std::vector<Tap> t(size_t(g.kw));
  for (int64_t kj = 0; kj < g.kw; ++kj) {
    Tap& tp = t[size_t(kj)];
    tp.off = kj * g.dil_w - g.pad_w;
    tap_range(tp.off, g.stride_w, g.W, g.W_out, tp.lo, tp.hi);
  }
  return t;
}
// Below this many multiply-adds per call a pool round-trip costs more than it saves.
inline int64_t grain(double macs_per_unit) {
  return std::max<int64_t>(1, int64_t(double(1 << 16) / std::max(1.0, macs_per_unit)));
}
}  // namespace conv_direct_detail

// ---- stride 1: whole padded rows ---------------------------------------------------
// With stride 1 a tap (ki, kj) is a constant shift in a zero-padded copy of the plane
// (width Wp = W + 2 pad_w), so a tap over R output rows is one contiguous loop of R*Wp
// elements instead of R loops of W_out: the loops are long enough to vectorize well.
// Columns ow >= W_out of a padded output row are scratch and never stored; reads past a
// row's end meet the next row or the zero tail, only ever for those scratch columns.
namespace conv_direct_detail {
struct Padded {
  int64_t Wp, Hp, tail;  // padded width and height, zeros after the last row
  explicit Padded(const ConvGeometry& g)
      : Wp(g.W + 2 * g.pad_w), Hp(g.H + 2 * g.pad_h), tail((g.kw - 1) * g.dil_w + 16) {}
};
// dst (rows x Wp) = padded rows [pr0, pr0 + rows) of one input plane (padded coordinates).
template <class T>
void pad_rows(T* dst, const T* plane, const ConvGeometry& g, const Padded& p, int64_t pr0, int64_t rows) {
  for (int64_t r = 0; r < rows; ++r) {
    T* d = dst + r * p.Wp;
    const int64_t ih = pr0 + r - g.pad_h;
    if (ih < 0 || ih >= g.H) {
      std::fill(d, d + p.Wp, T(0));
      continue;
    }
    std::fill(d, d + g.pad_w, T(0));
    std::copy(plane + ih * g.W, plane + (ih + 1) * g.W, d + g.pad_w);
    std::fill(d + g.pad_w + g.W, d + p.Wp, T(0));
  }
}
// dy of every (image, output channel) as rows of Wp with zero scratch columns.
template <class T>
std::vector<T> pad_dout(const T* dout, const ConvGeometry& g, const Padded& p) {
  const int64_t planes = g.N * g.C_out, len = g.H_out * p.Wp;
  std::vector<T> d(static_cast<size_t>(planes * len + p.tail), T(0));
  for (int64_t q = 0; q < planes; ++q)
    for (int64_t oh = 0; oh < g.H_out; ++oh)
      std::copy(dout + (q * g.H_out + oh) * g.W_out, dout + (q * g.H_out + oh + 1) * g.W_out,
                d.data() + q * len + oh * p.Wp);
  return d;
}
}  // namespace conv_direct_detail

template <class T>
void conv2d_direct_forward_s1(T* out, const T* inp, const T* weight, const T* bias, const ConvGeometry& g,
                              bool accumulate) {
  using namespace conv_direct_detail;
  const Padded p(g);
  const int64_t cig = g.cin_g(), cog = g.cout_g(), KK = g.kh * g.kw, halo = (g.kh - 1) * g.dil_h;
  // Row blocks of ~1024 outputs, and at least 4 units in all so two threads share the
  // work; fixed by the shape, and every output is summed inside one unit.
  const int64_t per_plane =
      std::min(g.H_out, std::max((g.H_out * p.Wp + 1023) / 1024, (4 + g.N * g.C_out - 1) / (g.N * g.C_out)));
  const int64_t R = (g.H_out + per_plane - 1) / per_plane;
  parallel_for(
      g.N * g.C_out * per_plane,
      [&](int64_t u0, int64_t u1) {
        std::vector<T> xbuf(static_cast<size_t>((R + halo) * p.Wp + p.tail), T(0));
        std::vector<T> abuf(static_cast<size_t>(R * p.Wp));
        for (int64_t u = u0; u < u1; ++u) {
          const int64_t b = u % per_plane, co = u / per_plane % g.C_out, n = u / (per_plane * g.C_out);
          const int64_t r0 = b * R, r1 = std::min(g.H_out, r0 + R), len = (r1 - r0) * p.Wp;
          const T* x = inp + (n * g.C_in + co / cog * cig) * g.in_plane();
          const T* w = weight + co * cig * KK;
          T* __restrict acc = abuf.data();
          std::fill(acc, acc + len, T(0));
          for (int64_t c = 0; c < cig; ++c) {
            pad_rows(xbuf.data(), x + c * g.in_plane(), g, p, r0, r1 - r0 + halo);
            for (int64_t ki = 0; ki < g.kh; ++ki)
              for (int64_t kj = 0; kj < g.kw; ++kj) {
                const T wv = w[(c * g.kh + ki) * g.kw + kj];
                const T* __restrict xs = xbuf.data() + ki * g.dil_h * p.Wp + kj * g.dil_w;
                for (int64_t e = 0; e < len; ++e) acc[e] += wv * xs[e];
              }
          }
          const T bv = bias ? bias[co] : T(0);
          for (int64_t oh = r0; oh < r1; ++oh) {
            T* y = out + (n * g.C_out + co) * g.out_plane() + oh * g.W_out;
            const T* a = acc + (oh - r0) * p.Wp;
            for (int64_t ow = 0; ow < g.W_out; ++ow) y[ow] = (accumulate ? y[ow] : T(0)) + a[ow] + bv;
          }
        }
      },
      1);
}

template <class T>
void conv2d_direct_backward_input_s1(T* dinp, const T* dout, const T* weight, const ConvGeometry& g, bool accumulate) {
  using namespace conv_direct_detail;
  const Padded p(g);
  const int64_t cig = g.cin_g(), cog = g.cout_g(), KK = g.kh * g.kw, len = g.H_out * p.Wp;
  const std::vector<T> dy = pad_dout(dout, g, p);
  parallel_for(
      g.N * g.C_in,
      [&](int64_t u0, int64_t u1) {
        std::vector<T> dbuf(static_cast<size_t>(p.Hp * p.Wp + p.tail));
        for (int64_t u = u0; u < u1; ++u) {
          const int64_t c = u % g.C_in, n = u / g.C_in, grp = c / cig, cl = c % cig;
          T* __restrict dxp = dbuf.data();
          std::fill(dbuf.begin(), dbuf.end(), T(0));
          for (int64_t co = grp * cog; co < (grp + 1) * cog; ++co) {
            const T* __restrict d = dy.data() + (n * g.C_out + co) * len;
            const T* w = weight + (co * cig + cl) * KK;
            for (int64_t ki = 0; ki < g.kh; ++ki)
              for (int64_t kj = 0; kj < g.kw; ++kj) {
                const T wv = w[ki * g.kw + kj];
                T* __restrict o = dxp + ki * g.dil_h * p.Wp + kj * g.dil_w;
                for (int64_t e = 0; e < len; ++e) o[e] += wv * d[e];
              }
          }
          T* plane = dinp + u * g.in_plane();
          for (int64_t ih = 0; ih < g.H; ++ih) {
            const T* s = dxp + (ih + g.pad_h) * p.Wp + g.pad_w;
            T* dst = plane + ih * g.W;
            for (int64_t iw = 0; iw < g.W; ++iw) dst[iw] = (accumulate ? dst[iw] : T(0)) + s[iw];
          }
        }
      },
      grain(double(cog * KK * len)));
}

template <class T>
void conv2d_direct_backward_weight_s1(T* dweight, const T* dout, const T* inp, const ConvGeometry& g) {
  using namespace conv_direct_detail;
  const Padded p(g);
  const int64_t cig = g.cin_g(), cog = g.cout_g(), KK = g.kh * g.kw, len = g.H_out * p.Wp;
  const std::vector<T> dy = pad_dout(dout, g, p);
  parallel_for(
      g.C_out * cig,
      [&](int64_t u0, int64_t u1) {
        std::vector<T> xbuf(static_cast<size_t>(p.Hp * p.Wp + p.tail), T(0));
        std::vector<T> sums(static_cast<size_t>(KK));
        for (int64_t u = u0; u < u1; ++u) {
          const int64_t co = u / cig, cl = u % cig, grp = co / cog;
          std::fill(sums.begin(), sums.end(), T(0));
          for (int64_t n = 0; n < g.N; ++n) {
            pad_rows(xbuf.data(), inp + (n * g.C_in + grp * cig + cl) * g.in_plane(), g, p, 0, p.Hp);
            const T* __restrict d = dy.data() + (n * g.C_out + co) * len;
            for (int64_t ki = 0; ki < g.kh; ++ki)
              for (int64_t kj = 0; kj < g.kw; ++kj) {
                const T* __restrict x = xbuf.data() + ki * g.dil_h * p.Wp + kj * g.dil_w;
                T part[16] = {};  // 16 lanes in a fixed order: vectorizes, same bits any split
                int64_t e = 0;
                for (; e + 16 <= len; e += 16)
                  for (int l = 0; l < 16; ++l) part[l] += d[e + l] * x[e + l];
                T s = 0;
                for (; e < len; ++e) s += d[e] * x[e];
                for (int l = 0; l < 16; ++l) s += part[l];
                sums[size_t(ki * g.kw + kj)] += s;
              }
          }
          for (int64_t k = 0; k < KK; ++k) dweight[u * KK + k] += sums[size_t(k)];
        }
      },
      grain(double(g.N * KK * len)));
}

// ---- any stride: one output row at a time ---------------------------------------------

// out = conv(inp, weight) (+ bias), or out += conv(...) when accumulate. Unit of work:
// one output row of one channel of one image, summed over (c, ki, kj) in that order.
template <class T>
void conv2d_direct_forward(T* out, const T* inp, const T* weight, const T* bias, const ConvGeometry& g,
                           bool accumulate) {
  using namespace conv_direct_detail;
  if (g.stride_h == 1 && g.stride_w == 1) return conv2d_direct_forward_s1(out, inp, weight, bias, g, accumulate);
  const int64_t cig = g.cin_g(), cog = g.cout_g(), Wo = g.W_out, sw = g.stride_w;
  const int64_t KK = g.kh * g.kw, inP = g.in_plane();
  const std::vector<Tap> tp = taps(g);
  parallel_for(
      g.N * g.C_out * g.H_out,
      [&](int64_t u0, int64_t u1) {
        std::vector<T> acc_buf(static_cast<size_t>(Wo));
        T* __restrict acc = acc_buf.data();
        for (int64_t u = u0; u < u1; ++u) {
          const int64_t oh = u % g.H_out, co = u / g.H_out % g.C_out, n = u / (g.H_out * g.C_out);
          const T* x = inp + (n * g.C_in + co / cog * cig) * inP;
          const T* w = weight + co * cig * KK;
          std::fill(acc, acc + Wo, T(0));
          for (int64_t c = 0; c < cig; ++c)
            for (int64_t ki = 0; ki < g.kh; ++ki) {
              const int64_t ih = oh * g.stride_h - g.pad_h + ki * g.dil_h;
              if (ih < 0 || ih >= g.H) continue;
              const T* __restrict row = x + c * inP + ih * g.W;
              for (int64_t kj = 0; kj < g.kw; ++kj) {
                const T wv = w[(c * g.kh + ki) * g.kw + kj];
                const Tap& t = tp[size_t(kj)];
                if (sw == 1)
                  for (int64_t ow = t.lo; ow < t.hi; ++ow) acc[ow] += wv * row[ow + t.off];
                else
                  for (int64_t ow = t.lo; ow < t.hi; ++ow) acc[ow] += wv * row[ow * sw + t.off];
              }
            }
          T* y = out + (n * g.C_out + co) * g.out_plane() + oh * Wo;
          const T b = bias ? bias[co] : T(0);
          for (int64_t ow = 0; ow < Wo; ++ow) y[ow] = (accumulate ? y[ow] : T(0)) + acc[ow] + b;
        }
      },
      grain(double(cig * KK * Wo)));
}

// dinp += conv^T(dout) (dinp = ... when !accumulate). Unit: one input plane, receiving
// its taps in the order (co, oh, ki, kj).
template <class T>
void conv2d_direct_backward_input(T* dinp, const T* dout, const T* weight, const ConvGeometry& g, bool accumulate) {
  using namespace conv_direct_detail;
  if (g.stride_h == 1 && g.stride_w == 1) return conv2d_direct_backward_input_s1(dinp, dout, weight, g, accumulate);
  const int64_t cig = g.cin_g(), cog = g.cout_g(), Wo = g.W_out, sw = g.stride_w;
  const int64_t KK = g.kh * g.kw, inP = g.in_plane(), P = g.out_plane();
  const std::vector<Tap> tp = taps(g);
  parallel_for(
      g.N * g.C_in,
      [&](int64_t u0, int64_t u1) {
        for (int64_t u = u0; u < u1; ++u) {
          const int64_t c = u % g.C_in, n = u / g.C_in, grp = c / cig, cl = c % cig;
          T* plane = dinp + u * inP;
          if (!accumulate) std::fill(plane, plane + inP, T(0));
          for (int64_t co = grp * cog; co < (grp + 1) * cog; ++co) {
            const T* w = weight + (co * cig + cl) * KK;
            for (int64_t oh = 0; oh < g.H_out; ++oh) {
              const T* __restrict dy = dout + (n * g.C_out + co) * P + oh * Wo;
              for (int64_t ki = 0; ki < g.kh; ++ki) {
                const int64_t ih = oh * g.stride_h - g.pad_h + ki * g.dil_h;
                if (ih < 0 || ih >= g.H) continue;
                T* __restrict row = plane + ih * g.W;
                for (int64_t kj = 0; kj < g.kw; ++kj) {
                  const T wv = w[ki * g.kw + kj];
                  const Tap& t = tp[size_t(kj)];
                  if (sw == 1)
                    for (int64_t ow = t.lo; ow < t.hi; ++ow) row[ow + t.off] += wv * dy[ow];
                  else
                    for (int64_t ow = t.lo; ow < t.hi; ++ow) row[ow * sw + t.off] += wv * dy[ow];
                }
              }
            }
          }
        }
      },
      grain(double(cog * KK * P)));
}

// dweight += dout (x) inp. Unit: the kh*kw weights of one (co, c) pair; each keeps a
// running row of partial sums per tap over (n, oh), reduced left to right at the end.
template <class T>
void conv2d_direct_backward_weight(T* dweight, const T* dout, const T* inp, const ConvGeometry& g) {
  using namespace conv_direct_detail;
  if (g.stride_h == 1 && g.stride_w == 1) return conv2d_direct_backward_weight_s1(dweight, dout, inp, g);
  const int64_t cig = g.cin_g(), cog = g.cout_g(), Wo = g.W_out, sw = g.stride_w;
  const int64_t KK = g.kh * g.kw, inP = g.in_plane(), P = g.out_plane();
  const std::vector<Tap> tp = taps(g);
  parallel_for(
      g.C_out * cig,
      [&](int64_t u0, int64_t u1) {
        std::vector<T> acc_buf(static_cast<size_t>(KK * Wo));
        for (int64_t u = u0; u < u1; ++u) {
          const int64_t co = u / cig, cl = u % cig, grp = co / cog;
          std::fill(acc_buf.begin(), acc_buf.end(), T(0));
          for (int64_t n = 0; n < g.N; ++n) {
            const T* x = inp + (n * g.C_in + grp * cig + cl) * inP;
            for (int64_t oh = 0; oh < g.H_out; ++oh) {
              const T* __restrict dy = dout + (n * g.C_out + co) * P + oh * Wo;
              for (int64_t ki = 0; ki < g.kh; ++ki) {
                const int64_t ih = oh * g.stride_h - g.pad_h + ki * g.dil_h;
                if (ih < 0 || ih >= g.H) continue;
                const T* __restrict row = x + ih * g.W;
                for (int64_t kj = 0; kj < g.kw; ++kj) {
                  T* __restrict acc = acc_buf.data() + (ki * g.kw + kj) * Wo;
                  const Tap& t = tp[size_t(kj)];
                  if (sw == 1)
                    for (int64_t ow = t.lo; ow < t.hi; ++ow) acc[ow] += dy[ow] * row[ow + t.off];
                  else
                    for (int64_t ow = t.lo; ow < t.hi; ++ow) acc[ow] += dy[ow] * row[ow * sw + t.off];
                }
              }
            }
          }
          T* dw = dweight + u * KK;
          for (int64_t k = 0; k < KK; ++k) {
            const T* acc = acc_buf.data() + k * Wo;
            T s = 0;
            for (int64_t ow = 0; ow < Wo; ++ow) s += acc[ow];
            dw[k] += s;
          }
        }
      },
      grain(double(g.N * KK * P)));
}

}  // namespace nns
