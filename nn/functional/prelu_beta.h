#pragma once
// prelu_beta(x, alpha, beta) = beta * max(x, 0) + alpha * min(x, 0)  (NNAO eq. 1).
// x is (N, C) or (N, C, H, W); alpha and beta are (C), applied along dim 1.
#include <stdexcept>

#include "core/autograd.h"
#include "core/kernels/prelu_beta.h"

namespace nns {

template <class T>
Var<T> prelu_beta(const Var<T>& x, const Var<T>& alpha, const Var<T>& beta) {
  if (x.shape().dim() < 2 || alpha.shape() != Shape{x.size(1)} || beta.shape() != Shape{x.size(1)})
    throw std::invalid_argument("prelu_beta: input " + x.shape().str() + " needs alpha and beta of shape [" +
                                std::to_string(x.shape().dim() < 2 ? 0 : x.size(1)) + "], got " + alpha.shape().str() +
                                " and " + beta.shape().str());
  const int64_t N = x.size(0), C = x.size(1), S = C && N ? x.numel() / (N * C) : 0;
  Tensor<T> out(x.shape());
  prelu_beta_forward(out.data(), x.value().data(), alpha.value().data(), beta.value().data(), N, C, S);
  return make_result<T>(std::move(out), {x, alpha, beta}, "prelu_beta", [N, C, S](Node<T>& n) {
    prelu_beta_backward(wants_grad(n, 0) ? n.parents[0]->grad_buffer().data() : nullptr,
                        wants_grad(n, 1) ? n.parents[1]->grad_buffer().data() : nullptr,
                        wants_grad(n, 2) ? n.parents[2]->grad_buffer().data() : nullptr, n.grad.data(),
                        n.parents[0]->value.data(), n.parents[1]->value.data(), n.parents[2]->value.data(), N, C, S);
  });
}

}  // namespace nns
