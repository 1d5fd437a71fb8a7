#include <gtest/gtest.h>

#include <cstring>

#include "nn/functional/reduce.h"
#include "nn/functional/reshape.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

TEST(Reduce, SumMeanValuesAndScalarShape) {
  Var<float> x(Tensor<float>::from({2, 3}, {1, 2, 3, 4, 5, 6}));
  auto s = sum(x), m = mean(x);
  EXPECT_EQ(s.shape(), Shape{});
  EXPECT_EQ(s.numel(), 1);
  EXPECT_FLOAT_EQ(s.value()[0], 21);
  EXPECT_FLOAT_EQ(m.value()[0], 3.5f);
}

TEST(Reduce, GradCheck) {
  Rng rng(5);
  std::vector<VarD> in = {VarD(random_tensor({3, 2, 5}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return sum(v[0]); }, in);
  gradcheck([](std::vector<VarD>& v) { return mean(v[0]); }, in);
}

TEST(Reduce, BackwardFromScalar) {
  Var<double> x(Tensor<double>::from({4}, {1, 2, 3, 4}), true);
  mean(x).backward();
  for (int i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(x.grad()[i], 0.25);
}

TEST(Reduce, DeterministicAcrossThreadCounts) {
  Rng rng(6);
  Tensor<float> x({1 << 20});
  for (auto& v : x) v = float(rng.normal());
  set_num_threads(1);
  float one = sum(Var<float>(x)).value()[0];
  set_num_threads(2);
  float two = sum(Var<float>(x)).value()[0];
  EXPECT_EQ(0, std::memcmp(&one, &two, sizeof one));
}

TEST(Reshape, ViewAndGradient) {
  Rng rng(7);
  std::vector<VarD> in = {VarD(random_tensor({2, 3, 2, 2}, rng), true)};
  auto f = flatten(in[0]);
  EXPECT_EQ(f.shape(), Shape({2, 12}));
  EXPECT_TRUE(f.value().shares_storage(in[0].value()));
  EXPECT_THROW(reshape(in[0], {5, 5}), std::invalid_argument);
  gradcheck([](std::vector<VarD>& v) { return reshape(v[0], {4, 6}); }, in);
  gradcheck([](std::vector<VarD>& v) { return flatten(v[0]); }, in);
}
