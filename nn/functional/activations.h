#pragma once
// relu, leaky_relu, tanh, sigmoid on any shape.
// `tanh_act` and `tanh` are the same op.
#include <cmath>

#include "core/kernels/activations.h"
#include "nn/functional/pointwise.h"

namespace nns {

using std::tanh;  // keeps unqualified tanh(float) inside nns meaning std::tanh

template <class T>
Var<T> relu(const Var<T>& x) {
  return pointwise_op(
      x, "relu", [](T* o, const T* i, int64_t n) { relu_forward(o, i, n); },
      [](T* di, const T* d, const T* i, const T*, int64_t n) { relu_backward(di, d, i, n); });
}

template <class T>
Var<T> leaky_relu(const Var<T>& x, double slope) {
  const T s = T(slope);
  return pointwise_op(
      x, "leaky_relu", [s](T* o, const T* i, int64_t n) { leaky_relu_forward(o, i, n, s); },
      [s](T* di, const T* d, const T* i, const T*, int64_t n) { leaky_relu_backward(di, d, i, n, s); });
}

template <class T>
Var<T> tanh_act(const Var<T>& x) {
  return pointwise_op(
      x, "tanh", [](T* o, const T* i, int64_t n) { tanh_forward(o, i, n); },
      [](T* di, const T* d, const T*, const T* o, int64_t n) { tanh_backward(di, d, o, n); });
}
template <class T>
Var<T> tanh(const Var<T>& x) {
  return tanh_act(x);
}

template <class T>
Var<T> sigmoid(const Var<T>& x) {
  return pointwise_op(
      x, "sigmoid", [](T* o, const T* i, int64_t n) { sigmoid_forward(o, i, n); },
      [](T* di, const T* d, const T*, const T* o, int64_t n) { sigmoid_backward(di, d, o, n); });
}

}  // namespace nns
