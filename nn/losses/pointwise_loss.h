#pragma once
// Records a mean-reduced pointwise loss (pred vs target, same shape) in the graph. The
// result is a 0-d scalar (shape {}), like sum() and mean(). The target may be a
// constant Var (no grad); if it requires grad it receives its gradient too.
#include <stdexcept>
#include <string>

#include "core/autograd.h"

namespace nns {

template <class T, class Fwd, class Bwd>
Var<T> pointwise_loss(const Var<T>& pred, const Var<T>& target, const char* name, Fwd fwd, Bwd bwd) {
  if (pred.shape() != target.shape())
    throw std::invalid_argument(std::string(name) + ": prediction " + pred.shape().str() + " and target " +
                                target.shape().str() + " differ");
  const int64_t n = pred.numel();
  if (n == 0) throw std::invalid_argument(std::string(name) + ": empty input");
  Tensor<T> out(Shape{});
  out[0] = T(fwd(pred.value().data(), target.value().data(), n));
  return make_result<T>(std::move(out), {pred, target}, name, [bwd, n](Node<T>& node) {
    bwd(wants_grad(node, 0) ? node.parents[0]->grad_buffer().data() : nullptr,
        wants_grad(node, 1) ? node.parents[1]->grad_buffer().data() : nullptr, node.grad[0],
        node.parents[0]->value.data(), node.parents[1]->value.data(), n);
  });
}

}  // namespace nns
