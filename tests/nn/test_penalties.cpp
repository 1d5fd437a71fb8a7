#include <gtest/gtest.h>

#include "nn/losses/penalties.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

TEST(Penalties, HandComputed) {
  Var<double> a(Tensor<double>::from({2}, {-1, 2}), true);
  Var<double> b(Tensor<double>::from({1, 1}, {-3}), true);
  EXPECT_DOUBLE_EQ(l1_penalty<double>({a, b}).value()[0], 6);
  EXPECT_DOUBLE_EQ(l2_penalty<double>({a, b}).value()[0], 14);
  l1_penalty<double>({a, b}).backward();
  EXPECT_DOUBLE_EQ(a.grad()[0], -1);
  EXPECT_DOUBLE_EQ(b.grad()[0], -1);
}

TEST(Penalties, GradCheck) {
  Rng rng(101);
  std::vector<VarD> in = {VarD(random_tensor({3, 4}, rng), true), VarD(random_tensor({5}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return l1_penalty(v); }, in);
  gradcheck([](std::vector<VarD>& v) { return l2_penalty(v); }, in);
}
