#pragma once
// Parameter penalties (NNAO's regularizer gamma * |theta|):
//   l1_penalty(params) = sum over all parameters of |theta|
//   l2_penalty(params) = sum over all parameters of theta^2   (no 1/2 factor)
// Each returns a 0-d scalar Var; multiply by the weight yourself, e.g.
//   loss = mse_loss(y, t) + l1_penalty(net.parameters()) * gamma.
#include <cmath>
#include <vector>

#include "core/autograd.h"
#include "core/kernels/reduce.h"

namespace nns {

namespace detail {
template <class T, class F, class DF>
Var<T> parameter_penalty(const std::vector<Var<T>>& params, const char* name, F f, DF df) {
  double s = 0;  // parameters in list order: deterministic
  for (const auto& p : params) {
    const T* v = p.value().data();
    s += chunked_sum(p.numel(), [&](int64_t i) { return f(double(v[i])); });
  }
  Tensor<T> out(Shape{});
  out[0] = T(s);
  return make_result<T>(std::move(out), params, name, [df](Node<T>& n) {
    const T g = n.grad[0];
    for (size_t k = 0; k < n.parents.size(); ++k) {
      if (!wants_grad(n, k)) continue;
      T* d = n.parents[k]->grad_buffer().data();
      const T* v = n.parents[k]->value.data();
      const int64_t cnt = n.parents[k]->value.numel();
      for (int64_t i = 0; i < cnt; ++i) d[i] += g * df(v[i]);
    }
  });
}
}  // namespace detail

// Subgradient 0 at theta = 0.
template <class T>
Var<T> l1_penalty(const std::vector<Var<T>>& params) {
  return detail::parameter_penalty(
      params, "l1_penalty", [](double v) { return std::abs(v); }, [](T v) { return T((v > 0) - (v < 0)); });
}

template <class T>
Var<T> l2_penalty(const std::vector<Var<T>>& params) {
  return detail::parameter_penalty(
      params, "l2_penalty", [](double v) { return v * v; }, [](T v) { return T(2) * v; });
}

}  // namespace nns
