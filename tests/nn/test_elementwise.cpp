#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "nn/functional/elementwise.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

namespace {
VarD rv(const Shape& s, Rng& rng, double scale = 1.0) { return VarD(random_tensor(s, rng, scale), true); }
// Values bounded away from zero, for divisors, logs and sqrt.
VarD positive(const Shape& s, Rng& rng) {
  TensorD t(s);
  for (auto& v : t) v = 0.5 + rng.uniform();
  return VarD(t, true);
}
}  // namespace

TEST(Broadcast, PlanMergesDims) {
  BroadcastPlan p = make_broadcast_plan({2, 3, 4, 5}, {3, 1, 1}, "test");
  EXPECT_EQ(p.out, Shape({2, 3, 4, 5}));
  EXPECT_EQ(p.nd, 3);  // [2, 3, 20]
  EXPECT_EQ(p.inner(), 20);
  EXPECT_EQ(p.inner_stride_b(), 0);
  BroadcastPlan q = make_broadcast_plan({4, 5}, {4, 5}, "test");
  EXPECT_EQ(q.nd, 1);
  EXPECT_THROW(make_broadcast_plan({2, 3}, {4}, "test"), std::invalid_argument);
}

// Broadcasting straight from the rule, index by index: the reference for the merged
// plan the kernels walk.
TEST(Broadcast, MatchesNaiveIndexing) {
  Rng rng(9);
  const std::vector<std::pair<Shape, Shape>> cases = {
      {{2, 1, 3, 1}, {4, 1, 5}}, {{3, 4}, {1}}, {{1, 3, 1, 2}, {2, 3, 4, 1}}, {{5}, {2, 3, 5}}};
  for (const auto& [sa, sb] : cases) {
    TensorD a = random_tensor(sa, rng), b = random_tensor(sb, rng);
    VarD y = sub(VarD(a), VarD(b));
    const Shape& so = y.shape();
    const int n = so.dim();
    std::vector<int64_t> idx(size_t(n), 0);
    for (int64_t flat = 0; flat < y.numel(); ++flat) {
      int64_t r = flat;
      for (int d = n - 1; d >= 0; --d) idx[size_t(d)] = r % so[d], r /= so[d];
      auto offset = [&](const Shape& s) {
        int64_t off = 0;
        for (int d = 0; d < s.dim(); ++d) {
          const int od = d + (n - s.dim());
          off = off * s[d] + (s[d] == 1 ? 0 : idx[size_t(od)]);
        }
        return off;
      };
      ASSERT_EQ(y.value()[flat], a[offset(sa)] - b[offset(sb)]) << sa.str() << " - " << sb.str();
    }
  }
}

TEST(Elementwise, ForwardBroadcastValues) {
  Var<float> a(Tensor<float>::from({2, 3}, {1, 2, 3, 4, 5, 6}));
  Var<float> col(Tensor<float>::from({2, 1}, {10, 20}));
  Var<float> row(Tensor<float>::from({3}, {1, 2, 4}));
  auto s = a + col;
  EXPECT_EQ(s.shape(), Shape({2, 3}));
  EXPECT_FLOAT_EQ(s.value()[0], 11);
  EXPECT_FLOAT_EQ(s.value()[5], 26);
  auto q = a / row;
  EXPECT_FLOAT_EQ(q.value()[2], 0.75f);
  EXPECT_FLOAT_EQ(q.value()[4], 2.5f);
  auto outer = col * row;  // (2,1) * (3) -> (2,3)
  EXPECT_EQ(outer.shape(), Shape({2, 3}));
  EXPECT_FLOAT_EQ(outer.value()[5], 80);
  auto d = col - row;
  EXPECT_FLOAT_EQ(d.value()[3], 19);
}

TEST(Elementwise, ScalarOperators) {
  Var<float> a(Tensor<float>::from({3}, {1, 2, 4}));
  EXPECT_FLOAT_EQ((a + 1.0f).value()[2], 5);
  EXPECT_FLOAT_EQ((1.0f - a).value()[2], -3);
  EXPECT_FLOAT_EQ((a - 1.0f).value()[0], 0);
  EXPECT_FLOAT_EQ((2.0f * a).value()[1], 4);
  EXPECT_FLOAT_EQ((a / 2.0f).value()[2], 2);
  EXPECT_FLOAT_EQ((2.0f / a).value()[2], 0.5f);
  EXPECT_FLOAT_EQ((-a).value()[1], -2);
}

TEST(Elementwise, UnaryValues) {
  Var<double> a(Tensor<double>::from({4}, {-2, 0, 0.25, 4}));
  EXPECT_DOUBLE_EQ(abs(a).value()[0], 2);
  EXPECT_DOUBLE_EQ(square(a).value()[0], 4);
  EXPECT_DOUBLE_EQ(sqrt(a).value()[3], 2);
  EXPECT_DOUBLE_EQ(exp(a).value()[1], 1);
  EXPECT_DOUBLE_EQ(log(a).value()[3], std::log(4.0));
  EXPECT_TRUE(std::isfinite(log(a).value()[1]));  // clamped, not -inf
  EXPECT_TRUE(std::isfinite(log(a).value()[0]));
}

TEST(Elementwise, GradCheckSameShape) {
  Rng rng(1);
  for (auto op : {0, 1, 2, 3}) {
    std::vector<VarD> in = {rv({3, 5}, rng), positive({3, 5}, rng)};
    gradcheck(
        [op](std::vector<VarD>& v) {
          switch (op) {
            case 0:
              return add(v[0], v[1]);
            case 1:
              return sub(v[0], v[1]);
            case 2:
              return mul(v[0], v[1]);
            default:
              return div(v[0], v[1]);
          }
        },
        in);
  }
}

TEST(Elementwise, GradCheckBroadcast) {
  Rng rng(2);
  // (N,C,H,W) with a per-channel (C,1,1), a row (W), a scalar-like (1) and (N,1,H,1).
  const Shape big{2, 3, 4, 5};
  for (Shape small : {Shape{3, 1, 1}, Shape{5}, Shape{1}, Shape{2, 1, 4, 1}}) {
    for (int op = 0; op < 4; ++op) {
      std::vector<VarD> in = {rv(big, rng), positive(small, rng)};
      auto f = [op](std::vector<VarD>& v) {
        switch (op) {
          case 0:
            return add(v[0], v[1]);
          case 1:
            return sub(v[1], v[0]);  // the broadcast operand on the left
          case 2:
            return mul(v[0], v[1]);
          default:
            return div(v[0], v[1]);
        }
      };
      gradcheck(f, in);
    }
  }
  // Both operands broadcast: (3,1) op (1,4) -> (3,4).
  std::vector<VarD> in = {rv({3, 1}, rng), positive({1, 4}, rng)};
  gradcheck([](std::vector<VarD>& v) { return div(v[0], v[1]) * v[0]; }, in);
}

TEST(Elementwise, GradCheckScalarAndUnary) {
  Rng rng(3);
  std::vector<VarD> in = {positive({2, 7}, rng)};
  gradcheck([](std::vector<VarD>& v) { return 3.0 - v[0] * 2.0 + 1.5; }, in);
  gradcheck([](std::vector<VarD>& v) { return 2.0 / v[0] + v[0] / 4.0 - (-v[0]); }, in);
  gradcheck([](std::vector<VarD>& v) { return square(v[0]); }, in);
  gradcheck([](std::vector<VarD>& v) { return sqrt(v[0]); }, in);
  gradcheck([](std::vector<VarD>& v) { return exp(v[0]); }, in);
  gradcheck([](std::vector<VarD>& v) { return log(v[0]); }, in);
  std::vector<VarD> signed_in = {rv({3, 5}, rng)};
  gradcheck([](std::vector<VarD>& v) { return abs(v[0]); }, signed_in);
  // The same Var used twice accumulates both contributions.
  gradcheck([](std::vector<VarD>& v) { return v[0] * v[0]; }, signed_in);
}

TEST(Elementwise, TargetWithoutGradGetsNone) {
  Var<double> a(Tensor<double>::from({2}, {1, 2}), true);
  Var<double> b(Tensor<double>::from({2}, {3, 4}));
  auto y = mul(a, b);
  y.backward(Tensor<double>::ones({2}));
  EXPECT_DOUBLE_EQ(a.grad()[1], 4);
  EXPECT_FALSE(b.grad().defined());
}

TEST(Elementwise, DeterministicAcrossThreadCounts) {
  Rng rng(4);
  Tensor<float> a({4, 16, 64, 64}), b({16, 1, 1}), c({4, 16, 64, 64});
  for (auto* t : {&a, &b, &c})
    for (auto& v : *t) v = float(rng.normal());
  auto run = [&](int threads) {
    set_num_threads(threads);
    Var<float> va(a.clone(), true), vb(b.clone(), true);
    Var<float> y = (va * vb + va) / 3.0f;
    y.backward(c);
    std::vector<float> all(y.value().begin(), y.value().end());
    all.insert(all.end(), va.grad().begin(), va.grad().end());
    all.insert(all.end(), vb.grad().begin(), vb.grad().end());
    return all;
  };
  auto one = run(1), two = run(2);
  set_num_threads(2);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(0, std::memcmp(one.data(), two.data(), one.size() * sizeof(float)));
}
