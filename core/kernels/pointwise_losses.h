#pragma once
// Mean-reduced pointwise losses as kernel pairs:  pred, target, dpred, dtarget all (n).
// Forward returns the mean loss (summed in double over fixed chunks: deterministic).
// Backward accumulates g * d(mean loss)/d(pred) into dpred and the same for dtarget
// (either may be null); g is the gradient of the scalar result.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/kernels/map.h"
#include "core/kernels/reduce.h"

namespace nns {

namespace detail {
// dpred[i] += dp(p, t), dtarget[i] += dt(p, t)
template <class T, class DP, class DT>
void loss_grad(T* dpred, T* dtarget, const T* pred, const T* target, int64_t n, DP dp, DT dt) {
  parallel_for(
      n,
      [=](int64_t b, int64_t e) {
        // Local copies: a float captured in dp/dt could alias the gradient buffers, and
        // GCC then keeps the loop scalar.
        const DP fp = dp;
        const DT ft = dt;
        T *gp = dpred, *gt = dtarget;
        const T *p = pred, *t = target;
        if (gp)
          for (int64_t i = b; i < e; ++i) gp[i] += fp(p[i], t[i]);
        if (gt)
          for (int64_t i = b; i < e; ++i) gt[i] += ft(p[i], t[i]);
      },
      kElementwiseGrain, 16);
}
}  // namespace detail

// mean((p - t)^2)
template <class T>
double mse_loss_forward(const T* pred, const T* target, int64_t n) {
  return chunked_sum(n,
                     [=](int64_t i) {
                       const double d = double(pred[i]) - double(target[i]);
                       return d * d;
                     }) /
         double(n);
}
template <class T>
void mse_loss_backward(T* dpred, T* dtarget, T g, const T* pred, const T* target, int64_t n) {
  const T k = T(2) * g / T(n);
  detail::loss_grad(
      dpred, dtarget, pred, target, n, [=](T p, T t) { return k * (p - t); }, [=](T p, T t) { return k * (t - p); });
}

// mean(|p - t|); subgradient 0 where p == t (PyTorch's sign)
template <class T>
double l1_loss_forward(const T* pred, const T* target, int64_t n) {
  return chunked_sum(n, [=](int64_t i) { return std::abs(double(pred[i]) - double(target[i])); }) / double(n);
}
template <class T>
void l1_loss_backward(T* dpred, T* dtarget, T g, const T* pred, const T* target, int64_t n) {
  const T k = g / T(n);
  detail::loss_grad(
      dpred, dtarget, pred, target, n, [=](T p, T t) { return k * T((p > t) - (p < t)); },
      [=](T p, T t) { return k * T((t > p) - (t < p)); });
}

// Binary cross-entropy on logits x in the stable form
//   max(x, 0) - x t + log(1 + exp(-|x|))
// (never exponentiates a positive number); d/dx = sigmoid(x) - t, d/dt = -x.
template <class T>
double bce_with_logits_loss_forward(const T* logits, const T* target, int64_t n) {
  return chunked_sum(n,
                     [=](int64_t i) {
                       const double x = double(logits[i]), t = double(target[i]);
                       return std::max(x, 0.0) - x * t + std::log1p(std::exp(-std::abs(x)));
                     }) /
         double(n);
}
template <class T>
void bce_with_logits_loss_backward(T* dlogits, T* dtarget, T g, const T* logits, const T* target, int64_t n) {
  const T k = g / T(n);
  detail::loss_grad(
      dlogits, dtarget, logits, target, n,
      [=](T x, T t) {
        const T s = x >= 0 ? T(1) / (T(1) + std::exp(-x)) : std::exp(x) / (T(1) + std::exp(x));
        return k * (s - t);
      },
      [=](T x, T) { return -k * x; });
}

// Binary cross-entropy on probabilities: -(t log p + (1 - t) log(1 - p)) with each log
// clamped at -100 as PyTorch does, so p = 0 or 1 gives a finite loss. The gradient
// follows PyTorch too: (p - t) / max(p (1 - p), 1e-12) for p, log(1-p) - log(p) for t.
template <class T>
double bce_loss_forward(const T* prob, const T* target, int64_t n) {
  return chunked_sum(n,
                     [=](int64_t i) {
                       const double p = double(prob[i]), t = double(target[i]);
                       const double lp = std::max(std::log(p), -100.0), lq = std::max(std::log(1 - p), -100.0);
                       return -(t * lp + (1 - t) * lq);
                     }) /
         double(n);
}
template <class T>
void bce_loss_backward(T* dprob, T* dtarget, T g, const T* prob, const T* target, int64_t n) {
  const T k = g / T(n);
  detail::loss_grad(
      dprob, dtarget, prob, target, n, [=](T p, T t) { return k * (p - t) / std::max(p * (T(1) - p), T(1e-12)); },
      [=](T p, T) {
        const T lp = std::max(std::log(p), T(-100)), lq = std::max(std::log(T(1) - p), T(-100));
        return k * (lq - lp);
      });
}

}  // namespace nns
