#include <gtest/gtest.h>

#include "models/gi/gi_losses.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::testing;

TEST(GradientL1, HandComputed) {
  // pred 2x3 (one image, one channel), target 0: differences across (1,1 | 3,-6) and down
  // (3,5,-2); mean |.| across = 11/4, down = 10/3.
  Var<double> p(Tensor<double>::from({1, 1, 2, 3}, {0, 1, 2, 3, 6, 0}));
  Var<double> t(Tensor<double>::zeros({1, 1, 2, 3}));
  EXPECT_NEAR(gradient_l1(p, t).value()[0], 11.0 / 4 + 10.0 / 3, 1e-14);
}

TEST(GradientL1, AConstantOffsetCostsNothing) {
  Rng rng(3);
  TensorD t = random_tensor({2, 3, 5, 4}, rng);
  TensorD p = t;
  for (auto& v : p) v += 0.7;
  EXPECT_NEAR(gradient_l1(Var<double>(p), Var<double>(t)).value()[0], 0.0, 1e-14);
}

TEST(GradientL1, GradCheck) {
  Rng rng(2);
  std::vector<VarD> in = {VarD(random_tensor({2, 2, 4, 5}, rng), true), VarD(random_tensor({2, 2, 4, 5}, rng))};
  gradcheck([](std::vector<VarD>& v) { return gradient_l1(v[0], v[1]); }, in);
}

TEST(GradientL1, RejectsWhatIsNotAnImage) {
  Var<double> flat(Tensor<double>::zeros({4, 4}));
  EXPECT_THROW(gradient_l1(flat, flat), std::invalid_argument);
  Var<double> row(Tensor<double>::zeros({1, 1, 1, 4}));
  EXPECT_THROW(gradient_l1(row, row), std::invalid_argument);
}
