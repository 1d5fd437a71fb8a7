#pragma once
// Pointwise math as kernel pairs:  inp, out, dout, dinp all (n).
// Backward accumulates into dinp. `out` is the forward result where the derivative is
// cheaper from it (exp, sqrt).
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/kernels/map.h"

namespace nns {

// out = alpha * inp + beta: covers x + s, x - s, s - x, x * s, x / s and -x.
template <class T>
void affine_forward(T* out, const T* inp, int64_t n, T alpha, T beta) {
  map_unary(out, inp, n, [=](T x) { return alpha * x + beta; });
}
template <class T>
void affine_backward(T* dinp, const T* dout, int64_t n, T alpha) {
  map_unary_grad(dinp, dout, dout, dout, n, [=](T, T) { return alpha; });
}

// out = s / inp
template <class T>
void rdiv_forward(T* out, const T* inp, int64_t n, T s) {
  map_unary(out, inp, n, [=](T x) { return s / x; });
}
template <class T>
void rdiv_backward(T* dinp, const T* dout, const T* inp, int64_t n, T s) {
  map_unary_grad(dinp, dout, inp, inp, n, [=](T x, T) { return -s / (x * x); });
}

template <class T>
void square_forward(T* out, const T* inp, int64_t n) {
  map_unary(out, inp, n, [](T x) { return x * x; });
}
template <class T>
void square_backward(T* dinp, const T* dout, const T* inp, int64_t n) {
  map_unary_grad(dinp, dout, inp, inp, n, [](T x, T) { return 2 * x; });
}

// sqrt's derivative is infinite at 0; we return 0 there instead of inf/NaN.
template <class T>
void sqrt_forward(T* out, const T* inp, int64_t n) {
  map_unary(out, inp, n, [](T x) { return std::sqrt(x); });
}
template <class T>
void sqrt_backward(T* dinp, const T* dout, const T* out, int64_t n) {
  map_unary_grad(dinp, dout, out, out, n, [](T y, T) { return y > 0 ? T(0.5) / y : T(0); });
}

template <class T>
void exp_forward(T* out, const T* inp, int64_t n) {
  map_unary(out, inp, n, [](T x) { return std::exp(x); });
}
template <class T>
void exp_backward(T* dinp, const T* dout, const T* out, int64_t n) {
  map_unary_grad(dinp, dout, out, out, n, [](T y, T) { return y; });
}

// log clamps its input at the smallest normal number, so log(0) is a large negative
// finite value (-87 in float, -708 in double) with zero gradient, never -inf or NaN.
template <class T>
void log_forward(T* out, const T* inp, int64_t n) {
  constexpr T tiny = std::numeric_limits<T>::min();
  map_unary(out, inp, n, [](T x) { return std::log(x < tiny ? tiny : x); });
}
template <class T>
void log_backward(T* dinp, const T* dout, const T* inp, int64_t n) {
  constexpr T tiny = std::numeric_limits<T>::min();
  map_unary_grad(dinp, dout, inp, inp, n, [](T x, T) { return x < tiny ? T(0) : T(1) / x; });
}

// |x|'s subgradient at 0 is taken as 0 (PyTorch's sign(0) = 0).
template <class T>
void abs_forward(T* out, const T* inp, int64_t n) {
  map_unary(out, inp, n, [](T x) { return std::abs(x); });
}
template <class T>
void abs_backward(T* dinp, const T* dout, const T* inp, int64_t n) {
  map_unary_grad(dinp, dout, inp, inp, n, [](T x, T) { return T((x > 0) - (x < 0)); });
}

}  // namespace nns
