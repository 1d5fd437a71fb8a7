#pragma once
// dropout(x, p, training, rng): inverted dropout (Srivastava et al. 2014; NNAO uses it
// on its input layer). Identity when !training or p == 0. Each call in training mode
// takes one 64-bit draw from `rng` as the mask's seed, so a run is reproducible from
// the generator's state.
#include <stdexcept>
#include <string>

#include "core/autograd.h"
#include "core/kernels/dropout.h"
#include "core/rng.h"

namespace nns {

template <class T>
Var<T> dropout(const Var<T>& x, double p, bool training, Rng& rng) {
  if (!(p >= 0 && p <= 1)) throw std::invalid_argument("dropout: p must be in [0, 1], got " + std::to_string(p));
  if (!training || p == 0) return x;
  const int64_t n = x.numel();
  Tensor<T> out(x.shape()), mask(x.shape());
  dropout_forward(out.data(), mask.data(), x.value().data(), n, p, rng.next_u64());
  return make_result<T>(std::move(out), {x}, "dropout", [mask, n](Node<T>& node) {
    dropout_backward(node.parents[0]->grad_buffer().data(), node.grad.data(), mask.data(), n);
  });
}

}  // namespace nns
