#include <gtest/gtest.h>

#include <cmath>

#include "models/gi/hdr_mapping.h"

using nns::gi::HdrMapping;

TEST(HdrMapping, RoundTripOverManyDecades) {
  for (float k : {0.05f, 1.0f, 7.5f}) {
    HdrMapping m(k);
    for (float x = 1e-4f; x < 1e4f; x *= 1.37f) {
      float y = m.to_tanh(x);
      ASSERT_GT(y, -1.0f);
      ASSERT_LT(y, 1.0f);
      // Float resolution of u = x/(x+k) near 1 is eps, and dx/du = k/(1-u)^2, so the
      // relative round-trip error grows like eps * (1 + x/k): bright light is coarser.
      const float tol = 8 * 0x1.0p-23f * x * (1 + x / k) + 1e-7f * k;
      EXPECT_NEAR(m.from_tanh(y), x, tol) << "k=" << k << " x=" << x;
      EXPECT_NEAR(m.from_unit(m.to_unit(x)), x, tol);
    }
  }
}

TEST(HdrMapping, KnownValues) {
  HdrMapping m(2.0f);
  EXPECT_FLOAT_EQ(m.to_tanh(0.0f), -1.0f);
  EXPECT_FLOAT_EQ(m.to_tanh(2.0f), 0.0f);  // the scale lands mid-range
  EXPECT_FLOAT_EQ(m.to_unit(6.0f), 0.75f);
  EXPECT_FLOAT_EQ(m.from_unit(0.5f), 2.0f);
}

TEST(HdrMapping, MonotoneAndClamped) {
  HdrMapping m(1.0f);
  float prev = -2;
  for (float x = 0; x < 100; x += 0.25f) {
    float y = m.to_tanh(x);
    EXPECT_GT(y, prev);
    prev = y;
  }
  EXPECT_FLOAT_EQ(m.to_tanh(-3.0f), -1.0f);  // negative light clamps to 0
  // A saturated Tanh output (exactly 1) inverts to a large, finite value.
  float big = m.from_tanh(1.0f);
  EXPECT_TRUE(std::isfinite(big));
  EXPECT_GT(big, 1e5f);
  EXPECT_FLOAT_EQ(m.from_tanh(-1.5f), 0.0f);
}

TEST(HdrMapping, RejectsBadScale) {
  EXPECT_THROW(HdrMapping{0.0f}, std::invalid_argument);
  EXPECT_THROW(HdrMapping{-1.0f}, std::invalid_argument);
  EXPECT_THROW(HdrMapping{INFINITY}, std::invalid_argument);
}
