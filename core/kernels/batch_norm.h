#pragma once
// Batch normalization as kernel pairs (Ioffe & Szegedy 2015, PyTorch semantics).
//   inp, out, dout, dinp (N, C, S) with S = H*W (S = 1 for BatchNorm1d's (N, C));
//   gamma, beta, dgamma, dbeta (C) or null (affine = false: gamma 1, beta 0);
//   mean, rstd (C): the statistics used, saved for the backward pass.
// Work is split over channels and each channel is reduced by one worker in a fixed
// order, so results do not depend on the thread count. Sums are in double. A channel's
// output follows its statistics while its data is still in cache; with AVX-512 (float)
// it runs in one loop with the next channel's statistics (detail::slice_pass).
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
// Two double sums over float data, 32 elements a step in 4 vector chains each (a single
// chain is latency-bound). Steps, chains and the tail combine in a fixed order:
// deterministic.
//   kGrad = false: s1 = sum(x - k), s2 = sum((x - k)^2)
//   kGrad = true:  s1 = sum(g),     s2 = sum(g * (x - k))
template <bool kGrad>
struct PairSums {
  __m512d a[4], q[4], kv;
  double k;
  explicit PairSums(double k_) : kv(_mm512_set1_pd(k_)), k(k_) {
    for (int c = 0; c < 4; ++c) a[c] = q[c] = _mm512_setzero_pd();
  }
  // 8 floats as doubles: a 256-bit load folded into the conversion (no lane extract).
  static __m512d wide(const float* p) { return _mm512_cvtps_pd(_mm256_loadu_ps(p)); }
  void step(const float* g, const float* x) {
    for (int c = 0; c < 4; ++c) {
      const __m512d d = _mm512_sub_pd(wide(x + 8 * c), kv);
      const __m512d v = kGrad ? wide(g + 8 * c) : d;
      a[c] = _mm512_add_pd(a[c], v);
      q[c] = _mm512_fmadd_pd(v, d, q[c]);
    }
  }
  // Adds the steps' sums and those of the n (< 32) elements at g, x to s1, s2.
  void finish(const float* g, const float* x, int64_t n, double& s1, double& s2) const {
    double t1 = _mm512_reduce_add_pd(_mm512_add_pd(_mm512_add_pd(a[0], a[1]), _mm512_add_pd(a[2], a[3])));
    double t2 = _mm512_reduce_add_pd(_mm512_add_pd(_mm512_add_pd(q[0], q[1]), _mm512_add_pd(q[2], q[3])));
    for (int64_t i = 0; i < n; ++i) {
      const double d = double(x[i]) - k;
      const double v = kGrad ? double(g[i]) : d;
      t1 += v, t2 = std::fma(v, d, t2);
    }
    s1 += t1, s2 += t2;
  }
};

// One slice of S floats of a channel's output (kOut: y from x, g) in one loop with the
// sums of a slice of the next channel (kSums: gn, xn). Once a channel outgrows L1 (48 KB)
// the time follows the L1 line fills: a memcpy fills 2 a line, statistics then output 3
// (the input is read twice). Fused, the double sums hide behind the fills, and the
// output walks backwards, so the end of its input, read last, still hits L1. At 64 KB a
// channel (1 thread) the forward went from ~1.85x to ~1.4x of a memcpy, the backward
// from ~1.3x to ~1.15x of two. An element's output is the same masked FMA sequence on
// every path, so it never depends on where a task boundary fell.
//   forward:  y = (x - m) * a + b
//   backward: y += ka * g + kb * (x - m) + kc   (y = dinp)
template <bool kBackward, bool kOut, bool kSums>
inline void slice_pass(float* y, const float* g, const float* x, float m, float ka, float kb, float kc, const float* gn,
                       const float* xn, int64_t S, PairSums<kBackward>& sums) {
  const __m512 mv = _mm512_set1_ps(m), av = _mm512_set1_ps(ka), bv = _mm512_set1_ps(kb), cv = _mm512_set1_ps(kc);
  auto out16 = [&](int64_t i, __mmask16 mask) {  // masked: the same code for the tail
    const __m512 d = _mm512_sub_ps(_mm512_maskz_loadu_ps(mask, x + i), mv);
    __m512 r;
    if constexpr (kBackward) {
      const __m512 gv = _mm512_maskz_loadu_ps(mask, g + i);
      r = _mm512_add_ps(_mm512_maskz_loadu_ps(mask, y + i), _mm512_fmadd_ps(av, gv, _mm512_fmadd_ps(bv, d, cv)));
    } else {
      r = _mm512_fmadd_ps(d, av, bv);
    }
    _mm512_mask_storeu_ps(y + i, mask, r);
  };
  const int64_t full = S / 32 * 32;
  if constexpr (kOut)
    for (int64_t j = full; j < S; j += 16) out16(j, __mmask16(S - j >= 16 ? 0xffff : (1u << (S - j)) - 1));
  for (int64_t t = 0; t < full; t += 32) {
    if constexpr (kSums) sums.step(gn + t, xn + t);
    if constexpr (kOut) out16(full - 16 - t, 0xffff), out16(full - 32 - t, 0xffff);
  }
  (void)gn, (void)xn;
}

// Mean, biased variance and 1/sqrt(var + eps) of a channel from its shifted sums.
inline void shifted_stats(double s1, double s2, double k, double M, double eps, double& mu, double& v, double& r) {
  // sum(d^2)/M - (sum(d)/M)^2 with d = x - k, k a sample of the channel: in double this
  // loses only ~(1 + (mean - k)^2 / var) double epsilons, no float cancellation.
  const double d = s1 / M;
  mu = k + d;
  v = std::max(0.0, s2 / M - d * d);
  r = 1.0 / std::sqrt(v + eps);
}
#endif
}  // namespace detail

// Train mode: normalizes with the batch mean and biased variance; writes them to mean
// and var (C) and 1/sqrt(var + eps) to rstd (C).
template <class T>
void batch_norm_forward_train(T* out, T* mean, T* var, T* rstd, const T* inp, const T* gamma, const T* beta, int64_t N,
                              int64_t C, int64_t S, double eps) {
  const double M = double(N * S);
#if defined(__AVX512F__)
  if constexpr (std::is_same_v<T, float>) {
    // Channel c's output runs in one loop with channel c + 1's statistics (slice_pass).
    parallel_for(
        C,
        [&](int64_t c0, int64_t c1) {
          using Sums = detail::PairSums<false>;
          auto sums_of = [&](int64_t c, double& s1, double& s2) {  // alone: a task's first channel
            for (int64_t n = 0; n < N; ++n) {
              const float* x = inp + (n * C + c) * S;
              Sums p{double(inp[c * S])};  // braces: with parentheses clang reads a function declaration
              detail::slice_pass<false, false, true>(nullptr, nullptr, nullptr, 0, 0, 0, 0, nullptr, x, S, p);
              p.finish(nullptr, x + S / 32 * 32, S % 32, s1, s2);
            }
          };
          double s1 = 0, s2 = 0;
          sums_of(c0, s1, s2);
          for (int64_t c = c0; c < c1; ++c) {
            double mu, v, r;
            detail::shifted_stats(s1, s2, double(inp[c * S]), M, eps, mu, v, r);
            mean[c] = float(mu), var[c] = float(v), rstd[c] = float(r);
            // (x - mean) first: at variance 0 (batch 1, 1x1) the output is exactly beta.
            const float a = float((gamma ? double(gamma[c]) : 1.0) * r), m = float(mu);
            const float b = beta ? beta[c] : 0.0f;
            const bool next = c + 1 < c1;
            const double k = next ? double(inp[(c + 1) * S]) : 0.0;
            s1 = s2 = 0;
            for (int64_t n = 0; n < N; ++n) {  // output slices last read first
              const float* x = inp + ((N - 1 - n) * C + c) * S;
              float* y = out + ((N - 1 - n) * C + c) * S;
              Sums p(k);
              if (next) {
                const float* xn = inp + (n * C + c + 1) * S;
                detail::slice_pass<false, true, true>(y, nullptr, x, m, a, b, 0, nullptr, xn, S, p);
                p.finish(nullptr, xn + S / 32 * 32, S % 32, s1, s2);
              } else {
                detail::slice_pass<false, true, false>(y, nullptr, x, m, a, b, 0, nullptr, nullptr, S, p);
              }
            }
          }
        },
        detail::bn_channel_grain(N, S));
    return;
  }
#endif
  parallel_for(
      C,
      [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) {
          double s = 0;
          for (int64_t n = 0; n < N; ++n) {
            const T* x = inp + (n * C + c) * S;
            s += detail::lane_sum(S, [x](int64_t i) { return double(x[i]); });
          }
          const double mu = s / M;
          double q = 0;  // second pass around the mean: no cancellation
          for (int64_t n = 0; n < N; ++n) {
            const T* x = inp + (n * C + c) * S;
            q += detail::lane_sum(S, [x, mu](int64_t i) {
              const double d = double(x[i]) - mu;
              return d * d;
            });
          }
          const double v = q / M;
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
void batch_norm_forward_eval(T* out, T* rstd, const T* inp, const T* gamma, const T* beta, const T* mean, const T* var,
                             int64_t N, int64_t C, int64_t S, double eps) {
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
void batch_norm_backward(T* dinp, T* dgamma, T* dbeta, const T* dout, const T* inp, const T* gamma, const T* mean,
                         const T* rstd, int64_t N, int64_t C, int64_t S, bool training) {
  const double M = double(N * S);
#if defined(__AVX512F__)
  if constexpr (std::is_same_v<T, float>) {
    // Channel c's input gradient runs in one loop with channel c + 1's sums (slice_pass).
    parallel_for(
        C,
        [&](int64_t c0, int64_t c1) {
          using Sums = detail::PairSums<true>;
          auto sums_of = [&](int64_t c, double& sg, double& sgx) {  // alone
            for (int64_t n = 0; n < N; ++n) {
              const float* x = inp + (n * C + c) * S;
              const float* g = dout + (n * C + c) * S;
              Sums p{double(mean[c])};
              detail::slice_pass<true, false, true>(nullptr, nullptr, nullptr, 0, 0, 0, 0, g, x, S, p);
              p.finish(g + S / 32 * 32, x + S / 32 * 32, S % 32, sg, sgx);
            }
          };
          double sg = 0, sgx = 0;  // sum(g), sum(g * (x - mean)) of channel c
          sums_of(c0, sg, sgx);
          for (int64_t c = c0; c < c1; ++c) {
            const double mu = double(mean[c]), r = double(rstd[c]);
            if (dbeta) dbeta[c] += float(sg);
            if (dgamma) dgamma[c] += float(sgx * r);
            const bool next = c + 1 < c1;
            if (!dinp) {
              sg = sgx = 0;
              if (next) sums_of(c + 1, sg, sgx);
              continue;
            }
            const double gm = gamma ? double(gamma[c]) : 1.0;
            const float k = float(gm * r), mu_t = float(mu);
            const float k2 = training ? float(-gm * r * r * r * sgx / M) : 0.0f;
            const float k3 = training ? float(-gm * r * sg / M) : 0.0f;
            const double kn = next ? double(mean[c + 1]) : 0.0;
            sg = sgx = 0;
            for (int64_t n = 0; n < N; ++n) {  // output slices last read first
              const int64_t o = ((N - 1 - n) * C + c) * S, nx = (n * C + c + 1) * S;
              const float *x = inp + o, *g = dout + o;
              float* dx = dinp + o;
              Sums p(kn);
              if (next) {
                detail::slice_pass<true, true, true>(dx, g, x, mu_t, k, k2, k3, dout + nx, inp + nx, S, p);
                p.finish(dout + nx + S / 32 * 32, inp + nx + S / 32 * 32, S % 32, sg, sgx);
              } else {
                detail::slice_pass<true, true, false>(dx, g, x, mu_t, k, k2, k3, nullptr, nullptr, S, p);
              }
            }
          }
        },
        detail::bn_channel_grain(N, S));
    return;
  }
#endif
  parallel_for(
      C,
      [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) {
          const double mu = double(mean[c]), r = double(rstd[c]);
          double sg = 0, sgx = 0;  // sum(g), sum(g * (x - mean))
          for (int64_t n = 0; n < N; ++n) {
            const T* x = inp + (n * C + c) * S;
            const T* g = dout + (n * C + c) * S;
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
