// The float batch-norm kernels (AVX-512: a channel's output fused with the next
// channel's sums, walked backwards) against the double kernels, which the gradient
// checks in tests/nn/test_batch_norm.cpp validate; and bitwise equal with 1 and 2
// threads where the task boundaries fall on different channels.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "core/kernels/batch_norm.h"
#include "core/rng.h"
#include "core/thread_pool.h"

using namespace nns;

namespace {

struct Shape3 {
  int64_t N, C, S;
};

std::vector<double> random_values(int64_t n, uint64_t seed, double mean, double stddev) {
  Rng rng(seed);
  std::vector<double> v(static_cast<size_t>(n));
  for (auto& x : v) x = rng.normal(mean, stddev);
  return v;
}

template <class T>
std::vector<T> as(const std::vector<double>& v) {
  return std::vector<T>(v.begin(), v.end());
}

// Forward (train) then backward (train) of one precision; returns y, mean, var, rstd,
// dinp, dgamma, dbeta concatenated. dinp, dgamma and dbeta start non-zero: the kernel
// accumulates.
template <class T>
std::vector<double> run(const Shape3& s, const std::vector<double>& x, const std::vector<double>& g,
                        const std::vector<double>& gamma, const std::vector<double>& beta) {
  const int64_t E = s.N * s.C * s.S;
  std::vector<T> xt = as<T>(x), gt = as<T>(g), gm = as<T>(gamma), bt = as<T>(beta);
  std::vector<T> y(static_cast<size_t>(E)), mean(static_cast<size_t>(s.C)), var(mean), rstd(mean);
  std::vector<T> dx(size_t(E), T(0.25)), dgm(size_t(s.C), T(1)), dbt(size_t(s.C), T(-1));
  batch_norm_forward_train(y.data(), mean.data(), var.data(), rstd.data(), xt.data(), gm.data(), bt.data(), s.N, s.C,
                           s.S, 1e-5);
  batch_norm_backward(dx.data(), dgm.data(), dbt.data(), gt.data(), xt.data(), gm.data(), mean.data(), rstd.data(), s.N,
                      s.C, s.S, true);
  std::vector<double> all;
  for (const auto* v : {&y, &mean, &var, &rstd, &dx, &dgm, &dbt}) all.insert(all.end(), v->begin(), v->end());
  return all;
}

struct Inputs {
  std::vector<double> x, g, gamma, beta;
  explicit Inputs(const Shape3& s)
      : x(random_values(s.N * s.C * s.S, 11, 3.0, 0.5)),  // an offset mean: float cancellation shows
        g(random_values(s.N * s.C * s.S, 12, 0.0, 1.0)),
        gamma(random_values(s.C, 13, 1.0, 0.3)),
        beta(random_values(s.C, 14, 0.0, 1.0)) {}
};

}  // namespace

TEST(BatchNormKernel, FloatAgreesWithDouble) {
  // Tails of every length class (S % 32 = 0, < 16, >= 16), a batch, single elements, and
  // the 64 KB channels of the pix2pix U-Net's first level.
  for (Shape3 s : {Shape3{1, 3, 1}, {3, 5, 37}, {2, 4, 7}, {2, 6, 64}, {1, 4, 16384}, {4, 3, 1000}}) {
    SCOPED_TRACE("N,C,S = " + std::to_string(s.N) + "," + std::to_string(s.C) + "," + std::to_string(s.S));
    Inputs in(s);
    const auto f = run<float>(s, in.x, in.g, in.gamma, in.beta);
    const auto d = run<double>(s, in.x, in.g, in.gamma, in.beta);
    ASSERT_EQ(f.size(), d.size());
    double worst = 0;
    for (size_t i = 0; i < f.size(); ++i) {
      ASSERT_TRUE(std::isfinite(f[i])) << "at " << i;
      worst = std::max(worst, std::abs(f[i] - d[i]) / (1 + std::abs(d[i])));
    }
    // Float inputs near 3 +- 0.5 carry ~1e-7 relative error; a wrong channel, slice or
    // tail element would be off by O(1). Sums over 16384 gradients reach ~1e2.
    EXPECT_LT(worst, 2e-5);
  }
}

TEST(BatchNormKernel, FloatBitwiseEqualWithOneAndTwoThreads) {
  // 32768+ elements a channel: one channel per task, so the two thread counts split the
  // channels differently (a channel's sums then run alone or fused with the output of
  // the one before it).
  const Shape3 s{2, 7, 16411};
  Inputs in(s);
  auto once = [&](int threads) {
    set_num_threads(threads);
    return run<float>(s, in.x, in.g, in.gamma, in.beta);
  };
  const auto one = once(1), two = once(2);
  set_num_threads(1);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(0, std::memcmp(one.data(), two.data(), one.size() * sizeof(double)));
}

TEST(BatchNormKernel, FloatBackwardWithoutInputGradientAndInEval) {
  // dinp null: the channels' sums then run alone; dgamma and dbeta must not change.
  // Eval (training = false): dinp += gamma * rstd * g, checked against the double kernel.
  const Shape3 s{2, 5, 333};
  Inputs in(s);
  const int64_t E = s.N * s.C * s.S;
  auto backward = [&](auto zero, bool with_dinp, bool training) {
    using T = decltype(zero);
    std::vector<T> x = as<T>(in.x), g = as<T>(in.g), gm = as<T>(in.gamma);
    std::vector<T> mean(static_cast<size_t>(s.C)), rstd(mean);
    for (int64_t c = 0; c < s.C; ++c)
      mean[size_t(c)] = T(3 + 0.1 * double(c)), rstd[size_t(c)] = T(2 - 0.1 * double(c));
    std::vector<T> dx(static_cast<size_t>(E), T(0)), dgm(mean.size(), T(0)), dbt(mean.size(), T(0));
    batch_norm_backward(with_dinp ? dx.data() : nullptr, dgm.data(), dbt.data(), g.data(), x.data(), gm.data(),
                        mean.data(), rstd.data(), s.N, s.C, s.S, training);
    std::vector<double> all(dx.begin(), dx.end());
    all.insert(all.end(), dgm.begin(), dgm.end());
    all.insert(all.end(), dbt.begin(), dbt.end());
    return all;
  };
  const auto with = backward(0.0f, true, true), without = backward(0.0f, false, true);
  for (size_t i = size_t(E); i < with.size(); ++i)
    EXPECT_EQ(with[i], without[i]) << "parameter gradient " << i - size_t(E);
  for (int64_t i = 0; i < E; ++i) ASSERT_EQ(without[size_t(i)], 0.0);
  const auto f = backward(0.0f, true, false), d = backward(0.0, true, false);
  for (size_t i = 0; i < f.size(); ++i) ASSERT_NEAR(f[i], d[i], 2e-5 * (1 + std::abs(d[i]))) << "at " << i;
}
