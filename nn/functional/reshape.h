#pragma once
// reshape(x, shape) and flatten(x) -> (N, rest). The result shares x's storage (free);
// its gradient is the output gradient with x's shape.
#include <stdexcept>

#include "core/autograd.h"
#include "core/kernels/map.h"

namespace nns {

template <class T>
Var<T> reshape(const Var<T>& x, const Shape& shape) {
  if (shape.numel() != x.numel())
    throw std::invalid_argument("reshape: cannot view " + x.shape().str() + " as " + shape.str());
  return make_result<T>(x.value().reshape(shape), {x}, "reshape", [](Node<T>& node) {
    T* d = node.parents[0]->grad_buffer().data();
    const T* g = node.grad.data();
    parallel_for(
        node.grad.numel(),
        [&](int64_t b, int64_t e) {
          for (int64_t i = b; i < e; ++i) d[i] += g[i];
        },
        kElementwiseGrain, 16);
  });
}

// (N, d1, d2, ...) -> (N, d1*d2*...)
template <class T>
Var<T> flatten(const Var<T>& x) {
  if (x.shape().dim() < 1) throw std::invalid_argument("flatten: needs at least one dimension");
  const int64_t n = x.size(0);
  return reshape(x, Shape{n, n ? x.numel() / n : 0});
}

}  // namespace nns
