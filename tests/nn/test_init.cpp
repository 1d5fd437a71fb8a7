#include <gtest/gtest.h>

#include <cmath>

#include "nn/batchnorm.h"
#include "nn/init.h"
#include "nn/prelu.h"
#include "nn/sequential.h"

using namespace nns;

namespace {
struct Moments {
  double mean = 0, std = 0, max_abs = 0;
};
Moments moments(const Tensor<float>& t) {
  Moments m;
  for (float v : t) m.mean += v;
  m.mean /= double(t.numel());
  for (float v : t) {
    m.std += (v - m.mean) * (v - m.mean);
    m.max_abs = std::max(m.max_abs, double(std::abs(v)));
  }
  m.std = std::sqrt(m.std / double(t.numel()));
  return m;
}
// A stand-in for a layer with a matrix weight and a bias (conv/linear).
class Affine : public Module<float> {
 public:
  Affine() {
    weight = register_parameter("weight", Tensor<float>::full({64, 32, 3, 3}, 5));
    bias = register_parameter("bias", Tensor<float>::full({64}, 5));
  }
  Var<float> weight, bias;
};
}  // namespace

TEST(Init, FansFollowPyTorch) {
  EXPECT_EQ(fan_in({10, 20}), 20);
  EXPECT_EQ(fan_out({10, 20}), 10);
  EXPECT_EQ(fan_in({64, 32, 3, 3}), 288);
  EXPECT_EQ(fan_out({64, 32, 3, 3}), 576);
  EXPECT_THROW(fan_in({5}), std::invalid_argument);
}

TEST(Init, DistributionsHaveTheirMoments) {
  Rng rng(1);
  Tensor<float> t({256, 128});  // fan_in 128, fan_out 256, 32768 draws
  normal_(t, 1.0, 0.5, rng);
  EXPECT_NEAR(moments(t).mean, 1.0, 0.01);
  EXPECT_NEAR(moments(t).std, 0.5, 0.01);
  uniform_(t, -2, 2, rng);
  EXPECT_NEAR(moments(t).std, 4 / std::sqrt(12.0), 0.02);
  EXPECT_LE(moments(t).max_abs, 2.0);
  kaiming_normal_(t, rng);
  EXPECT_NEAR(moments(t).std, std::sqrt(2.0 / 128), 0.003);
  kaiming_uniform_(t, rng, std::sqrt(5.0));  // PyTorch's Linear default: bound 1/sqrt(fan_in)
  EXPECT_LE(moments(t).max_abs, 1 / std::sqrt(128.0) + 1e-7);
  EXPECT_NEAR(moments(t).std, 1 / std::sqrt(128.0) / std::sqrt(3.0), 0.002);
  kaiming_normal_(t, rng, 0.0, 8);  // explicit fan_in
  EXPECT_NEAR(moments(t).std, 0.5, 0.01);
  xavier_uniform_(t, rng);
  EXPECT_LE(moments(t).max_abs, std::sqrt(6.0 / 384) + 1e-7);
  xavier_normal_(t, rng, 2.0);
  EXPECT_NEAR(moments(t).std, 2 * std::sqrt(2.0 / 384), 0.003);
}

TEST(Init, Pix2PixByNameAndShape) {
  Sequential<float> net;
  auto conv = net.add(std::make_shared<Affine>());
  auto bn = net.add(std::make_shared<BatchNorm2d<float>>(512));
  auto act = net.add(std::make_shared<PReLUBeta<float>>(4, 0.25, 1.0));
  Rng rng(2);
  init_pix2pix(net, rng);
  Moments w = moments(conv->weight.value()), g = moments(bn->weight.value());
  EXPECT_NEAR(w.mean, 0, 0.002);
  EXPECT_NEAR(w.std, 0.02, 0.001);
  EXPECT_NEAR(g.mean, 1, 0.004);
  EXPECT_NEAR(g.std, 0.02, 0.003);
  for (float v : conv->bias.value()) EXPECT_EQ(v, 0);
  for (float v : bn->bias.value()) EXPECT_EQ(v, 0);
  for (float v : act->alpha.value()) EXPECT_EQ(v, 0.25f);  // untouched
  // Same seed, same weights.
  Rng again(2);
  Sequential<float> net2;
  auto conv2 = net2.add(std::make_shared<Affine>());
  net2.add(std::make_shared<BatchNorm2d<float>>(512));
  init_pix2pix(net2, again);
  for (int64_t i = 0; i < conv->weight.numel(); ++i) ASSERT_EQ(conv->weight.value()[i], conv2->weight.value()[i]);
}
