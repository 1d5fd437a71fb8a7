#include <gtest/gtest.h>

#include "nn/activations.h"
#include "nn/batchnorm.h"
#include "nn/dropout.h"
#include "nn/functional/elementwise.h"
#include "nn/functional/reduce.h"
#include "nn/prelu.h"
#include "nn/sequential.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

TEST(Modules, SequentialNamesAndForward) {
  auto net = std::make_shared<Sequential<float>>();
  net->add(std::make_shared<PReLUBeta<float>>(3, 0.1, 2.0));
  net->add(std::make_shared<ReLU<float>>());
  net->add(std::make_shared<BatchNorm1d<float>>(3));
  auto names = net->named_parameters();
  ASSERT_EQ(names.size(), 4u);
  EXPECT_EQ(names[0].first, "0.alpha");
  EXPECT_EQ(names[1].first, "0.beta");
  EXPECT_EQ(names[2].first, "2.weight");
  EXPECT_EQ(net->named_buffers()[1].first, "2.running_var");
  Var<float> x(Tensor<float>::from({2, 3}, {-1, 1, 2, 3, -2, 4}));
  net->eval();
  auto y = net->forward(x);
  // prelu: [-0.1, 2, 4, 6, -0.2, 8]; relu zeroes negatives; BN eval ~ identity.
  EXPECT_NEAR(y.value()[0], 0, 1e-6);
  EXPECT_NEAR(y.value()[1], 2 / std::sqrt(1 + 1e-5), 1e-5);
  EXPECT_NEAR(y.value()[5], 8 / std::sqrt(1 + 1e-5), 1e-5);
}

TEST(Modules, ActivationValues) {
  Var<float> x(Tensor<float>::from({3}, {-2, 0.5, 3}));
  EXPECT_FLOAT_EQ(LeakyReLU<float>(0.2).forward(x).value()[0], -0.4f);
  EXPECT_FLOAT_EQ(Tanh<float>().forward(x).value()[1], std::tanh(0.5f));
  EXPECT_FLOAT_EQ(Sigmoid<float>().forward(x).value()[1], 1 / (1 + std::exp(-0.5f)));
}

TEST(Modules, PReLUBetaParameterGradients) {
  Rng rng(81);
  PReLUBeta<double> act(4, 0.3, 1.2);
  VarD x(random_tensor({3, 4, 2, 2}, rng), true);
  std::vector<VarD> in = {x, act.alpha, act.beta};
  gradcheck([&](std::vector<VarD>& v) { return act.forward(v[0]); }, in);
}

TEST(Modules, DropoutFollowsModeAndCheckpointsItsRng) {
  Dropout<float> d(0.5, 7);
  Var<float> x(Tensor<float>::ones({1000}));
  auto rngs = d.named_rngs();
  ASSERT_EQ(rngs.size(), 1u);
  EXPECT_EQ(rngs[0].first, "rng");
  Rng::State saved = rngs[0].second->state();
  auto a = d.forward(x).value();
  rngs[0].second->set_state(saved);  // as a checkpoint restore would
  auto b = d.forward(x).value();
  for (int64_t i = 0; i < a.numel(); ++i) ASSERT_EQ(a[i], b[i]);
  int zeros = 0;
  for (float v : a) zeros += v == 0;
  EXPECT_GT(zeros, 400);
  EXPECT_LT(zeros, 600);
  d.eval();
  EXPECT_TRUE(d.forward(x).value().shares_storage(x.value()));
}

TEST(Modules, TrainModeIsExplicitAtBatchOne) {
  // BatchNorm in train mode at batch 1 still normalizes with batch statistics.
  BatchNorm1d<float> bn(2);
  Var<float> x(Tensor<float>::from({1, 2}, {5, -3}));
  auto y = bn.forward(x);
  EXPECT_FLOAT_EQ(y.value()[0], 0);
  EXPECT_FLOAT_EQ(y.value()[1], 0);
  EXPECT_NEAR((*bn.running_mean)[0], 0.5f, 1e-6);
}
