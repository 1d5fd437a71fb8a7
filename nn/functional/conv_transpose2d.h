#pragma once
// y = conv_transpose2d(x, W) + b, recorded in the autograd graph (PyTorch's
// F.conv_transpose2d):
//   x (N, C_in, H, W), W (C_in, C_out/groups, kh, kw), b (C_out) or undefined
//   y (N, C_out, H_out, W_out), H_out = (H - 1)s - 2p + d(k-1) + output_padding + 1
#include <stdexcept>
#include <string>

#include "core/autograd.h"
#include "core/kernels/conv_transpose2d.h"

namespace nns {

struct ConvTranspose2dParams {
  int stride_h = 1, stride_w = 1, pad_h = 0, pad_w = 0, out_pad_h = 0, out_pad_w = 0;
  int dil_h = 1, dil_w = 1, groups = 1;

  // The same stride, padding, output padding and dilation in both directions.
  static ConvTranspose2dParams square(int stride, int padding = 0, int output_padding = 0, int dilation = 1,
                                      int groups = 1) {
    return {stride, stride, padding, padding, output_padding, output_padding, dilation, dilation, groups};
  }
};

template <class T>
Var<T> conv_transpose2d(const Var<T>& x, const Var<T>& w, const Var<T>& b = Var<T>(),
                        const ConvTranspose2dParams& p = {}) {
  if (x.shape().dim() != 4 || w.shape().dim() != 4)
    throw std::invalid_argument("conv_transpose2d: input " + x.shape().str() + " and weight " + w.shape().str() +
                                " must both be 4-d (NCHW, IOHW)");
  if (p.groups <= 0 || w.size(0) != x.size(1) || x.size(1) % p.groups)
    throw std::invalid_argument("conv_transpose2d: weight " + w.shape().str() + " with groups=" +
                                std::to_string(p.groups) + " does not match input channels of " + x.shape().str());
  const int64_t C_out = w.size(1) * p.groups;
  if (b.defined() && b.shape() != Shape{C_out})
    throw std::invalid_argument("conv_transpose2d: bias " + b.shape().str() + " for " + std::to_string(C_out) +
                                " output channels");
  const ConvGeometry g =
      conv_transpose2d_geometry(x.size(0), x.size(1), x.size(2), x.size(3), C_out, w.size(2), w.size(3), p.stride_h,
                                p.stride_w, p.pad_h, p.pad_w, p.out_pad_h, p.out_pad_w, p.dil_h, p.dil_w, p.groups);
  Tensor<T> out({g.N, g.C_in, g.H, g.W});
  conv_transpose2d_forward(out.data(), x.value().data(), w.value().data(), b.defined() ? b.value().data() : nullptr, g);
  return make_result<T>(std::move(out), {x, w, b}, "conv_transpose2d", [g](Node<T>& n) {
    conv_transpose2d_backward(wants_grad(n, 0) ? n.parents[0]->grad_buffer().data() : nullptr,
                              wants_grad(n, 1) ? n.parents[1]->grad_buffer().data() : nullptr,
                              wants_grad(n, 2) ? n.parents[2]->grad_buffer().data() : nullptr, n.grad.data(),
                              n.parents[0]->value.data(), n.parents[1]->value.data(), g);
  });
}

}  // namespace nns
