// End-to-end fits: the layers, autograd and Adam together drive a loss to near zero.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "nn/conv2d.h"
#include "nn/functional/activations.h"
#include "nn/functional/elementwise.h"
#include "nn/functional/reduce.h"
#include "nn/linear.h"
#include "optim/adam.h"

using namespace nns;

namespace {

Var<float> mse(const Var<float>& pred, const Var<float>& target) { return mean(square(pred - target)); }

}  // namespace

TEST(EndToEnd, MlpLearnsXor) {
  Rng init(3);
  Linear<float> fc1(init, 2, 8), fc2(init, 8, 1);
  std::vector<Var<float>> params = fc1.parameters();
  for (auto& p : fc2.parameters()) params.push_back(p);
  Adam<float> opt(params, {.lr = 0.03});
  Var<float> x(Tensor<float>::from({4, 2}, {0, 0, 0, 1, 1, 0, 1, 1}));
  Var<float> y(Tensor<float>::from({4, 1}, {0, 1, 1, 0}));
  float first = 0, last = 0;
  for (int step = 0; step < 1500; ++step) {
    opt.zero_grad();
    Var<float> loss = mse(fc2.forward(tanh(fc1.forward(x))), y);
    loss.backward();
    opt.step();
    if (step == 0) first = loss.value()[0];
    last = loss.value()[0];
  }
  EXPECT_GT(first, 0.1f);  // it did start far from the answer
  EXPECT_LT(last, 1e-4f);
  NoGradGuard no_grad;
  Var<float> pred = fc2.forward(tanh(fc1.forward(x)));
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(pred.value()[i], y.value()[i], 0.02) << "input " << i;
}

TEST(EndToEnd, ConvLearnsAFixed3x3Filter) {
  // Targets come from a known 3x3 kernel and bias (zero padding); a single Conv2d
  // trained on random images must recover them.
  const float kernel[9] = {1, 0, -1, 2, 0.5f, -2, 1, 0, -1}, bias = 0.25f;
  Rng init(5), data(6);
  Conv2d<float> conv(init, 1, 1, 3, /*stride=*/1, /*padding=*/1);
  Adam<float> opt(conv.parameters(), {.lr = 0.05});
  const int64_t B = 4, H = 9, W = 7;
  float last = 0;
  for (int step = 0; step < 400; ++step) {
    Tensor<float> x({B, 1, H, W}), y({B, 1, H, W});
    for (auto& v : x) v = float(data.normal());
    for (int64_t b = 0; b < B; ++b)
      for (int64_t i = 0; i < H; ++i)
        for (int64_t j = 0; j < W; ++j) {
          float s = bias;
          for (int di = -1; di <= 1; ++di)
            for (int dj = -1; dj <= 1; ++dj) {
              int64_t ii = i + di, jj = j + dj;
              if (ii >= 0 && ii < H && jj >= 0 && jj < W) s += kernel[(di + 1) * 3 + dj + 1] * x[(b * H + ii) * W + jj];
            }
          y[(b * H + i) * W + j] = s;
        }
    opt.zero_grad();
    Var<float> loss = mse(conv.forward(Var<float>(x)), Var<float>(y));
    loss.backward();
    opt.step();
    last = loss.value()[0];
  }
  EXPECT_LT(last, 1e-6f);
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(conv.weight.value()[k], kernel[k], 1e-3) << "tap " << k;
  EXPECT_NEAR(conv.bias.value()[0], bias, 1e-3);
}
