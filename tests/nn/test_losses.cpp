#include <gtest/gtest.h>

#include <cmath>

#include "nn/losses/bce.h"
#include "nn/losses/l1.h"
#include "nn/losses/mse.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

namespace {
TensorD uniform_tensor(const Shape& s, Rng& rng, double lo, double hi) {
  TensorD t(s);
  for (auto& v : t) v = rng.uniform(lo, hi);
  return t;
}
}  // namespace

TEST(Losses, ForwardHandComputed) {
  Var<double> p(Tensor<double>::from({2, 2}, {1, 2, 3, 4}));
  Var<double> t(Tensor<double>::from({2, 2}, {1, 0, 4, 6}));
  EXPECT_EQ(mse_loss(p, t).shape(), Shape{});
  EXPECT_DOUBLE_EQ(mse_loss(p, t).value()[0], (0 + 4 + 1 + 4) / 4.0);
  EXPECT_DOUBLE_EQ(l1_loss(p, t).value()[0], (0 + 2 + 1 + 2) / 4.0);

  Var<double> x(Tensor<double>::from({3}, {0, 2, -1}));
  Var<double> y(Tensor<double>::from({3}, {1, 0, 0.5}));
  const double want = (std::log(2.0) + std::log(1 + std::exp(2.0)) +
                       (0.5 * std::log(1 + std::exp(1.0)) + 0.5 * std::log(1 + std::exp(-1.0)))) /
                      3;
  EXPECT_NEAR(bce_with_logits_loss(x, y).value()[0], want, 1e-14);

  Var<double> pr(Tensor<double>::from({2}, {0.25, 0.5}));
  Var<double> ta(Tensor<double>::from({2}, {1, 0}));
  EXPECT_NEAR(bce_loss(pr, ta).value()[0], -(std::log(0.25) + std::log(0.5)) / 2, 1e-14);
}

TEST(Losses, ExtremesStayFinite) {
  Var<float> big(Tensor<float>::from({2}, {-1000, 1000}));
  Var<float> t(Tensor<float>::from({2}, {1, 0}));
  EXPECT_NEAR(bce_with_logits_loss(big, t).value()[0], 1000.0f, 1e-3f);
  Var<float> p(Tensor<float>::from({2}, {0, 1}));
  EXPECT_FLOAT_EQ(bce_loss(p, t).value()[0], 100.0f);  // PyTorch's clamp at -100
  Var<float> pg(Tensor<float>::from({2}, {0, 1}), true);
  bce_loss(pg, t).backward();
  for (float g : pg.grad()) EXPECT_TRUE(std::isfinite(g));
}

TEST(Losses, GradCheck) {
  Rng rng(61);
  const Shape s{3, 2, 5};
  std::vector<VarD> in = {VarD(random_tensor(s, rng), true), VarD(random_tensor(s, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return mse_loss(v[0], v[1]); }, in);
  gradcheck([](std::vector<VarD>& v) { return l1_loss(v[0], v[1]); }, in);
  std::vector<VarD> logits = {VarD(random_tensor(s, rng, 3.0), true), VarD(uniform_tensor(s, rng, 0, 1), true)};
  gradcheck([](std::vector<VarD>& v) { return bce_with_logits_loss(v[0], v[1]); }, logits);
  std::vector<VarD> probs = {VarD(uniform_tensor(s, rng, 0.05, 0.95), true), VarD(uniform_tensor(s, rng, 0, 1), true)};
  gradcheck([](std::vector<VarD>& v) { return bce_loss(v[0], v[1]); }, probs);
}

TEST(Losses, ScalarTargets) {
  Var<double> x(Tensor<double>::from({2}, {0.5, -1}));
  Var<double> ones(Tensor<double>::ones({2}));
  EXPECT_DOUBLE_EQ(bce_with_logits_loss(x, 1.0).value()[0], bce_with_logits_loss(x, ones).value()[0]);
  EXPECT_DOUBLE_EQ(mse_loss(x, 1.0).value()[0], (0.25 + 4) / 2);
  Var<double> p(Tensor<double>::from({2}, {0.5, 0.25}));
  EXPECT_DOUBLE_EQ(bce_loss(p, 0.0).value()[0], -(std::log(0.5) + std::log(0.75)) / 2);
}

TEST(Losses, TargetWithoutGradAndShapeMismatch) {
  Var<double> p(Tensor<double>::from({2}, {1, 3}), true);
  Var<double> t(Tensor<double>::from({2}, {0, 0}));
  mse_loss(p, t).backward();
  EXPECT_DOUBLE_EQ(p.grad()[1], 3.0);  // 2 * 3 / 2
  EXPECT_FALSE(t.grad().defined());
  EXPECT_THROW(mse_loss(p, Var<double>(Tensor<double>::zeros({3}))), std::invalid_argument);
}
