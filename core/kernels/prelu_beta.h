#pragma once
// NNAO's PReLU with a learned positive slope (Holden et al. 2016, eq. 1):
//   f(x) = beta * max(x, 0) + alpha * min(x, 0), alpha and beta per channel.
//   inp, out (N, C, S) with S = H*W (S = 1 for (N, C) activations); alpha, beta (C).
// Backward accumulates into dinp, dalpha, dbeta (any may be null). Parameter gradients
// are reduced per channel by one worker each, in a fixed order: deterministic.
#include <cstdint>

#include "core/kernels/map.h"

namespace nns {

template <class T>
void prelu_beta_forward(T* out, const T* inp, const T* alpha, const T* beta, int64_t N, int64_t C, int64_t S) {
  parallel_for(
      N * C,
      [&](int64_t r0, int64_t r1) {
        for (int64_t r = r0; r < r1; ++r) {
          const T a = alpha[r % C], b = beta[r % C];
          const T* x = inp + r * S;
          T* y = out + r * S;
          for (int64_t s = 0; s < S; ++s) y[s] = x[s] > 0 ? b * x[s] : a * x[s];
        }
      },
      S >= kElementwiseGrain ? 1 : kElementwiseGrain / S);
}

template <class T>
void prelu_beta_backward(T* dinp, T* dalpha, T* dbeta, const T* dout, const T* inp, const T* alpha, const T* beta,
                         int64_t N, int64_t C, int64_t S) {
  if (dinp)
    parallel_for(
        N * C,
        [&](int64_t r0, int64_t r1) {
          for (int64_t r = r0; r < r1; ++r) {
            const T a = alpha[r % C], b = beta[r % C];
            const T* x = inp + r * S;
            const T* g = dout + r * S;
            T* dx = dinp + r * S;
            for (int64_t s = 0; s < S; ++s) dx[s] += g[s] * (x[s] > 0 ? b : a);
          }
        },
        S >= kElementwiseGrain ? 1 : kElementwiseGrain / S);
  if (!dalpha && !dbeta) return;
  parallel_for(
      C,
      [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) {
          double sneg = 0, spos = 0;
          for (int64_t n = 0; n < N; ++n) {
            const T* x = inp + (n * C + c) * S;
            const T* g = dout + (n * C + c) * S;
            for (int64_t s = 0; s < S; ++s) {
              const double gx = double(g[s]) * double(x[s]);
              (x[s] > 0 ? spos : sneg) += gx;
            }
          }
          if (dalpha) dalpha[c] += T(sneg);
          if (dbeta) dbeta[c] += T(spos);
        }
      },
      N * S >= kElementwiseGrain ? 1 : kElementwiseGrain / (N * S + 1));
}

}  // namespace nns
