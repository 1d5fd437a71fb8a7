#pragma once
// y = x W^T + b on a batch: x (B, IN), W (OUT, IN), b (OUT) or undefined.
#include <stdexcept>

#include "core/autograd.h"
#include "core/kernels/linear.h"

namespace nns {

template <class T>
Var<T> linear(const Var<T>& x, const Var<T>& w, const Var<T>& b = Var<T>()) {
  if (x.shape().dim() != 2 || w.shape().dim() != 2 || x.size(1) != w.size(1))
    throw std::invalid_argument("linear: input " + x.shape().str() + " and weight " + w.shape().str() +
                                " do not match");
  const int64_t B = x.size(0), IN = x.size(1), OUT = w.size(0);
  Tensor<T> out({B, OUT});
  linear_forward(out.data(), x.value().data(), w.value().data(), b.defined() ? b.value().data() : nullptr, B, IN, OUT);
  return make_result<T>(std::move(out), {x, w, b}, "linear", [B, IN, OUT](Node<T>& n) {
    const auto& xv = n.parents[0]->value;
    const auto& wv = n.parents[1]->value;
    linear_backward(wants_grad(n, 0) ? n.parents[0]->grad_buffer().data() : nullptr,
                    wants_grad(n, 1) ? n.parents[1]->grad_buffer().data() : nullptr,
                    wants_grad(n, 2) ? n.parents[2]->grad_buffer().data() : nullptr, n.grad.data(), xv.data(),
                    wv.data(), B, IN, OUT);
  });
}

}  // namespace nns
