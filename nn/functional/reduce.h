#pragma once
// sum(x) and mean(x) over all elements. The result is a 0-d scalar: shape {} with
// numel() == 1 (PyTorch's convention), so backward() can start from it. Every loss in
// nn/losses returns the same scalar shape.
#include "core/autograd.h"
#include "core/kernels/reduce.h"

namespace nns {

template <class T>
Var<T> sum(const Var<T>& x) {
  const int64_t n = x.numel();
  Tensor<T> out(Shape{});
  sum_forward(out.data(), x.value().data(), n);
  return make_result<T>(std::move(out), {x}, "sum", [n](Node<T>& node) {
    sum_backward(node.parents[0]->grad_buffer().data(), node.grad.data(), n, T(1));
  });
}

template <class T>
Var<T> mean(const Var<T>& x) {
  const int64_t n = x.numel();
  if (n == 0) throw std::invalid_argument("mean: empty tensor " + x.shape().str());
  Tensor<T> out(Shape{});
  out[0] = T(chunked_sum(n, [p = x.value().data()](int64_t i) { return double(p[i]); }) / double(n));
  return make_result<T>(std::move(out), {x}, "mean", [n](Node<T>& node) {
    sum_backward(node.parents[0]->grad_buffer().data(), node.grad.data(), n, T(1.0 / double(n)));
  });
}

}  // namespace nns
