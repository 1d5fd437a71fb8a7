#include <gtest/gtest.h>

#include "nn/functional/prelu_beta.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

TEST(PReLUBeta, ForwardHandComputed) {
  // (N=1, C=2): channel 0 alpha 0.1 beta 2, channel 1 alpha 0.5 beta 1.
  Var<float> x(Tensor<float>::from({2, 2}, {-1, -2, 3, 4}));
  Var<float> a(Tensor<float>::from({2}, {0.1f, 0.5f}));
  Var<float> b(Tensor<float>::from({2}, {2, 1}));
  auto y = prelu_beta(x, a, b);
  EXPECT_FLOAT_EQ(y.value()[0], -0.1f);
  EXPECT_FLOAT_EQ(y.value()[1], -1.0f);
  EXPECT_FLOAT_EQ(y.value()[2], 6.0f);
  EXPECT_FLOAT_EQ(y.value()[3], 4.0f);
}

TEST(PReLUBeta, GradCheckPerUnit) {
  Rng rng(21);
  std::vector<VarD> in = {away_from_zero({5, 3}, rng), VarD(random_tensor({3}, rng), true),
                          VarD(random_tensor({3}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return prelu_beta(v[0], v[1], v[2]); }, in);
}

TEST(PReLUBeta, GradCheckPerChannel) {
  Rng rng(22);
  std::vector<VarD> in = {away_from_zero({2, 3, 4, 5}, rng), VarD(random_tensor({3}, rng), true),
                          VarD(random_tensor({3}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return prelu_beta(v[0], v[1], v[2]); }, in);
}

TEST(PReLUBeta, RejectsWrongParameterShape) {
  Var<float> x(Tensor<float>::zeros({2, 3}));
  Var<float> a(Tensor<float>::zeros({2})), b(Tensor<float>::zeros({3}));
  EXPECT_THROW(prelu_beta(x, a, b), std::invalid_argument);
}
