// Determinism: a small training run with dropout and batchnorm gives bitwise
// identical weights for two runs with one seed, and for 1 thread vs 2 threads.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <vector>

#include "core/thread_pool.h"
#include "nn/batchnorm.h"
#include "nn/conv2d.h"
#include "nn/functional/activations.h"
#include "nn/functional/dropout.h"
#include "nn/functional/elementwise.h"
#include "nn/functional/reduce.h"
#include "optim/adam.h"

using namespace nns;

namespace {

struct ConvNet : Module<float> {
  explicit ConvNet(uint64_t seed) {
    Rng init(seed);
    conv1 = register_module("conv1", std::make_shared<Conv2d<float>>(init, 3, 16, 3, 1, 1));
    bn = register_module("bn", std::make_shared<BatchNorm2d<float>>(16));
    conv2 = register_module("conv2", std::make_shared<Conv2d<float>>(init, 16, 1, 3, 1, 1));
    drop = &register_rng("drop", seed + 1);
  }
  Var<float> forward(const Var<float>& x) override {
    Var<float> h = relu(bn->forward(conv1->forward(x)));
    return conv2->forward(dropout(h, 0.3, is_training(), *drop));
  }
  std::shared_ptr<Conv2d<float>> conv1, conv2;
  std::shared_ptr<BatchNorm2d<float>> bn;
  Rng* drop;
};

// Trains for a few steps and returns every parameter and buffer value, in order.
std::vector<float> train(uint64_t seed, int threads) {
  set_num_threads(threads);
  ConvNet net(seed);
  Adam<float> opt(net.parameters(), {.lr = 1e-2});
  Rng data(seed + 2);
  for (int step = 0; step < 6; ++step) {
    Tensor<float> x({4, 3, 24, 20}), y({4, 1, 24, 20});
    for (auto& v : x) v = float(data.normal());
    for (auto& v : y) v = float(data.uniform());
    opt.zero_grad();
    mean(square(net.forward(Var<float>(x)) - Var<float>(y))).backward();
    opt.step();
  }
  std::vector<float> out;
  for (auto& p : net.parameters()) out.insert(out.end(), p.value().begin(), p.value().end());
  for (auto& [name, b] : net.named_buffers()) out.insert(out.end(), b->begin(), b->end());
  set_num_threads(2);
  return out;
}

// Bitwise comparison that reports the first differing index.
void expect_bitwise_equal(const std::vector<float>& a, const std::vector<float>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i)
    ASSERT_EQ(std::memcmp(&a[i], &b[i], sizeof(float)), 0) << "index " << i << ": " << a[i] << " vs " << b[i];
}

}  // namespace

TEST(Determinism, SameSeedSameWeights) { expect_bitwise_equal(train(1, 2), train(1, 2)); }

TEST(Determinism, OneThreadAndTwoThreadsAgreeBitwise) { expect_bitwise_equal(train(1, 1), train(1, 2)); }

TEST(Determinism, AnotherSeedGivesOtherWeights) {
  // The control: the comparison above would pass trivially if training did nothing.
  auto a = train(1, 2), b = train(2, 2);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_NE(a, b);
}

TEST(Determinism, AdamOnALargeTensorAgreesAcrossThreads) {
  // Above the optimizer's threshold for splitting the update over the workers.
  auto run = [](int threads) {
    set_num_threads(threads);
    Rng rng(9);
    Tensor<float> w({300001});
    for (auto& v : w) v = float(rng.normal());
    Var<float> p(w, true);
    Adam<float> opt({p}, {.lr = 1e-2, .weight_decay = 1e-3});
    for (int step = 0; step < 3; ++step) {
      auto& g = p.grad_buffer();
      for (auto& v : g) v = float(rng.normal());
      opt.step();
    }
    std::vector<float> out(p.value().begin(), p.value().end());
    set_num_threads(2);
    return out;
  };
  expect_bitwise_equal(run(1), run(2));
}
