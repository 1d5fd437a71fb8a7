#pragma once
// Batch normalization as kernel pairs (Ioffe & Szegedy 2015, PyTorch semantics).
//   inp, out, dout, dinp (N, C, S) with S = H*W (S = 1 for BatchNorm1d's (N, C));
//   gamma, beta, dgamma, dbeta (C) or null (affine = false: gamma 1, beta 0);
//   mean, rstd (C): the statistics used, saved for the backward pass.
// Work is split over channels and each channel is reduced by one worker in a fixed
// order, so results do not depend on the thread count. A channel's passes (statistics,
// then output) run back to back while its data is still in cache; sums are in double.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "core/thread_pool.h"

namespace nns {

namespace detail {
// Channels per parallel task: enough elements that waking the pool pays off.
inline int64_t bn_channel_grain(int64_t N, int64_t S) {
  const int64_t per_channel = N * S > 0 ? N * S : 1;
  return per_channel >= (1 << 15) ? 1 : (1 << 15) / per_channel;
}

// sum of f(i) over [0, n) in 16 independent double lanes: one accumulator would chain
// every add on the previous one (4 cycles each) and keep the loop from vectorizing. The
// lanes combine in a fixed order, so the result is deterministic. (Two sums fused in
// one loop did not vectorize with GCC 12: each sum gets its own pass over data that is
// still in cache.)
template <class F>
inline double lane_sum(int64_t n, F f) {
  double acc[16] = {};
  int64_t i = 0;
  for (; i + 16 <= n; i += 16)
    for (int k = 0; k < 16; ++k) acc[k] += f(i + k);
  for (int k = 0; i < n; ++i, ++k) acc[k] += f(i);
  double s = 0;
  for (double a : acc) s += a;
  return s;
}

#if defined(__AVX512F__)
// One pass over n floats for two double sums, 4 vector chains each (a single chain is
// latency-bound). Lanes and chains combine in a fixed order: deterministic.
//   shifted: s1 = sum(x - k), s2 = sum((x - k)^2)
//   grad:    s1 = sum(g),     s2 = sum(g * (x - k))
template <bool kGrad>
inline void fused_sums(const float* g, const float* x, int64_t n, double k, double& s1,
                       double& s2) {
  auto halves = [](__m512 v, __m512d& lo, __m512d& hi) {
    lo = _mm512_cvtps_pd(_mm512_castps512_ps256(v));
    hi = _mm512_cvtps_pd(_mm256_castsi256_ps(_mm512_extracti64x4_epi64(_mm512_castps_si512(v), 1)));
  };
  const __m512d kv = _mm512_set1_pd(k);
  __m512d a[4], q[4];
  for (int c = 0; c < 4; ++c) a[c] = q[c] = _mm512_setzero_pd();
  int64_t i = 0;
  for (; i + 32 <= n; i += 32)
    for (int h = 0; h < 2; ++h) {
      __m512d xl, xh;
      halves(_mm512_loadu_ps(x + i + 16 * h), xl, xh);
      xl = _mm512_sub_pd(xl, kv), xh = _mm512_sub_pd(xh, kv);
      if constexpr (kGrad) {
        __m512d gl, gh;
        halves(_mm512_loadu_ps(g + i + 16 * h), gl, gh);
        a[2 * h] = _mm512_add_pd(a[2 * h], gl), a[2 * h + 1] = _mm512_add_pd(a[2 * h + 1], gh);
        q[2 * h] = _mm512_fmadd_pd(gl, xl, q[2 * h]);
        q[2 * h + 1] = _mm512_fmadd_pd(gh, xh, q[2 * h + 1]);
      } else {
        a[2 * h] = _mm512_add_pd(a[2 * h], xl), a[2 * h + 1] = _mm512_add_pd(a[2 * h + 1], xh);
        q[2 * h] = _mm512_fmadd_pd(xl, xl, q[2 * h]);
        q[2 * h + 1] = _mm512_fmadd_pd(xh, xh, q[2 * h + 1]);
      }
    }
  double t1 = _mm512_reduce_add_pd(_mm512_add_pd(_mm512_add_pd(a[0], a[1]), _mm512_add_pd(a[2], a[3])));
  double t2 = _mm512_reduce_add_pd(_mm512_add_pd(_mm512_add_pd(q[0], q[1]), _mm512_add_pd(q[2], q[3])));
  for (; i < n; ++i) {
    const double d = double(x[i]) - k;
    const double v = kGrad ? double(g[i]) : d;
    t1 += v, t2 += v * d;
  }
  s1 += t1, s2 += t2;
}
#endif
}  // namespace detail

// Train mode: normalizes with the batch mean and biased variance; writes them to mean
// and var (C) and 1/sqrt(var + eps) to rstd (C).
template <class T>
void batch_norm_forward_train(T* out, T* mean, T* var, T* rstd, const T* inp, const T* gamma,
                              const T* beta, int64_t N, int64_t C, int64_t S, double eps) {
  const double M = double(N * S);
  parallel_for(
      C,
      [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) {
          double mu, v;
#if defined(__AVX512F__)
          if constexpr (std::is_same_v<T, float>) {
            // One pass in double around a sample of the channel: sum(d^2)/M - (sum(d)/M)^2
            // loses only ~(1 + (mean - k)^2 / var) double epsilons, no float cancellation.
            const double k = double(inp[c * S]);
            double s1 = 0, s2 = 0;
            for (int64_t n = 0; n < N; ++n)
              detail::fused_sums<false>(nullptr, inp + (n * C + c) * S, S, k, s1, s2);
            const double d = s1 / M;
            mu = k + d;
            v = std::max(0.0, s2 / M - d * d);
          } else
#endif
          {
            double s = 0;
            for (int64_t n = 0; n < N; ++n) {
              const T* x = inp + (n * C + c) * S;
              s += detail::lane_sum(S, [x](int64_t i) { return double(x[i]); });
            }
            mu = s / M;
            double q = 0;  // second pass around the mean: no cancellation
            for (int64_t n = 0; n < N; ++n) {
              const T* x = inp + (n * C + c) * S;
              q += detail::lane_sum(S, [x, mu](int64_t i) {
                const double d = double(x[i]) - mu;
                return d * d;
              });
            }
            v = q / M;
          }
          const double r = 1.0 / std::sqrt(v + eps);
          mean[c] = T(mu);
          var[c] = T(v);
          rstd[c] = T(r);
          // (x - mean) first: at variance 0 (batch 1, 1x1) the output is exactly beta.
          const T a = T((gamma ? double(gamma[c]) : 1.0) * r), m = T(mu);
          const T b = beta ? beta[c] : T(0);
          for (int64_t n = 0; n < N; ++n) {
            const T* x = inp + (n * C + c) * S;
            T* y = out + (n * C + c) * S;
            for (int64_t i = 0; i < S; ++i) y[i] = (x[i] - m) * a + b;
          }
        }
      },
      detail::bn_channel_grain(N, S));
}

// Eval mode: normalizes with the given statistics (the running estimates); writes the
// rstd it used (C) for the backward pass.
template <class T>
void batch_norm_forward_eval(T* out, T* rstd, const T* inp, const T* gamma, const T* beta,
                             const T* mean, const T* var, int64_t N, int64_t C, int64_t S,
                             double eps) {
  parallel_for(
      C,
      [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) {
          const double r = 1.0 / std::sqrt(double(var[c]) + eps);
          rstd[c] = T(r);
          const T a = T((gamma ? double(gamma[c]) : 1.0) * r), m = mean[c];
          const T b = beta ? beta[c] : T(0);
          for (int64_t n = 0; n < N; ++n) {
            const T* x = inp + (n * C + c) * S;
            T* y = out + (n * C + c) * S;
            for (int64_t i = 0; i < S; ++i) y[i] = (x[i] - m) * a + b;
          }
        }
      },
      detail::bn_channel_grain(N, S));
}

// Accumulates into dinp, dgamma, dbeta (any may be null). With xhat = (x - mean) * rstd:
//   dbeta += sum(g), dgamma += sum(g * xhat), and
//   train: dinp += gamma * rstd / M * (M * g - sum(g) - xhat * sum(g * xhat))
//   eval:  dinp += gamma * rstd * g  (the statistics are constants)
template <class T>
void batch_norm_backward(T* dinp, T* dgamma, T* dbeta, const T* dout, const T* inp,
                         const T* gamma, const T* mean, const T* rstd, int64_t N, int64_t C,
                         int64_t S, bool training) {
  const double M = double(N * S);
  parallel_for(
      C,
      [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) {
          const double mu = double(mean[c]), r = double(rstd[c]);
          double sg = 0, sgx = 0;  // sum(g), sum(g * (x - mean))
          for (int64_t n = 0; n < N; ++n) {
            const T* x = inp + (n * C + c) * S;
            const T* g = dout + (n * C + c) * S;
#if defined(__AVX512F__)
            if constexpr (std::is_same_v<T, float>) {
              detail::fused_sums<true>(g, x, S, mu, sg, sgx);
              continue;
            }
#endif
            sg += detail::lane_sum(S, [g](int64_t i) { return double(g[i]); });
            sgx += detail::lane_sum(S, [g, x, mu](int64_t i) { return double(g[i]) * (double(x[i]) - mu); });
          }
          const double sgxhat = sgx * r;
          if (dbeta) dbeta[c] += T(sg);
          if (dgamma) dgamma[c] += T(sgxhat);
          if (!dinp) continue;
          const double gm = gamma ? double(gamma[c]) : 1.0;
          // dinp += k * g + k2 * (x - mean) + k3: one fused step per element.
          const T k = T(gm * r), mu_t = T(mu);
          const T k2 = training ? T(-gm * r * r * r * sgx / M) : T(0);
          const T k3 = training ? T(-gm * r * sg / M) : T(0);
          for (int64_t n = 0; n < N; ++n) {
            const T* x = inp + (n * C + c) * S;
            const T* g = dout + (n * C + c) * S;
            T* dx = dinp + (n * C + c) * S;
            for (int64_t i = 0; i < S; ++i) dx[i] += k * g[i] + k2 * (x[i] - mu_t) + k3;
          }
        }
      },
      detail::bn_channel_grain(N, S));
}

}  // namespace nns
