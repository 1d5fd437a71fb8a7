#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "nn/linear.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

TEST(LinearModule, ParametersNamesShapesAndInit) {
  Rng rng(3);
  Linear<float> fc(rng, 50, 7);
  auto named = fc.named_parameters();
  ASSERT_EQ(named.size(), 2u);
  EXPECT_EQ(named[0].first, "weight");
  EXPECT_EQ(named[1].first, "bias");
  EXPECT_EQ(fc.weight.shape(), (Shape{7, 50}));
  EXPECT_EQ(fc.bias.shape(), (Shape{7}));
  EXPECT_EQ(fc.parameter_count(), 7 * 50 + 7);
  // PyTorch: weight and bias ~ U(-1/sqrt(in), 1/sqrt(in)).
  const double bound = 1.0 / std::sqrt(50.0);
  double maxabs = 0, mean = 0;
  for (float v : fc.weight.value()) {
    maxabs = std::max(maxabs, std::abs(double(v)));
    mean += v / 350.0;
  }
  EXPECT_LE(maxabs, bound);
  EXPECT_GT(maxabs, 0.9 * bound);
  EXPECT_LT(std::abs(mean), 0.2 * bound);
  for (float v : fc.bias.value()) EXPECT_LE(std::abs(v), bound);

  Linear<float> nobias(rng, 4, 3, /*bias=*/false);
  EXPECT_EQ(nobias.named_parameters().size(), 1u);
  EXPECT_FALSE(nobias.bias.defined());

  Rng a(11), b(11);
  Linear<float> l1(a, 9, 5), l2(b, 9, 5);
  EXPECT_EQ(std::memcmp(l1.weight.value().data(), l2.weight.value().data(), sizeof(float) * 45), 0);
}

TEST(LinearModule, ForwardMatchesFunctional) {
  Rng rng(4);
  Linear<float> fc(rng, 3, 2);
  Var<float> x(Tensor<float>::from({2, 3}, {1, 2, 3, -1, 0, 0.5f}));
  Var<float> y = fc.forward(x);
  ASSERT_EQ(y.shape(), (Shape{2, 2}));
  const auto& w = fc.weight.value();
  const auto& b = fc.bias.value();
  for (int i = 0; i < 2; ++i)
    for (int o = 0; o < 2; ++o) {
      float e = b[o];
      for (int k = 0; k < 3; ++k) e += x.value()[i * 3 + k] * w[o * 3 + k];
      EXPECT_FLOAT_EQ(y.value()[i * 2 + o], e);
    }
}

TEST(LinearModule, GradCheckThroughTheModule) {
  Rng rng(5);
  Linear<double> fc(rng, 6, 3);
  VarD x(random_tensor({4, 6}, rng), true);
  gradcheck([&fc](std::vector<VarD>& v) { return fc.forward(v[0]); }, {x, fc.weight, fc.bias});
}
