#pragma once
// Activation functions as kernel pairs:  inp, out, dout, dinp all (n).
// Backward accumulates into dinp.
#include <cmath>
#include <cstdint>

#include "core/kernels/map.h"

namespace nns {

template <class T>
void relu_forward(T* out, const T* inp, int64_t n) {
  map_unary(out, inp, n, [](T x) { return x > 0 ? x : T(0); });
}
template <class T>
void relu_backward(T* dinp, const T* dout, const T* inp, int64_t n) {
  map_unary_grad(dinp, dout, inp, inp, n, [](T x, T) { return x > 0 ? T(1) : T(0); });
}

template <class T>
void leaky_relu_forward(T* out, const T* inp, int64_t n, T slope) {
  map_unary(out, inp, n, [=](T x) { return x > 0 ? x : slope * x; });
}
template <class T>
void leaky_relu_backward(T* dinp, const T* dout, const T* inp, int64_t n, T slope) {
  map_unary_grad(dinp, dout, inp, inp, n, [=](T x, T) { return x > 0 ? T(1) : slope; });
}

// Derivatives from the output: tanh' = 1 - y^2, sigmoid' = y (1 - y).
template <class T>
void tanh_forward(T* out, const T* inp, int64_t n) {
  map_unary(out, inp, n, [](T x) { return std::tanh(x); });
}
template <class T>
void tanh_backward(T* dinp, const T* dout, const T* out, int64_t n) {
  map_unary_grad(dinp, dout, out, out, n, [](T y, T) { return T(1) - y * y; });
}

// Two branches so exp never overflows: for x < 0, e^x / (1 + e^x).
template <class T>
void sigmoid_forward(T* out, const T* inp, int64_t n) {
  map_unary(out, inp, n, [](T x) {
    if (x >= 0) return T(1) / (T(1) + std::exp(-x));
    T e = std::exp(x);
    return e / (T(1) + e);
  });
}
template <class T>
void sigmoid_backward(T* dinp, const T* dout, const T* out, int64_t n) {
  map_unary_grad(dinp, dout, out, out, n, [](T y, T) { return y * (T(1) - y); });
}

}  // namespace nns
