// The moving average of weights against its closed form, the swap, and the saved state.
#include <gtest/gtest.h>

#include "optim/weight_average.h"

using namespace nns;

namespace {

Var<double> param(double v) { return Var<double>(Tensor<double>::from({2}, {v, -v}), true); }

}  // namespace

// avg_0 = w_0; avg_t = d_t avg + (1 - d_t) w_t with d_t = min(decay, (1+t)/(10+t)).
TEST(WeightAverage, FollowsTheRampedDecayThenTheDecay) {
  auto p = param(1.0);
  WeightAverage<double> avg({p}, 0.5);
  EXPECT_DOUBLE_EQ(avg.decay_at(0), 0.1);
  EXPECT_DOUBLE_EQ(avg.decay_at(8), 0.5);  // 9/18: the ramp meets the decay
  EXPECT_DOUBLE_EQ(avg.decay_at(100), 0.5);
  double expect = 1.0;
  for (int t = 0; t < 12; ++t) {
    p.value()[0] = 2.0 + t, p.value()[1] = -(2.0 + t);
    avg.update();
    const double d = std::min(0.5, (1.0 + t) / (10.0 + t));
    expect = d * expect + (1 - d) * (2.0 + t);
    EXPECT_NEAR(avg.average(0)[0], expect, 1e-12) << t;
    EXPECT_NEAR(avg.average(0)[1], -expect, 1e-12) << t;
  }
  EXPECT_EQ(avg.updates(), 12);
}

TEST(WeightAverage, SwapExchangesAndSwapsBack) {
  auto p = param(1.0);
  WeightAverage<double> avg({p}, 0.9);
  p.value()[0] = 5.0;
  avg.update();  // d_0 = 0.1: 0.1 * 1 + 0.9 * 5
  avg.swap();
  EXPECT_DOUBLE_EQ(p.value()[0], 4.6);
  EXPECT_DOUBLE_EQ(avg.average(0)[0], 5.0);
  avg.swap();
  EXPECT_DOUBLE_EQ(p.value()[0], 5.0);
  EXPECT_DOUBLE_EQ(avg.average(0)[0], 4.6);
}

// A restored average continues exactly as the one that was saved.
TEST(WeightAverage, SavedStateContinuesBitwise) {
  auto p = param(1.0), q = param(1.0);
  WeightAverage<double> a({p}, 0.99), b({q}, 0.99);
  for (int t = 0; t < 5; ++t) p.value()[0] = 0.3 * t, a.update();
  Blob blob("test");
  a.save_state(blob, "ema.");
  b.load_state(blob, "ema.");
  EXPECT_EQ(b.updates(), 5);
  for (int t = 0; t < 5; ++t) {
    p.value()[0] = q.value()[0] = 1.7 * t, p.value()[1] = q.value()[1] = -t;
    a.update(), b.update();
  }
  EXPECT_EQ(a.average(0)[0], b.average(0)[0]);
  EXPECT_EQ(a.average(0)[1], b.average(0)[1]);
}

TEST(WeightAverage, RefusesADecayOutsideZeroToOne) {
  auto p = param(1.0);
  EXPECT_THROW(WeightAverage<double>({p}, 1.0), std::invalid_argument);
  EXPECT_THROW(WeightAverage<double>({p}, -0.1), std::invalid_argument);
}
