#pragma once
// batch_norm(x, gamma, beta, running_mean, running_var, training, momentum, eps) with
// PyTorch's semantics. x is (N, C) or (N, C, H, W); gamma/beta (C) or undefined.
//  * training: normalize with the batch mean and BIASED variance; if running stats are
//    given, update them as running = (1 - momentum) * running + momentum * batch, with
//    the UNBIASED variance (M / (M - 1), M = N*H*W values per channel). At M = 1 (batch
//    1, 1x1 spatial, which pix2pix's bottleneck reaches) the variance is 0, the output
//    is beta and the running variance takes the biased value 0 (PyTorch refuses M = 1).
//  * eval: normalize with the running statistics (required).
// running_mean / running_var may be nullptr (no update). The mode is the caller's to choose; it never depends on the
// batch size.
#include <stdexcept>
#include <string>
#include <type_traits>

#include "core/autograd.h"
#include "core/kernels/batch_norm.h"

namespace nns {

template <class T>
Var<T> batch_norm(const Var<T>& x, const Var<T>& gamma, const Var<T>& beta,
                  std::type_identity_t<Tensor<T>>* running_mean, std::type_identity_t<Tensor<T>>* running_var,
                  bool training, double momentum = 0.1, double eps = 1e-5) {
  const Shape& xs = x.shape();
  if (xs.dim() != 2 && xs.dim() != 4)
    throw std::invalid_argument("batch_norm: input must be (N, C) or (N, C, H, W), got " + xs.str());
  const int64_t N = xs[0], C = xs[1], S = xs.dim() == 4 ? xs[2] * xs[3] : 1;
  const Shape cs{C};
  if (gamma.defined()) check_shape(gamma.value(), cs, "batch_norm weight (gamma)");
  if (beta.defined()) check_shape(beta.value(), cs, "batch_norm bias (beta)");
  if (running_mean) check_shape(*running_mean, cs, "batch_norm running_mean");
  if (running_var) check_shape(*running_var, cs, "batch_norm running_var");
  if (N * S == 0) throw std::invalid_argument("batch_norm: empty input " + xs.str());
  const T* g = gamma.defined() ? gamma.value().data() : nullptr;
  const T* b = beta.defined() ? beta.value().data() : nullptr;

  Tensor<T> out(xs), mean(cs), rstd(cs);
  if (training) {
    Tensor<T> var(cs);
    batch_norm_forward_train(out.data(), mean.data(), var.data(), rstd.data(), x.value().data(), g, b, N, C, S, eps);
    const double M = double(N * S), unbias = M > 1 ? M / (M - 1) : 1.0;
    for (int64_t c = 0; c < C; ++c) {
      if (running_mean)
        (*running_mean)[c] = T((1 - momentum) * double((*running_mean)[c]) + momentum * double(mean[c]));
      if (running_var)
        (*running_var)[c] = T((1 - momentum) * double((*running_var)[c]) + momentum * double(var[c]) * unbias);
    }
  } else {
    if (!running_mean || !running_var)
      throw std::invalid_argument("batch_norm: eval mode needs running_mean and running_var");
    mean = running_mean->clone();  // saved: the buffers may change before backward
    batch_norm_forward_eval(out.data(), rstd.data(), x.value().data(), g, b, mean.data(), running_var->data(), N, C, S,
                            eps);
  }
  return make_result<T>(std::move(out), {x, gamma, beta}, "batch_norm", [mean, rstd, N, C, S, training](Node<T>& n) {
    const auto& gp = n.parents[1];
    batch_norm_backward(wants_grad(n, 0) ? n.parents[0]->grad_buffer().data() : nullptr,
                        wants_grad(n, 1) ? n.parents[1]->grad_buffer().data() : nullptr,
                        wants_grad(n, 2) ? n.parents[2]->grad_buffer().data() : nullptr, n.grad.data(),
                        n.parents[0]->value.data(), gp ? gp->value.data() : nullptr, mean.data(), rstd.data(), N, C, S,
                        training);
  });
}

}  // namespace nns
