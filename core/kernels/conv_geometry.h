#pragma once
// The geometry of one 2-d convolution, shared by conv2d and conv_transpose2d.
//
// It always describes the *forward convolution*: input (N, C_in, H, W), weight
// (C_out, C_in/groups, kh, kw), output (N, C_out, H_out, W_out). A transposed
// convolution is this convolution run backwards, so it is described by the geometry of
// the convolution whose input-gradient pass it is (see core/kernels/conv_transpose2d.h).
// H_out/W_out are stored, not recomputed, because a transposed convolution with
// output_padding >= stride (allowed when dilation > stride) has a conv "input" one row
// larger than the formula would give back.
#include <cstdint>
#include <stdexcept>
#include <string>

namespace nns {

struct ConvGeometry {
  int64_t N = 0, C_in = 0, H = 0, W = 0;  // input (N, C_in, H, W)
  int64_t C_out = 0, kh = 0, kw = 0;      // weight (C_out, C_in/groups, kh, kw)
  int64_t stride_h = 1, stride_w = 1, pad_h = 0, pad_w = 0, dil_h = 1, dil_w = 1, groups = 1;
  int64_t H_out = 0, W_out = 0;  // output (N, C_out, H_out, W_out)

  int64_t cin_g() const { return C_in / groups; }
  int64_t cout_g() const { return C_out / groups; }
  int64_t col_rows() const { return cin_g() * kh * kw; }  // GEMM K of the forward pass
  int64_t in_plane() const { return H * W; }
  int64_t out_plane() const { return H_out * W_out; }
  int64_t weight_numel() const { return C_out * col_rows(); }
  // The kernel is the identity gather: im2col would copy the input unchanged.
  bool is_pointwise() const { return kh == 1 && kw == 1 && stride_h == 1 && stride_w == 1 && pad_h == 0 && pad_w == 0; }
  // Multiply-adds of one forward pass (a backward pass costs twice this).
  double macs() const { return double(N) * C_out * out_plane() * col_rows(); }
};

// PyTorch's output size: floor((in + 2p - d(k-1) - 1) / s) + 1.
inline int64_t conv_out_size(int64_t in, int64_t k, int64_t s, int64_t p, int64_t d) {
  return (in + 2 * p - d * (k - 1) - 1) / s + 1;
}

// Checks the arguments of a convolution and fills in H_out/W_out (if not set).
inline void validate(ConvGeometry& g, const char* op) {
  auto fail = [&](const std::string& why) { throw std::invalid_argument(std::string(op) + ": " + why); };
  if (g.N < 0 || g.C_in <= 0 || g.H <= 0 || g.W <= 0 || g.C_out <= 0) fail("empty input or channel count");
  if (g.kh <= 0 || g.kw <= 0) fail("kernel size must be positive");
  if (g.stride_h <= 0 || g.stride_w <= 0) fail("stride must be positive");
  if (g.dil_h <= 0 || g.dil_w <= 0) fail("dilation must be positive");
  if (g.pad_h < 0 || g.pad_w < 0) fail("padding must be non-negative");
  if (g.groups <= 0 || g.C_in % g.groups || g.C_out % g.groups)
    fail("groups=" + std::to_string(g.groups) + " must divide in channels (" + std::to_string(g.C_in) +
         ") and out channels (" + std::to_string(g.C_out) + ")");
  if (g.H_out == 0 && g.W_out == 0) {
    g.H_out = conv_out_size(g.H, g.kh, g.stride_h, g.pad_h, g.dil_h);
    g.W_out = conv_out_size(g.W, g.kw, g.stride_w, g.pad_w, g.dil_w);
  }
  if (g.H_out <= 0 || g.W_out <= 0)
    fail("input " + std::to_string(g.H) + "x" + std::to_string(g.W) + " is smaller than the dilated kernel " +
         std::to_string(g.dil_h * (g.kh - 1) + 1) + "x" + std::to_string(g.dil_w * (g.kw - 1) + 1) + " after padding");
}

}  // namespace nns
