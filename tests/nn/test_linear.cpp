#include <gtest/gtest.h>

#include "nn/functional/linear.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

TEST(Linear, ForwardHandComputed) {
  Var<float> x(Tensor<float>::from({1, 2}, {1, 2}));
  Var<float> w(Tensor<float>::from({2, 2}, {1, 0, 3, -1}));
  Var<float> b(Tensor<float>::from({2}, {0.5f, 1}));
  auto y = linear(x, w, b);
  EXPECT_FLOAT_EQ(y.value()[0], 1.5f);
  EXPECT_FLOAT_EQ(y.value()[1], 2.0f);
}

TEST(Linear, GradCheck) {
  Rng rng(7);
  std::vector<VarD> in = {VarD(random_tensor({3, 5}, rng), true), VarD(random_tensor({4, 5}, rng), true),
                          VarD(random_tensor({4}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return linear(v[0], v[1], v[2]); }, in);
}
