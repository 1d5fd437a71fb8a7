#include <gtest/gtest.h>

#include <cmath>

#include "nn/functional/activations.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

TEST(Activations, ForwardValues) {
  Var<double> x(Tensor<double>::from({4}, {-2, -0.5, 0, 3}));
  auto r = relu(x), l = leaky_relu(x, 0.2), t = tanh_act(x), s = sigmoid(x);
  EXPECT_DOUBLE_EQ(r.value()[0], 0);
  EXPECT_DOUBLE_EQ(r.value()[3], 3);
  EXPECT_DOUBLE_EQ(l.value()[0], -0.4);
  EXPECT_DOUBLE_EQ(l.value()[3], 3);
  EXPECT_DOUBLE_EQ(t.value()[1], std::tanh(-0.5));
  EXPECT_DOUBLE_EQ(s.value()[2], 0.5);
  EXPECT_NEAR(s.value()[0], 1 / (1 + std::exp(2.0)), 1e-15);
  // Extreme inputs stay finite.
  Var<float> big(Tensor<float>::from({2}, {-200, 200}));
  auto sb = sigmoid(big);
  EXPECT_EQ(sb.value()[0], 0.0f);
  EXPECT_EQ(sb.value()[1], 1.0f);
}

TEST(Activations, GradCheck) {
  Rng rng(11);
  std::vector<VarD> in = {away_from_zero({3, 4, 2, 5}, rng)};
  gradcheck([](std::vector<VarD>& v) { return relu(v[0]); }, in);
  gradcheck([](std::vector<VarD>& v) { return leaky_relu(v[0], 0.2); }, in);
  gradcheck([](std::vector<VarD>& v) { return tanh_act(v[0]); }, in);
  gradcheck([](std::vector<VarD>& v) { return nns::tanh(v[0]); }, in);
  gradcheck([](std::vector<VarD>& v) { return sigmoid(v[0]); }, in);
}
