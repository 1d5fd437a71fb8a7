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

// The hook data-parallel training starts a gradient bucket from (grad_final): once per
// backward, after the last op that adds to that leaf, never before.
TEST(Autograd, GradFinalRunsOnceWhenTheLastContributionIsIn) {
  Var<double> w(Tensor<double>::from({1, 1}, {1.0}), true);
  Var<double> v(Tensor<double>::from({1, 1}, {1.0}), true);
  Var<double> h(Tensor<double>::from({1, 1}, {1.0}));
  for (int i = 0; i < 5; ++i) h = linear(h, w);  // w used by 5 ops: 5 contributions
  h = linear(h, v);
  int w_calls = 0, v_calls = 0;
  double w_seen = 0;
  w.node()->grad_final = [&] { ++w_calls, w_seen = w.grad()[0]; };
  v.node()->grad_final = [&] { ++v_calls; EXPECT_EQ(w_calls, 0) << "v (used last) is final before w"; };
  h.backward();
  EXPECT_EQ(w_calls, 1);
  EXPECT_EQ(v_calls, 1);
  EXPECT_DOUBLE_EQ(w_seen, 5.0);  // all five contributions were in when the hook ran
  EXPECT_DOUBLE_EQ(w.grad()[0], 5.0);
}
