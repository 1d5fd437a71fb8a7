#pragma once
// Records a one-input pointwise op in the graph. `fwd(out, inp, n)` runs the forward
// kernel; `bwd(dinp, dout, inp, out, n)` accumulates the input gradient. The backward
// reads the input and output values straight from the graph nodes, so nothing extra is
// saved.
#include <utility>

#include "core/autograd.h"

namespace nns {

template <class T, class Fwd, class Bwd>
Var<T> pointwise_op(const Var<T>& x, const char* name, Fwd fwd, Bwd bwd) {
  const int64_t n = x.numel();
  Tensor<T> out(x.shape());
  fwd(out.data(), x.value().data(), n);
  return make_result<T>(std::move(out), {x}, name, [bwd, n](Node<T>& node) {
    bwd(node.parents[0]->grad_buffer().data(), node.grad.data(), node.parents[0]->value.data(), node.value.data(), n);
  });
}

}  // namespace nns
