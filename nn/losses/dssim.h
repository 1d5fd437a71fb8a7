#pragma once
// Deep Shading's loss (Nalbach et al. 2017): DSSIM = (1 - SSIM) / 2, with SSIM as in
// core/kernels/ssim.h (11x11 Gaussian window, sigma 1.5, constants for data in [0, 1],
// computed per channel over valid window positions, averaged). The paper tiles 8x8
// patches; we use the standard Gaussian-window SSIM.
//   dssim_loss(pred, target) -> 0-d scalar Var; ssim(a, b) -> double, for metrics.
// Inputs are (..., H, W) with H, W >= 11; every leading dim is a separate plane.
#include <stdexcept>
#include <string>

#include "core/autograd.h"
#include "core/kernels/ssim.h"

namespace nns {

namespace detail {
inline void ssim_check(const Shape& a, const Shape& b, const char* op) {
  if (a != b) throw std::invalid_argument(std::string(op) + ": shapes " + a.str() + " and " + b.str() + " differ");
  if (a.dim() < 2 || a[-1] < kSsimWindow || a[-2] < kSsimWindow)
    throw std::invalid_argument(std::string(op) + ": needs images of at least 11x11 (the SSIM window), got " + a.str());
}
}  // namespace detail

template <class T>
double ssim(const Tensor<T>& a, const Tensor<T>& b) {
  detail::ssim_check(a.shape(), b.shape(), "ssim");
  const int64_t H = a.shape()[-2], W = a.shape()[-1];
  return ssim_forward(a.data(), b.data(), a.numel() / (H * W), H, W);
}

template <class T>
Var<T> dssim_loss(const Var<T>& pred, const Var<T>& target) {
  detail::ssim_check(pred.shape(), target.shape(), "dssim_loss");
  const int64_t H = pred.shape()[-2], W = pred.shape()[-1], P = pred.numel() / (H * W);
  Tensor<T> out(Shape{});
  out[0] = T((1 - ssim_forward(pred.value().data(), target.value().data(), P, H, W)) / 2);
  return make_result<T>(std::move(out), {pred, target}, "dssim_loss", [P, H, W](Node<T>& n) {
    ssim_backward(wants_grad(n, 0) ? n.parents[0]->grad_buffer().data() : nullptr,
                  wants_grad(n, 1) ? n.parents[1]->grad_buffer().data() : nullptr, -0.5 * double(n.grad[0]),
                  n.parents[0]->value.data(), n.parents[1]->value.data(), P, H, W);
  });
}

}  // namespace nns
