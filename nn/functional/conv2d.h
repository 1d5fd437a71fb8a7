#pragma once
// y = conv2d(x, W) + b, recorded in the autograd graph (PyTorch's F.conv2d):
//   x (N, C_in, H, W), W (C_out, C_in/groups, kh, kw), b (C_out) or undefined
//   y (N, C_out, H_out, W_out), H_out = (H + 2p - d(k-1) - 1)/s + 1
#include <stdexcept>
#include <string>

#include "core/autograd.h"
#include "core/kernels/conv2d.h"

namespace nns {

struct Conv2dParams {
  int stride_h = 1, stride_w = 1, pad_h = 0, pad_w = 0, dil_h = 1, dil_w = 1, groups = 1;

  // The same stride, padding and dilation in both directions.
  static Conv2dParams square(int stride, int padding = 0, int dilation = 1, int groups = 1) {
    return {stride, stride, padding, padding, dilation, dilation, groups};
  }
};

template <class T>
Var<T> conv2d(const Var<T>& x, const Var<T>& w, const Var<T>& b = Var<T>(), const Conv2dParams& p = {}) {
  if (x.shape().dim() != 4 || w.shape().dim() != 4)
    throw std::invalid_argument("conv2d: input " + x.shape().str() + " and weight " + w.shape().str() +
                                " must both be 4-d (NCHW, OIHW)");
  if (p.groups <= 0 || w.size(1) * p.groups != x.size(1))
    throw std::invalid_argument("conv2d: weight " + w.shape().str() + " with groups=" + std::to_string(p.groups) +
                                " does not match input channels of " + x.shape().str());
  if (b.defined() && b.shape() != Shape{w.size(0)})
    throw std::invalid_argument("conv2d: bias " + b.shape().str() + " for " + std::to_string(w.size(0)) +
                                " output channels");
  const ConvGeometry g = conv2d_geometry(x.size(0), x.size(1), x.size(2), x.size(3), w.size(0), w.size(2), w.size(3),
                                         p.stride_h, p.stride_w, p.pad_h, p.pad_w, p.dil_h, p.dil_w, p.groups);
  Tensor<T> out({g.N, g.C_out, g.H_out, g.W_out});
  conv2d_forward(out.data(), x.value().data(), w.value().data(), b.defined() ? b.value().data() : nullptr, g);
  return make_result<T>(std::move(out), {x, w, b}, "conv2d", [g](Node<T>& n) {
    conv2d_backward(wants_grad(n, 0) ? n.parents[0]->grad_buffer().data() : nullptr,
                    wants_grad(n, 1) ? n.parents[1]->grad_buffer().data() : nullptr,
                    wants_grad(n, 2) ? n.parents[2]->grad_buffer().data() : nullptr, n.grad.data(),
                    n.parents[0]->value.data(), n.parents[1]->value.data(), g);
  });
}

}  // namespace nns
