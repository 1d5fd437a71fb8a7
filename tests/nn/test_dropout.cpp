#include <gtest/gtest.h>

#include <cstring>

#include "nn/functional/dropout.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

TEST(Dropout, StatisticsMatchP) {
  for (double p : {0.1, 0.5, 0.8}) {
    Rng rng(31);
    const int64_t n = 200000;
    Var<float> x(Tensor<float>::ones({n}));
    auto y = dropout(x, p, true, rng);
    int64_t dropped = 0;
    double total = 0;
    for (float v : y.value()) {
      dropped += v == 0;
      total += v;
    }
    // Binomial std of the drop fraction is sqrt(p(1-p)/n) < 1.2e-3: allow 5 sigma.
    EXPECT_NEAR(double(dropped) / n, p, 6e-3) << "p=" << p;
    EXPECT_NEAR(total / n, 1.0, 0.03) << "mean not preserved, p=" << p;
    for (float v : y.value())
      if (v != 0) {
        EXPECT_FLOAT_EQ(v, float(1 / (1 - p)));
        break;
      }
  }
}

TEST(Dropout, IdentityInEvalOrAtZero) {
  Rng rng(32);
  Var<float> x(Tensor<float>::from({3}, {1, 2, 3}), true);
  EXPECT_TRUE(dropout(x, 0.5, false, rng).value().shares_storage(x.value()));
  EXPECT_TRUE(dropout(x, 0.0, true, rng).value().shares_storage(x.value()));
  Var<float> all = dropout(x, 1.0, true, rng);
  for (float v : all.value()) EXPECT_EQ(v, 0.0f);
  EXPECT_THROW(dropout(x, 1.5, true, rng), std::invalid_argument);
}

TEST(Dropout, SameSeedSameMaskAndThreadIndependent) {
  Tensor<float> t = Tensor<float>::ones({100003});
  auto run = [&](int threads) {
    set_num_threads(threads);
    Rng rng(33);
    return dropout(Var<float>(t), 0.3, true, rng).value();
  };
  Tensor<float> a = run(1), b = run(2), c = run(2);
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), sizeof(float) * size_t(a.numel())));
  EXPECT_EQ(0, std::memcmp(b.data(), c.data(), sizeof(float) * size_t(a.numel())));
  Rng r1(33), r2(34);
  auto d = dropout(Var<float>(t), 0.3, true, r1).value();
  auto e = dropout(Var<float>(t), 0.3, true, r2).value();
  EXPECT_NE(0, std::memcmp(d.data(), e.data(), sizeof(float) * size_t(d.numel())));
}

TEST(Dropout, GradCheck) {
  Rng rng(34);
  std::vector<VarD> in = {VarD(random_tensor({4, 7}, rng), true)};
  // Re-seeded inside f so every evaluation draws the same mask.
  gradcheck(
      [](std::vector<VarD>& v) {
        Rng r(99);
        return dropout(v[0], 0.4, true, r);
      },
      in);
}
