#include <gtest/gtest.h>

#include <cstring>

#include "core/rng.h"
#include "optim/sgd.h"

using namespace nns;

namespace {

Var<double> param(double v) { return Var<double>(Tensor<double>::from({1}, {v}), true); }
void set_grad(Var<double>& p, double g) { p.grad_buffer()[0] = g; }

}  // namespace

TEST(Sgd, PlainStep) {
  auto p = param(1.0);
  Sgd<double> opt({p}, {.lr = 0.1});
  set_grad(p, 2.0);
  opt.step();
  EXPECT_DOUBLE_EQ(p.value()[0], 0.8);
}

TEST(Sgd, MomentumTwoSteps) {
  // b1 = g1 = 1, p = 1 - 0.1 = 0.9; b2 = 0.9 * 1 + 2 = 2.9, p = 0.9 - 0.29 = 0.61.
  auto p = param(1.0);
  Sgd<double> opt({p}, {.lr = 0.1, .momentum = 0.9});
  set_grad(p, 1.0);
  opt.step();
  EXPECT_DOUBLE_EQ(p.value()[0], 0.9);
  opt.zero_grad();
  set_grad(p, 2.0);
  opt.step();
  EXPECT_NEAR(p.value()[0], 0.61, 1e-15);
}

TEST(Sgd, NesterovTwoSteps) {
  // b1 = 1, step 1 + 0.9 * 1 = 1.9 -> p = 0.81; b2 = 2.9, step 2 + 0.9 * 2.9 = 4.61 -> p = 0.349.
  auto p = param(1.0);
  Sgd<double> opt({p}, {.lr = 0.1, .momentum = 0.9, .nesterov = true});
  set_grad(p, 1.0);
  opt.step();
  EXPECT_NEAR(p.value()[0], 0.81, 1e-15);
  opt.zero_grad();
  set_grad(p, 2.0);
  opt.step();
  EXPECT_NEAR(p.value()[0], 0.349, 1e-15);
}

TEST(Sgd, WeightDecayAddsToTheGradient) {
  auto p = param(2.0);
  Sgd<double> opt({p}, {.lr = 0.1, .weight_decay = 0.5});
  set_grad(p, 0.0);
  opt.step();
  EXPECT_DOUBLE_EQ(p.value()[0], 1.9);
}

TEST(Sgd, SkipsParametersWithoutGradient) {
  auto a = param(1.0), b = param(1.0);
  Sgd<double> opt({a, b}, {.lr = 0.1, .momentum = 0.9});
  set_grad(a, 1.0);
  opt.step();
  opt.step();  // a's gradient is still there (not zeroed): momentum keeps building
  EXPECT_DOUBLE_EQ(b.value()[0], 1.0);
  EXPECT_NEAR(a.value()[0], 1.0 - 0.1 - 0.19, 1e-15);
}

TEST(Sgd, MomentumStateRoundTripsThroughABlob) {
  auto p = param(1.0);
  Sgd<double> opt({p}, {.lr = 0.1, .momentum = 0.9});
  set_grad(p, 1.0);
  opt.step();
  Blob b;
  opt.save_state(b, "");
  auto q = param(p.value()[0]);
  Sgd<double> restored({q}, {.lr = 0.1, .momentum = 0.9});
  restored.load_state(Blob::parse(b.serialize(), "test"), "");
  set_grad(q, 2.0);
  restored.step();
  EXPECT_NEAR(q.value()[0], 0.61, 1e-15);
}

TEST(Sgd, NesterovNeedsMomentum) {
  auto p = param(1.0);
  EXPECT_THROW(Sgd<double>({p}, {.nesterov = true}), std::invalid_argument);
}

TEST(Sgd, ResultDoesNotDependOnTensorBoundaries) {
  // One 37-element parameter against 37 one-element parameters: the compiler's
  // vectorised body and scalar tail must round alike.
  Rng rng(8);
  std::vector<float> w(37), g(37);
  for (auto& x : w) x = float(rng.normal());
  for (auto& x : g) x = float(rng.normal());
  Var<float> whole(Tensor<float>::from({37}, w), true);
  std::vector<Var<float>> parts;
  for (int k = 0; k < 37; ++k) parts.emplace_back(Tensor<float>::from({1}, {w[k]}), true);
  Sgd<float> a({whole}, {.lr = 0.1, .momentum = 0.9, .nesterov = true, .weight_decay = 0.01});
  Sgd<float> b(parts, {.lr = 0.1, .momentum = 0.9, .nesterov = true, .weight_decay = 0.01});
  for (int step = 0; step < 3; ++step) {
    for (int k = 0; k < 37; ++k) {
      whole.grad_buffer()[k] = g[k];
      parts[k].grad_buffer()[0] = g[k];
    }
    a.step();
    b.step();
  }
  for (int k = 0; k < 37; ++k) EXPECT_EQ(std::memcmp(&whole.value()[k], &parts[k].value()[0], 4), 0) << k;
}
