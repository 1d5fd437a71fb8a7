#pragma once
// Gradient check (dlib's impl_test_layer, done through our autograd in double).
//
// For f(inputs) -> out, project the output on a fixed random Gaussian tensor R and
// compare the analytic gradient of L = sum(out * R) with central finite differences,
// for every input that requires grad (data inputs and parameters alike). A plain
// sum(out) would prove nothing for ops whose output sums to a constant (batchnorm).
//
// Before backward every gradient buffer is pre-filled with a sentinel S and S is
// subtracted afterwards: an op that forgot to write leaves 0 where a gradient was due,
// and an op that assigned instead of accumulating loses S; both fail the comparison.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/autograd.h"
#include "core/rng.h"

namespace nns::testing {

using VarD = Var<double>;
using TensorD = Tensor<double>;

inline TensorD random_tensor(const Shape& s, Rng& rng, double scale = 1.0) {
  TensorD t(s);
  for (auto& v : t) v = scale * rng.normal();
  return t;
}

// Inputs kept away from 0, where a kink (relu, prelu) would break finite differences.
inline VarD away_from_zero(const Shape& s, Rng& rng) {
  TensorD t = random_tensor(s, rng);
  for (auto& v : t) v += v >= 0 ? 0.05 : -0.05;
  return VarD(t, true);
}

struct GradCheckResult {
  // Max over entries of |a - n| / (max(|a|, |n|) + abs_tol / tol): the combined
  // relative-plus-absolute criterion, so that passing means this is <= tol.
  double max_error = 0;
  // Max plain relative error |a - n| / max(|a|, |n|) over entries whose gradient is not
  // negligible (>= 1e-4): the figure to quote.
  double max_rel_error = 0;
  std::string worst;  // which input and index
};

// `f` must be deterministic in its inputs (dropout: re-seed inside f).
// Central differences with step eps have truncation error ~eps^2 and round-off
// ~1e-16/eps relative to the loss, so abs_tol = 1e-8 is far above the noise and far
// below any real mistake in an O(1) gradient.
inline GradCheckResult gradcheck(const std::function<VarD(std::vector<VarD>&)>& f, std::vector<VarD> inputs,
                                 double tol = 1e-6, double eps = 1e-6, double abs_tol = 1e-8, uint64_t seed = 1234) {
  GradCheckResult res;
  Rng rng(seed);
  VarD out0 = f(inputs);
  TensorD R = random_tensor(out0.shape(), rng);
  auto loss_of = [&](std::vector<VarD>& in) {
    NoGradGuard ng;
    VarD o = f(in);
    double s = 0;
    for (int64_t i = 0; i < o.numel(); ++i) s += o.value()[i] * R[i];
    return s;
  };

  // Analytic gradients, with the sentinel.
  const double S = 1e3 + 0.123;
  for (auto& in : inputs)
    if (in.requires_grad()) in.grad_buffer().fill(S);
  VarD out = f(inputs);
  if (!out.requires_grad()) {
    ADD_FAILURE() << "gradcheck: output does not require grad";
    return res;
  }
  out.backward(R);

  for (size_t k = 0; k < inputs.size(); ++k) {
    VarD& in = inputs[k];
    if (!in.requires_grad()) continue;
    TensorD analytic = in.grad().clone();
    for (auto& v : analytic) v -= S;
    TensorD& x = in.value();
    for (int64_t i = 0; i < x.numel(); ++i) {
      double orig = x[i];
      x[i] = orig + eps;
      double lp = loss_of(inputs);
      x[i] = orig - eps;
      double lm = loss_of(inputs);
      x[i] = orig;
      double numeric = (lp - lm) / (2 * eps);
      double a = analytic[i];
      double mag = std::max(std::abs(a), std::abs(numeric));
      double diff = std::abs(a - numeric);
      double err = diff / (mag + abs_tol / tol);
      if (mag >= 1e-4) res.max_rel_error = std::max(res.max_rel_error, diff / mag);
      if (err > res.max_error) {
        res.max_error = err;
        res.worst = "input " + std::to_string(k) + " index " + std::to_string(i) + ": analytic " + std::to_string(a) +
                    " numeric " + std::to_string(numeric);
      }
    }
  }
  EXPECT_LE(res.max_error, tol) << "worst: " << res.worst;
  // For the closing note's table: ctest -V (or running the test binary) shows it.
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::printf("[gradcheck] %s.%s max_rel_error=%.3e criterion=%.3e\n", info->test_suite_name(), info->name(),
              res.max_rel_error, res.max_error);
  return res;
}

}  // namespace nns::testing
