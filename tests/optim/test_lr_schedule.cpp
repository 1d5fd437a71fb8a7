#include <gtest/gtest.h>

#include "optim/adam.h"
#include "optim/lr_schedule.h"

using namespace nns;

TEST(LrSchedule, ConstantIsConstant) {
  auto s = LrSchedule::constant(2e-4);
  EXPECT_EQ(s.at(0), 2e-4);
  EXPECT_EQ(s.at(1000), 2e-4);
}

TEST(LrSchedule, LinearHoldsThenDecays) {
  // n_epochs 3, n_epochs_decay 4: factor 1 - max(0, e + 1 - 3) / 5.
  auto s = LrSchedule::linear(1.0, 3, 4);
  const double expected[] = {1, 1, 1, 0.8, 0.6, 0.4, 0.2};
  for (int e = 0; e < 7; ++e) EXPECT_NEAR(s.at(e), expected[e], 1e-15) << "epoch " << e;
}

TEST(LrSchedule, Pix2pixDefaults) {
  // pix2pix: lr 2e-4, 100 epochs constant then 100 of decay.
  auto s = LrSchedule::linear(2e-4, 100, 100);
  EXPECT_EQ(s.at(99), 2e-4);
  EXPECT_NEAR(s.at(100), 2e-4 * (1 - 1.0 / 101), 1e-18);
  EXPECT_NEAR(s.at(199), 2e-4 * (1 - 100.0 / 101), 1e-18);
}

TEST(LrSchedule, AppliesToAnOptimizer) {
  Var<float> p(Tensor<float>::zeros({1}), true);
  Adam<float> opt({p}, {.lr = 1.0});
  LrSchedule::linear(1.0, 1, 1).apply(opt, 1);
  EXPECT_DOUBLE_EQ(opt.lr(), 0.5);
}
