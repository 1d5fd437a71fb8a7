#pragma once
// Elementwise arithmetic on Vars: add/sub/mul/div with numpy/PyTorch broadcasting and
// the operators + - * / (Var op Var, Var op T, T op Var), unary -, and the pointwise
// math square, sqrt, exp, log (clamped, see core/kernels/unary.h), abs.
#include <cmath>
#include <type_traits>
#include <utility>

#include "core/kernels/binary.h"
#include "core/kernels/unary.h"
#include "nn/functional/pointwise.h"

namespace nns {

// The Var overloads below would hide the scalar functions from unqualified calls
// inside namespace nns; these keep `sqrt(2.0f)` there meaning std::sqrt.
using std::abs;
using std::exp;
using std::log;
using std::sqrt;

namespace detail {
template <class T, class Fwd, class Bwd>
Var<T> broadcast_op(const Var<T>& a, const Var<T>& b, const char* name, Fwd fwd, Bwd bwd) {
  BroadcastPlan plan = make_broadcast_plan(a.shape(), b.shape(), name);
  Tensor<T> out(plan.out);
  fwd(out.data(), a.value().data(), b.value().data(), plan);
  return make_result<T>(std::move(out), {a, b}, name, [bwd, plan](Node<T>& n) {
    bwd(wants_grad(n, 0) ? n.parents[0]->grad_buffer().data() : nullptr,
        wants_grad(n, 1) ? n.parents[1]->grad_buffer().data() : nullptr, n.grad.data(), n.parents[0]->value.data(),
        n.parents[1]->value.data(), plan);
  });
}
}  // namespace detail

template <class T>
Var<T> add(const Var<T>& a, const Var<T>& b) {
  return detail::broadcast_op(a, b, "add", add_forward<T>, add_backward<T>);
}
template <class T>
Var<T> sub(const Var<T>& a, const Var<T>& b) {
  return detail::broadcast_op(a, b, "sub", sub_forward<T>, sub_backward<T>);
}
template <class T>
Var<T> mul(const Var<T>& a, const Var<T>& b) {
  return detail::broadcast_op(a, b, "mul", mul_forward<T>, mul_backward<T>);
}
template <class T>
Var<T> div(const Var<T>& a, const Var<T>& b) {
  return detail::broadcast_op(a, b, "div", div_forward<T>, div_backward<T>);
}

// y = alpha * x + beta: the one op behind every Var-with-scalar operator.
template <class T>
Var<T> affine(const Var<T>& x, T alpha, T beta) {
  return pointwise_op(
      x, "affine", [=](T* o, const T* i, int64_t n) { affine_forward(o, i, n, alpha, beta); },
      [=](T* di, const T* d, const T*, const T*, int64_t n) { affine_backward(di, d, n, alpha); });
}

// y = s / x
template <class T>
Var<T> rdiv(T s, const Var<T>& x) {
  return pointwise_op(
      x, "rdiv", [=](T* o, const T* i, int64_t n) { rdiv_forward(o, i, n, s); },
      [=](T* di, const T* d, const T* i, const T*, int64_t n) { rdiv_backward(di, d, i, n, s); });
}

template <class T>
Var<T> neg(const Var<T>& x) {
  return affine(x, T(-1), T(0));
}

template <class T>
Var<T> square(const Var<T>& x) {
  return pointwise_op(
      x, "square", [](T* o, const T* i, int64_t n) { square_forward(o, i, n); },
      [](T* di, const T* d, const T* i, const T*, int64_t n) { square_backward(di, d, i, n); });
}
template <class T>
Var<T> sqrt(const Var<T>& x) {
  return pointwise_op(
      x, "sqrt", [](T* o, const T* i, int64_t n) { sqrt_forward(o, i, n); },
      [](T* di, const T* d, const T*, const T* o, int64_t n) { sqrt_backward(di, d, o, n); });
}
template <class T>
Var<T> exp(const Var<T>& x) {
  return pointwise_op(
      x, "exp", [](T* o, const T* i, int64_t n) { exp_forward(o, i, n); },
      [](T* di, const T* d, const T*, const T* o, int64_t n) { exp_backward(di, d, o, n); });
}
template <class T>
Var<T> log(const Var<T>& x) {
  return pointwise_op(
      x, "log", [](T* o, const T* i, int64_t n) { log_forward(o, i, n); },
      [](T* di, const T* d, const T* i, const T*, int64_t n) { log_backward(di, d, i, n); });
}
template <class T>
Var<T> abs(const Var<T>& x) {
  return pointwise_op(
      x, "abs", [](T* o, const T* i, int64_t n) { abs_forward(o, i, n); },
      [](T* di, const T* d, const T* i, const T*, int64_t n) { abs_backward(di, d, i, n); });
}

template <class T>
Var<T> operator+(const Var<T>& a, const Var<T>& b) {
  return add(a, b);
}
template <class T>
Var<T> operator-(const Var<T>& a, const Var<T>& b) {
  return sub(a, b);
}
template <class T>
Var<T> operator*(const Var<T>& a, const Var<T>& b) {
  return mul(a, b);
}
template <class T>
Var<T> operator/(const Var<T>& a, const Var<T>& b) {
  return div(a, b);
}
template <class T>
Var<T> operator-(const Var<T>& x) {
  return neg(x);
}

// Scalars: std::type_identity_t keeps T deduced from the Var alone, so `x * 2.0` works
// on a Var<float>.
template <class T>
Var<T> operator+(const Var<T>& x, std::type_identity_t<T> s) {
  return affine(x, T(1), s);
}
template <class T>
Var<T> operator+(std::type_identity_t<T> s, const Var<T>& x) {
  return affine(x, T(1), s);
}
template <class T>
Var<T> operator-(const Var<T>& x, std::type_identity_t<T> s) {
  return affine(x, T(1), T(-s));
}
template <class T>
Var<T> operator-(std::type_identity_t<T> s, const Var<T>& x) {
  return affine(x, T(-1), s);
}
template <class T>
Var<T> operator*(const Var<T>& x, std::type_identity_t<T> s) {
  return affine(x, s, T(0));
}
template <class T>
Var<T> operator*(std::type_identity_t<T> s, const Var<T>& x) {
  return affine(x, s, T(0));
}
template <class T>
Var<T> operator/(const Var<T>& x, std::type_identity_t<T> s) {
  return affine(x, T(1) / s, T(0));
}
template <class T>
Var<T> operator/(std::type_identity_t<T> s, const Var<T>& x) {
  return rdiv(s, x);
}

}  // namespace nns
