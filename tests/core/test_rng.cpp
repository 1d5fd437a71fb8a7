#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/rng.h"

using namespace nns;

TEST(Rng, SeedingFollowsSplitmix64AndOutputFollowsXoshiro256StarStar) {
  // splitmix64's published outputs for seed 0, and xoshiro256**'s first output
  // rotl(s[1] * 5, 7) * 9 computed from them by hand.
  Rng r(0);
  Rng::State expected = {0xe220a8397b1dcdafull, 0x6e789e6aa1b965f4ull, 0x06c45d188009454full, 0xf88bb8a8724c81ecull};
  EXPECT_EQ(r.state(), expected);
  EXPECT_EQ(r.next_u64(), 0x99ec5f36cb75f2b4ull);
}

TEST(Rng, SameSeedSameSequence) {
  Rng a(42), b(42), c(43);
  bool c_differs = false;
  for (int i = 0; i < 1000; ++i) {
    uint64_t x = a.next_u64();
    ASSERT_EQ(x, b.next_u64());
    c_differs |= x != c.next_u64();
  }
  EXPECT_TRUE(c_differs);
}

TEST(Rng, RestoredStateContinuesTheSequence) {
  Rng a(7);
  for (int i = 0; i < 10; ++i) a.normal();
  Rng::State saved = a.state();
  std::vector<double> first;
  for (int i = 0; i < 100; ++i) first.push_back(a.normal());
  Rng b(999);
  b.set_state(saved);
  for (int i = 0; i < 100; ++i) ASSERT_EQ(b.normal(), first[size_t(i)]);
}

TEST(Rng, ForkIsDeterministicIndependentAndLeavesTheParentAlone) {
  Rng a(5);
  Rng::State before = a.state();
  Rng f1 = a.fork(1), f1b = a.fork(1), f2 = a.fork(2);
  EXPECT_EQ(a.state(), before);
  EXPECT_EQ(f1.state(), f1b.state());
  EXPECT_NE(f1.state(), f2.state());
  EXPECT_NE(f1.next_u64(), a.next_u64());
}

TEST(Rng, UniformRanges) {
  Rng r(3);
  for (int i = 0; i < 100000; ++i) {
    double u = r.uniform();
    float f = r.uniform_float();
    ASSERT_TRUE(u >= 0 && u < 1) << u;
    ASSERT_TRUE(f >= 0 && f < 1) << f;
    double v = r.uniform(-2, 3);
    ASSERT_TRUE(v >= -2 && v < 3) << v;
    ASSERT_LT(r.below(7), 7u);
  }
  EXPECT_EQ(r.below(0), 0u);
  std::set<uint64_t> seen;
  for (int i = 0; i < 1000; ++i) seen.insert(r.below(5));
  EXPECT_EQ(seen.size(), 5u);
}

TEST(Rng, NormalMoments) {
  // 200k draws: the sample mean's standard error is 0.0022, the variance's 0.0032;
  // the bounds are about 9 standard errors, so a correct generator never fails.
  Rng r(11);
  const int n = 200000;
  double s = 0, s2 = 0, s4 = 0;
  for (int i = 0; i < n; ++i) {
    double x = r.normal();
    s += x;
    s2 += x * x;
    s4 += x * x * x * x;
  }
  double mean = s / n, var = s2 / n - mean * mean;
  EXPECT_NEAR(mean, 0.0, 0.02);
  EXPECT_NEAR(var, 1.0, 0.03);
  EXPECT_NEAR(s4 / n, 3.0, 0.15);  // a Gaussian's fourth moment, not a uniform's 1.8
  Rng q(11);
  EXPECT_NEAR(q.normal(10, 0.5), 10 + 0.5 * Rng(11).normal(), 1e-12);
}
