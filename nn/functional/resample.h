#pragma once
// avg_pool2x2(x): (N, C, H, W) -> (N, C, H/2, W/2), 2x2 means, stride 2.
// upsample_bilinear2x(x): (N, C, H, W) -> (N, C, 2H, 2W), PyTorch's bilinear upsampling
// with align_corners=False.
#include <stdexcept>
#include <string>

#include "core/autograd.h"
#include "core/kernels/avg_pool2x2.h"
#include "core/kernels/upsample_bilinear2x.h"

namespace nns {

namespace detail {
inline void require_nchw(const Shape& s, const char* op) {
  if (s.dim() != 4) throw std::invalid_argument(std::string(op) + ": expected (N, C, H, W), got " + s.str());
}
}  // namespace detail

template <class T>
Var<T> avg_pool2x2(const Var<T>& x) {
  detail::require_nchw(x.shape(), "avg_pool2x2");
  const int64_t P = x.size(0) * x.size(1), H = x.size(2), W = x.size(3);
  Tensor<T> out({x.size(0), x.size(1), H / 2, W / 2});
  avg_pool2x2_forward(out.data(), x.value().data(), P, H, W);
  return make_result<T>(std::move(out), {x}, "avg_pool2x2", [P, H, W](Node<T>& n) {
    avg_pool2x2_backward(n.parents[0]->grad_buffer().data(), n.grad.data(), P, H, W);
  });
}

template <class T>
Var<T> upsample_bilinear2x(const Var<T>& x) {
  detail::require_nchw(x.shape(), "upsample_bilinear2x");
  const int64_t P = x.size(0) * x.size(1), H = x.size(2), W = x.size(3);
  Tensor<T> out({x.size(0), x.size(1), 2 * H, 2 * W});
  upsample_bilinear2x_forward(out.data(), x.value().data(), P, H, W);
  return make_result<T>(std::move(out), {x}, "upsample_bilinear2x", [P, H, W](Node<T>& n) {
    upsample_bilinear2x_backward(n.parents[0]->grad_buffer().data(), n.grad.data(), P, H, W);
  });
}

}  // namespace nns
