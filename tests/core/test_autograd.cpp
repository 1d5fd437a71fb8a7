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

// A leaf frozen when an op is recorded gets no gradient from that op, even if it is
// unfrozen before backward (PyTorch's rule). The GAN trainer freezes D while G's
// adversarial loss is recorded and unfreezes it before G's backward: reading the flag at
// backward time gave D the generator's gradient (docs/gan.md, "The bug that held D").
TEST(Autograd, RequiresGradIsReadWhenTheOpIsRecorded) {
  Var<double> x(Tensor<double>::from({1, 1}, {2.0}), true);
  Var<double> w(Tensor<double>::from({1, 1}, {3.0}), false);
  auto y = linear(x, w);
  w.set_requires_grad(true);
  y.backward();
  EXPECT_DOUBLE_EQ(x.grad()[0], 3.0);
  EXPECT_FALSE(w.grad().defined()) << "w was frozen when linear() was recorded";
  // And the other way: a leaf that wanted a gradient at record time gets it.
  Var<double> v(Tensor<double>::from({1, 1}, {5.0}), true);
  auto z = linear(x, v);
  v.set_requires_grad(false);
  z.backward();
  ASSERT_TRUE(v.grad().defined());
  EXPECT_DOUBLE_EQ(v.grad()[0], 2.0);
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
  v.node()->grad_final = [&] {
    ++v_calls;
    EXPECT_EQ(w_calls, 0) << "v (used last) is final before w";
  };
  h.backward();
  EXPECT_EQ(w_calls, 1);
  EXPECT_EQ(v_calls, 1);
  EXPECT_DOUBLE_EQ(w_seen, 5.0);  // all five contributions were in when the hook ran
  EXPECT_DOUBLE_EQ(w.grad()[0], 5.0);
}
