#pragma once
// Transposed 2-d convolution = the convolution run backwards (tinygrad, ggml): its
// forward is conv2d's input-gradient pass (GEMM + col2im), its input gradient is
// conv2d's forward, its weight gradient is conv2d's weight gradient with the roles of
// input and output gradient swapped. One kernel set serves both layers; there is no
// per-element scatter.
//
// `g` is the geometry of the convolution being inverted (core/kernels/conv_geometry.h),
// so, in PyTorch's names for ConvTranspose2d:
//   inp    (N, Cin_t, H_t, W_t)           = (N, g.C_out, g.H_out, g.W_out)
//   weight (Cin_t, Cout_t/groups, kh, kw) = (g.C_out, g.C_in/groups, kh, kw)
//   bias   (Cout_t) = (g.C_in) or null
//   out    (N, Cout_t, Hout_t, Wout_t)    = (N, g.C_in, g.H, g.W)
//   Hout_t = (H_t - 1)s - 2p + d(k-1) + output_padding + 1
#include <cstdint>

#include "core/kernels/conv2d.h"

namespace nns {

// Geometry of the convolution that a ConvTranspose2d inverts.
inline ConvGeometry conv_transpose2d_geometry(int64_t N, int64_t C_in_t, int64_t H_t, int64_t W_t, int64_t C_out_t,
                                              int64_t kh, int64_t kw, int64_t stride_h, int64_t stride_w, int64_t pad_h,
                                              int64_t pad_w, int64_t out_pad_h, int64_t out_pad_w, int64_t dil_h,
                                              int64_t dil_w, int64_t groups) {
  // PyTorch: output padding must be smaller than either stride or dilation.
  if (out_pad_h < 0 || out_pad_w < 0 || out_pad_h >= std::max(stride_h, dil_h) ||
      out_pad_w >= std::max(stride_w, dil_w))
    throw std::invalid_argument("conv_transpose2d: output_padding (" + std::to_string(out_pad_h) + ", " +
                                std::to_string(out_pad_w) +
                                ") must be non-negative and smaller than stride or dilation");
  ConvGeometry g;
  g.N = N;
  g.C_in = C_out_t;
  g.C_out = C_in_t;
  g.kh = kh, g.kw = kw;
  g.stride_h = stride_h, g.stride_w = stride_w, g.pad_h = pad_h, g.pad_w = pad_w;
  g.dil_h = dil_h, g.dil_w = dil_w, g.groups = groups;
  g.H = (H_t - 1) * stride_h - 2 * pad_h + dil_h * (kh - 1) + out_pad_h + 1;
  g.W = (W_t - 1) * stride_w - 2 * pad_w + dil_w * (kw - 1) + out_pad_w + 1;
  g.H_out = H_t, g.W_out = W_t;
  if (g.H <= 0 || g.W <= 0)
    throw std::invalid_argument("conv_transpose2d: output size " + std::to_string(g.H) + "x" + std::to_string(g.W) +
                                " is not positive (padding too large)");
  validate(g, "conv_transpose2d");
  return g;
}

// out (N, g.C_in, g.H, g.W) is assigned.
template <class T>
void conv_transpose2d_forward(T* out, const T* inp, const T* weight, const T* bias, const ConvGeometry& g) {
  conv2d_backward_input(out, inp, weight, g, /*accumulate=*/false);
  if (bias) add_channel_bias(out, bias, g.N, g.C_in, g.in_plane());
}

// Accumulates into dinp (shape of inp), dweight, dbias; any may be null.
template <class T>
void conv_transpose2d_backward(T* dinp, T* dweight, T* dbias, const T* dout, const T* inp, const T* weight,
                               const ConvGeometry& g) {
  if (dbias) channel_sum_add(dbias, dout, g.N, g.C_in, g.in_plane());
  if (dweight) conv2d_backward_weight(dweight, /*dout=*/inp, /*inp=*/dout, g);
  if (dinp) conv2d_gemm_forward(dinp, dout, weight, static_cast<const T*>(nullptr), g, /*accumulate=*/true);
}

}  // namespace nns
