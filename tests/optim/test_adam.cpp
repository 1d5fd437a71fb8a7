#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>

#include "core/rng.h"
#include "optim/adam.h"

using namespace nns;

// Counts heap allocations so the test can show step() allocates nothing. GCC cannot see
// that this operator new and delete pair up through malloc/free.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
static std::atomic<int64_t> g_allocations{0};
void* operator new(size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }

namespace {

Var<double> param(std::vector<double> v) { return Var<double>(Tensor<double>::from({int64_t(v.size())}, v), true); }
void set_grad(Var<double>& p, std::vector<double> g) {
  auto& buf = p.grad_buffer();
  for (size_t i = 0; i < g.size(); ++i) buf[int64_t(i)] = g[i];
}

}  // namespace

TEST(Adam, FirstStepMovesByLearningRate) {
  // After one step m_hat = g and v_hat = g^2, so the update is lr * g / (|g| + eps).
  auto p = param({1.0});
  Adam<double> opt({p}, {.lr = 0.1});
  set_grad(p, {0.5});
  opt.step();
  EXPECT_NEAR(p.value()[0], 1.0 - 0.1 * 0.5 / (0.5 + 1e-8), 1e-15);
  EXPECT_EQ(opt.steps(0), 1);
}

TEST(Adam, EpsIsAddedOutsideTheSquareRoot) {
  // g = 0.5, eps = 0.1: outside the root 0.1 * 0.5 / 0.6; inside it would be
  // 0.1 * 0.5 / sqrt(0.35).
  auto p = param({1.0});
  Adam<double> opt({p}, {.lr = 0.1, .eps = 0.1});
  set_grad(p, {0.5});
  opt.step();
  EXPECT_NEAR(p.value()[0], 1.0 - 0.05 / 0.6, 1e-15);
}

class AdamTextbook : public ::testing::TestWithParam<double> {};

// beta1 0.8 and 0.9 take one branch of PyTorch's lerp, pix2pix's 0.5 and 0.3 the other.
INSTANTIATE_TEST_SUITE_P(Beta1, AdamTextbook, ::testing::Values(0.9, 0.8, 0.5, 0.3));

TEST_P(AdamTextbook, ThreeStepsMatchTheTextbookFormula) {
  // The reference uses the paper's form with explicit m_hat and v_hat; the optimizer
  // uses PyTorch's rearrangement, so they agree to rounding.
  const double lr = 0.01, b1 = GetParam(), b2 = 0.95, eps = 1e-6, wd = 0.05;
  std::vector<double> w = {0.3, -1.2, 2.0}, m(3, 0), v(3, 0);
  auto p = param(w);
  Adam<double> opt({p}, {.lr = lr, .beta1 = b1, .beta2 = b2, .eps = eps, .weight_decay = wd});
  const double grads[3][3] = {{0.1, -0.4, 1.5}, {-0.2, 0.3, 0.0}, {0.7, -0.1, -2.0}};
  for (int t = 1; t <= 3; ++t) {
    opt.zero_grad();
    set_grad(p, {grads[t - 1][0], grads[t - 1][1], grads[t - 1][2]});
    opt.step();
    for (int k = 0; k < 3; ++k) {
      double g = grads[t - 1][k] + wd * w[k];
      m[k] = b1 * m[k] + (1 - b1) * g;
      v[k] = b2 * v[k] + (1 - b2) * g * g;
      double m_hat = m[k] / (1 - std::pow(b1, t)), v_hat = v[k] / (1 - std::pow(b2, t));
      w[k] -= lr * m_hat / (std::sqrt(v_hat) + eps);
      EXPECT_NEAR(p.value()[k], w[k], 1e-14) << "step " << t << " element " << k;
    }
  }
}

TEST(Adam, ParametersWithoutGradientAreSkippedAndKeepTheirOwnStepCount) {
  auto a = param({1.0}), b = param({1.0});
  Adam<double> opt({a, b}, {.lr = 0.1});
  set_grad(a, {1.0});
  opt.step();
  EXPECT_EQ(b.value()[0], 1.0);
  EXPECT_EQ(opt.steps(1), 0);
  // b's first step must use t = 1's bias correction: a move of lr, whatever a did.
  opt.zero_grad();
  set_grad(b, {-3.0});
  opt.step();
  EXPECT_NEAR(b.value()[0], 1.0 + 0.1 * 3.0 / (3.0 + 1e-8), 1e-15);
  EXPECT_EQ(opt.steps(0), 1);
  EXPECT_EQ(opt.steps(1), 1);
}

TEST(Adam, ZeroGradDropsGradients) {
  auto p = param({1.0});
  Adam<double> opt({p});
  set_grad(p, {1.0});
  opt.zero_grad();
  EXPECT_FALSE(p.grad().defined());
}

TEST(Adam, StepAllocatesNothing) {
  // NNAO-sized: a few layers, ~15k values in total.
  std::vector<Var<float>> ps;
  for (int64_t n : {4 * 512, 512, 512 * 16, 16, 16 * 256, 256, 4})
    ps.emplace_back(Tensor<float>::full({n}, 0.5f), true);
  Adam<float> opt(ps, {.lr = 1e-3});
  for (auto& p : ps) p.grad_buffer().fill(0.25f);
  opt.step();
  int64_t before = g_allocations.load();
  for (int i = 0; i < 10; ++i) opt.step();
  EXPECT_EQ(g_allocations.load(), before);
}

TEST(Adam, StateRoundTripsThroughABlob) {
  auto p = param({0.5, -0.5});
  Adam<double> opt({p}, {.lr = 0.01});
  set_grad(p, {1.0, 2.0});
  opt.step();
  Blob b;
  opt.save_state(b, "opt.");
  Blob back = Blob::parse(b.serialize(), "test");

  auto q = Var<double>(p.value().clone(), true);
  Adam<double> restored({q}, {.lr = 0.5});
  restored.load_state(back, "opt.");
  EXPECT_EQ(restored.lr(), 0.01);
  EXPECT_EQ(restored.steps(0), 1);
  set_grad(p, {-1.0, 0.5});
  set_grad(q, {-1.0, 0.5});
  opt.step();
  restored.step();
  EXPECT_EQ(p.value()[0], q.value()[0]);
  EXPECT_EQ(p.value()[1], q.value()[1]);
}

TEST(Adam, RejectsBadOptions) {
  auto p = param({1.0});
  EXPECT_THROW(Adam<double>({p}, {.beta1 = 1.0}), std::invalid_argument);
  EXPECT_THROW(Adam<double>({p}, {.lr = -1}), std::invalid_argument);
  EXPECT_THROW(Adam<double>({Var<double>(Tensor<double>::zeros({1}))}), std::invalid_argument);
  EXPECT_THROW(Adam<double>({p, p}), std::invalid_argument);
}

TEST(Adam, VectorAndScalarPathsAgreeBitwise) {
  // 37 elements: the SIMD body plus a scalar tail, against one scalar call per element.
  Rng rng(4);
  const int64_t n = 37;
  std::vector<float> w(n), m(n), v(n), g(n);
  for (int64_t k = 0; k < n; ++k) {
    w[k] = float(rng.normal());
    m[k] = float(0.1 * rng.normal());
    v[k] = float(0.01 * rng.uniform());
    g[k] = float(rng.normal());
  }
  auto w2 = w, m2 = m, v2 = v;
  for (float beta1 : {0.9f, 0.5f}) {  // both forms of the moment's lerp
    const AdamCoeffs<float> c{beta1, 1 - beta1, 0.999f, 0.001f, 0.01f, 0.3f, 1e-8f, 0.002f};
    adam_update(w.data(), m.data(), v.data(), g.data(), n, c);
    for (int64_t k = 0; k < n; ++k) adam_update(&w2[k], &m2[k], &v2[k], &g[k], 1, c);
    for (int64_t k = 0; k < n; ++k) {
      EXPECT_EQ(std::memcmp(&w[k], &w2[k], 4), 0) << k;
      EXPECT_EQ(std::memcmp(&m[k], &m2[k], 4), 0) << k;
      EXPECT_EQ(std::memcmp(&v[k], &v2[k], 4), 0) << k;
    }
  }
}
