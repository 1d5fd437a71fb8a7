#pragma once
// Naive direct-loop convolutions: the definitions the fast kernels are tested against
// (and benchmarks check before they time). Written from each op's own definition, not
// from each other, so a shared mistake in the fast kernels cannot hide.
//   conv2d:           inp (N, C_in, H, W), weight (C_out, C_in/g, kh, kw) -> (N, C_out, H_out, W_out)
//   conv_transpose2d: inp (N, C_out, H_out, W_out), weight (C_out, C_in/g, kh, kw) -> (N, C_in, H, W)
// where g is a ConvGeometry (for the transposed op, that of the convolution it inverts:
// its input channels C_out are the conv's output channels).
#include <cstdint>

#include "core/kernels/conv_geometry.h"

namespace nns {

// Calls f(ih, iw, oh, ow, ki, kj) for every tap of the kernel that lands inside the input.
template <class F>
inline void for_each_tap(const ConvGeometry& g, F&& f) {
  for (int64_t oh = 0; oh < g.H_out; ++oh)
    for (int64_t ow = 0; ow < g.W_out; ++ow)
      for (int64_t ki = 0; ki < g.kh; ++ki)
        for (int64_t kj = 0; kj < g.kw; ++kj) {
          int64_t ih = oh * g.stride_h - g.pad_h + ki * g.dil_h;
          int64_t iw = ow * g.stride_w - g.pad_w + kj * g.dil_w;
          if (ih >= 0 && ih < g.H && iw >= 0 && iw < g.W) f(ih, iw, oh, ow, ki, kj);
        }
}

// out (N, C_out, H_out, W_out) is assigned; bias (C_out) may be null.
template <class T>
void conv2d_forward_reference(T* out, const T* inp, const T* weight, const T* bias, const ConvGeometry& g) {
  const int64_t cig = g.cin_g(), cog = g.cout_g();
  for (int64_t n = 0; n < g.N; ++n)
    for (int64_t co = 0; co < g.C_out; ++co) {
      T* o = out + (n * g.C_out + co) * g.out_plane();
      for (int64_t i = 0; i < g.out_plane(); ++i) o[i] = bias ? bias[co] : T(0);
      const int64_t grp = co / cog;
      for (int64_t c = 0; c < cig; ++c) {
        const T* x = inp + (n * g.C_in + grp * cig + c) * g.in_plane();
        const T* w = weight + (co * cig + c) * g.kh * g.kw;
        for_each_tap(g, [&](int64_t ih, int64_t iw, int64_t oh, int64_t ow, int64_t ki, int64_t kj) {
          o[oh * g.W_out + ow] += x[ih * g.W + iw] * w[ki * g.kw + kj];
        });
      }
    }
}

// Accumulates into dinp (N, C_in, H, W), dweight (C_out, C_in/g, kh, kw), dbias (C_out);
// any may be null.
template <class T>
void conv2d_backward_reference(T* dinp, T* dweight, T* dbias, const T* dout, const T* inp, const T* weight,
                               const ConvGeometry& g) {
  const int64_t cig = g.cin_g(), cog = g.cout_g();
  for (int64_t n = 0; n < g.N; ++n)
    for (int64_t co = 0; co < g.C_out; ++co) {
      const T* d = dout + (n * g.C_out + co) * g.out_plane();
      if (dbias)
        for (int64_t i = 0; i < g.out_plane(); ++i) dbias[co] += d[i];
      const int64_t grp = co / cog;
      for (int64_t c = 0; c < cig; ++c) {
        const int64_t xoff = (n * g.C_in + grp * cig + c) * g.in_plane();
        const int64_t woff = (co * cig + c) * g.kh * g.kw;
        for_each_tap(g, [&](int64_t ih, int64_t iw, int64_t oh, int64_t ow, int64_t ki, int64_t kj) {
          T dy = d[oh * g.W_out + ow];
          if (dinp) dinp[xoff + ih * g.W + iw] += dy * weight[woff + ki * g.kw + kj];
          if (dweight) dweight[woff + ki * g.kw + kj] += dy * inp[xoff + ih * g.W + iw];
        });
      }
    }
}

// The transposed convolution by its definition: every input pixel scatters its
// kernel-weighted copy into the output. out (N, C_in, H, W) is assigned; bias (C_in).
template <class T>
void conv_transpose2d_forward_reference(T* out, const T* inp, const T* weight, const T* bias, const ConvGeometry& g) {
  const int64_t cig = g.cin_g(), cog = g.cout_g();
  for (int64_t n = 0; n < g.N; ++n)
    for (int64_t c = 0; c < g.C_in; ++c) {
      T* o = out + (n * g.C_in + c) * g.in_plane();
      for (int64_t i = 0; i < g.in_plane(); ++i) o[i] = bias ? bias[c] : T(0);
    }
  for (int64_t n = 0; n < g.N; ++n)
    for (int64_t ci = 0; ci < g.C_out; ++ci) {
      const T* x = inp + (n * g.C_out + ci) * g.out_plane();
      const int64_t grp = ci / cog;
      for (int64_t c = 0; c < cig; ++c) {
        T* o = out + (n * g.C_in + grp * cig + c) * g.in_plane();
        const T* w = weight + (ci * cig + c) * g.kh * g.kw;
        for_each_tap(g, [&](int64_t oh, int64_t ow, int64_t ih, int64_t iw, int64_t ki, int64_t kj) {
          o[oh * g.W + ow] += x[ih * g.W_out + iw] * w[ki * g.kw + kj];
        });
      }
    }
}

// Accumulates into dinp (N, C_out, H_out, W_out), dweight (C_out, C_in/g, kh, kw),
// dbias (C_in); any may be null.
template <class T>
void conv_transpose2d_backward_reference(T* dinp, T* dweight, T* dbias, const T* dout, const T* inp, const T* weight,
                                         const ConvGeometry& g) {
  const int64_t cig = g.cin_g(), cog = g.cout_g();
  if (dbias)
    for (int64_t n = 0; n < g.N; ++n)
      for (int64_t c = 0; c < g.C_in; ++c)
        for (int64_t i = 0; i < g.in_plane(); ++i) dbias[c] += dout[(n * g.C_in + c) * g.in_plane() + i];
  for (int64_t n = 0; n < g.N; ++n)
    for (int64_t ci = 0; ci < g.C_out; ++ci) {
      const int64_t xoff = (n * g.C_out + ci) * g.out_plane();
      const int64_t grp = ci / cog;
      for (int64_t c = 0; c < cig; ++c) {
        const T* d = dout + (n * g.C_in + grp * cig + c) * g.in_plane();
        const int64_t woff = (ci * cig + c) * g.kh * g.kw;
        for_each_tap(g, [&](int64_t oh, int64_t ow, int64_t ih, int64_t iw, int64_t ki, int64_t kj) {
          T dy = d[oh * g.W + ow];
          if (dinp) dinp[xoff + ih * g.W_out + iw] += dy * weight[woff + ki * g.kw + kj];
          if (dweight) dweight[woff + ki * g.kw + kj] += dy * inp[xoff + ih * g.W_out + iw];
        });
      }
    }
}

}  // namespace nns
