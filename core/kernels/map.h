#pragma once
// Parallel elementwise loops shared by the unary kernels (activations, exp, log, ...).
// Elementwise work may split any way and stay bitwise deterministic (each output is
// computed the same way whatever the split); small tensors run inline because waking
// the pool costs more than the loop.
#include <cstdint>

#include "core/thread_pool.h"

namespace nns {

// Below this many elements per worker, a loop runs on the calling thread.
inline constexpr int64_t kElementwiseGrain = 1 << 15;

// out[i] = f(x[i])          out, x (n)
template <class T, class F>
void map_unary(T* out, const T* x, int64_t n, F f) {
  parallel_for(
      n,
      [=](int64_t b, int64_t e) {
        // Local copies of the functor and pointers: a float written through `out` could
        // alias a float captured in `f`, and GCC then falls back to a scalar loop.
        const F fn = f;
        T* o = out;
        const T* in = x;
        for (int64_t i = b; i < e; ++i) o[i] = fn(in[i]);
      },
      kElementwiseGrain, 16);
}

// dx[i] += dout[i] * df(x[i], y[i])   where y = f(x) is the forward output
template <class T, class DF>
void map_unary_grad(T* dx, const T* dout, const T* x, const T* y, int64_t n, DF df) {
  parallel_for(
      n,
      [=](int64_t b, int64_t e) {
        const DF fn = df;  // see map_unary
        T* d = dx;
        const T *g = dout, *in = x, *res = y;
        for (int64_t i = b; i < e; ++i) d[i] += g[i] * fn(in[i], res[i]);
      },
      kElementwiseGrain, 16);
}

}  // namespace nns
