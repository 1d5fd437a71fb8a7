#include <gtest/gtest.h>

#include "core/autograd.h"
#include "nn/functional/linear.h"

using namespace nns;

TEST(Autograd, GradientsAccumulateAcrossBackwardCalls) {
  Var<double> x(Tensor<double>::from({1, 1}, {2.0}), true);
  Var<double> w(Tensor<double>::from({1, 1}, {3.0}), true);
  linear(x, w).backward();
  linear(x, w).backward();
  EXPECT_DOUBLE_EQ(w.grad()[0], 4.0);  // 2 + 2
  w.zero_grad();
  EXPECT_FALSE(w.grad().defined());
}

TEST(Autograd, NoGradGuardRecordsNothing) {
  Var<double> x(Tensor<double>::from({1, 1}, {2.0}), true);
  NoGradGuard g;
  auto y = linear(x, x);
  EXPECT_FALSE(y.requires_grad());
}

TEST(Autograd, DeepChainDoesNotOverflowTheStack) {
  Var<double> w(Tensor<double>::from({1, 1}, {1.0}), true);
  Var<double> h(Tensor<double>::from({1, 1}, {1.0}));
  for (int i = 0; i < 200000; ++i) h = linear(h, w);
  h.backward();
  EXPECT_DOUBLE_EQ(w.grad()[0], 200000.0);
}

TEST(Autograd, DeepGraphWithoutBackwardIsFreedWithoutRecursion) {
  Var<double> w(Tensor<double>::from({1, 1}, {1.0}), true);
  Var<double> h(Tensor<double>::from({1, 1}, {1.0}));
  for (int i = 0; i < 200000; ++i) h = linear(h, w);
  h = Var<double>();  // must not overflow the stack
  SUCCEED();
}
