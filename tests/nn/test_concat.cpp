#include <gtest/gtest.h>

#include "nn/functional/concat.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

TEST(Concat, ForwardLayout) {
  // a (2,1,2), b (2,2,2) -> (2,3,2): per batch item a's channel then b's two.
  Var<float> a(Tensor<float>::from({2, 1, 2}, {1, 2, 3, 4}));
  Var<float> b(Tensor<float>::from({2, 2, 2}, {10, 11, 12, 13, 20, 21, 22, 23}));
  auto y = concat_channels<float>({a, b});
  EXPECT_EQ(y.shape(), Shape({2, 3, 2}));
  std::vector<float> want = {1, 2, 10, 11, 12, 13, 3, 4, 20, 21, 22, 23};
  for (int i = 0; i < 12; ++i) EXPECT_EQ(y.value()[i], want[size_t(i)]) << i;
}

TEST(Concat, GradCheckImagesAndVectors) {
  Rng rng(51);
  std::vector<VarD> in = {VarD(random_tensor({2, 3, 4, 5}, rng), true), VarD(random_tensor({2, 1, 4, 5}, rng), true),
                          VarD(random_tensor({2, 2, 4, 5}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return concat_channels(v); }, in);
  std::vector<VarD> flat = {VarD(random_tensor({3, 2}, rng), true), VarD(random_tensor({3, 5}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return concat_channels(v); }, flat);
  // One input without grad, and one used twice.
  std::vector<VarD> mixed = {VarD(random_tensor({2, 2, 3}, rng), true)};
  VarD constant(random_tensor({2, 1, 3}, rng));
  gradcheck([&](std::vector<VarD>& v) { return concat_channels<double>({v[0], constant, v[0]}); }, mixed);
}

TEST(Concat, RejectsMismatchedShapes) {
  Var<float> a(Tensor<float>::zeros({1, 2, 4, 4})), b(Tensor<float>::zeros({1, 2, 4, 3}));
  EXPECT_THROW(concat_channels<float>({a, b}), std::invalid_argument);
}
