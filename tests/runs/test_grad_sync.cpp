// --accumulate K in one process (runs/distributed/grad_sync.h): the step's gradient is
// exactly the left fold, in micro-batch order, of the K micro-batch gradients (each
// computed alone into cleared buffers), divided by K in float; with buckets and the
// backward hooks armed, and with dropout drawing micro-batch m's masks from the step's
// generators forked at m. It also matches the full batch's gradient to rounding (the
// mean of K micro-batch means is the batch mean). The MPI runs (N = 1, 2, 3) are tested
// against this one-process definition in tests/distributed.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "core/autograd.h"
#include "nn/dropout.h"
#include "nn/functional/activations.h"
#include "nn/functional/linear.h"
#include "nn/linear.h"
#include "nn/losses/mse.h"
#include "runs/distributed/grad_sync.h"

namespace {

using namespace nns;

struct Net : Module<float> {
  explicit Net(Rng& rng) {
    a = register_module("a", std::make_shared<Linear<float>>(rng, 5, 16));
    drop = register_module("drop", std::make_shared<Dropout<float>>(0.3, 7));
    b = register_module("b", std::make_shared<Linear<float>>(rng, 16, 16));
    c = register_module("c", std::make_shared<Linear<float>>(rng, 16, 1));
  }
  Var<float> forward(const Var<float>& x) override {
    return c->forward(tanh(b->forward(drop->forward(tanh(a->forward(x))))));
  }
  std::shared_ptr<Linear<float>> a, b, c;
  std::shared_ptr<Dropout<float>> drop;
};

struct Batch {
  Tensor<float> x, y;
};
Batch rows(const Batch& all, int64_t begin, int64_t n) {
  Batch b{Tensor<float>({n, 5}), Tensor<float>({n, 1})};
  std::memcpy(b.x.data(), all.x.data() + begin * 5, sizeof(float) * size_t(n * 5));
  std::memcpy(b.y.data(), all.y.data() + begin, sizeof(float) * size_t(n));
  return b;
}
Batch random_batch(int64_t n, uint64_t seed) {
  Rng r(seed);
  Batch b{Tensor<float>({n, 5}), Tensor<float>({n, 1})};
  for (int64_t i = 0; i < b.x.numel(); ++i) b.x[i] = float(r.uniform() * 2 - 1);
  for (int64_t i = 0; i < n; ++i) b.y[i] = float(r.uniform());
  return b;
}
float loss_and_backward(Net& net, const Batch& b) {
  net.zero_grad();
  Var<float> l = mse_loss(net.forward(Var<float>(b.x)), Var<float>(b.y));
  l.backward();
  return l.value()[0];
}
std::vector<std::vector<float>> grads(Net& net) {
  std::vector<std::vector<float>> g;
  for (auto& p : net.parameters()) g.emplace_back(p.grad().data(), p.grad().data() + p.numel());
  return g;
}

// The definition, written out: per micro-batch gradients, folded left, divided by K.
std::vector<std::vector<float>> by_definition(Net& net, const Batch& all, int K, int64_t mb) {
  const Rng step = *net.drop->named_rngs()[0].second;
  std::vector<std::vector<float>> acc;
  for (int m = 0; m < K; ++m) {
    net.drop->named_rngs()[0].second->set_state(step.fork(uint64_t(m)).state());
    loss_and_backward(net, rows(all, m * mb, mb));
    auto g = grads(net);
    if (m == 0) {
      acc = g;
      continue;
    }
    for (size_t i = 0; i < g.size(); ++i)
      for (size_t e = 0; e < g[i].size(); ++e) acc[i][e] += g[i][e];
  }
  for (auto& v : acc)
    for (auto& e : v) e /= float(K);
  return acc;
}

std::vector<std::vector<float>> accumulated(Net& net, const Batch& all, int K, int64_t mb, double bucket_mb,
                                            std::vector<double>* mean_loss = nullptr) {
  std::vector<Rng*> rngs;
  for (auto& [n, r] : net.named_rngs()) rngs.push_back(r);
  runs::GradSync sync(net.parameters(), rngs, K, bucket_mb);
  EXPECT_TRUE(sync.active());
  std::vector<std::vector<double>> losses;
  for (int m = sync.mine().begin; m < sync.mine().end; ++m) {
    sync.begin_micro(m);
    losses.push_back({loss_and_backward(net, rows(all, m * mb, mb))});
    sync.end_micro(m);
  }
  sync.finish_step();
  if (mean_loss) *mean_loss = sync.mean_over_micro(losses);
  return grads(net);
}

TEST(GradSync, AccumulatedGradientIsTheOrderedMeanOfMicroBatchGradients) {
  const Batch all = random_batch(12, 3);
  for (int K : {2, 3, 4}) {
    for (double bucket_mb : {0.0, 1e-4}) {  // one bucket; buckets of ~26 floats (hooks start them)
      Rng r1(11), r2(11);
      Net a(r1), b(r2);
      const auto want = by_definition(a, all, K, 12 / K);
      const auto got = accumulated(b, all, K, 12 / K, bucket_mb);
      ASSERT_EQ(want.size(), got.size());
      for (size_t i = 0; i < want.size(); ++i)
        for (size_t e = 0; e < want[i].size(); ++e)
          ASSERT_EQ(std::memcmp(&want[i][e], &got[i][e], sizeof(float)), 0)
              << "K " << K << " bucket " << bucket_mb << " parameter " << i << " element " << e << ": " << want[i][e]
              << " vs " << got[i][e];
    }
  }
}

TEST(GradSync, DropoutGeneratorsAdvanceOneDrawPerStep) {
  const Batch all = random_batch(8, 4);
  Rng r(5);
  Net net(r);
  Rng* g = net.drop->named_rngs()[0].second;
  Rng start = *g;
  accumulated(net, all, 2, 4, 0);
  start.next_u64();
  EXPECT_EQ(g->state(), start.state());
}

TEST(GradSync, MatchesTheFullBatchGradientToRounding) {
  // Without dropout (its masks differ by construction) the mean of the micro-batch means
  // is the batch mean: the gradients agree to float rounding, not bitwise.
  const Batch all = random_batch(12, 6);
  Rng r1(9), r2(9);
  Net full(r1), acc(r2);
  full.drop->eval();
  acc.drop->eval();
  const float batch_loss = loss_and_backward(full, all);
  const auto want = grads(full);
  std::vector<double> mean_loss;
  const auto got = accumulated(acc, all, 3, 4, 1e-4, &mean_loss);
  EXPECT_NEAR(mean_loss[0], batch_loss, 1e-6 * std::abs(batch_loss));
  double worst = 0;
  for (size_t i = 0; i < want.size(); ++i)
    for (size_t e = 0; e < want[i].size(); ++e)
      worst = std::max(worst, double(std::abs(want[i][e] - got[i][e])) / (1e-3 + std::abs(want[i][e])));
  EXPECT_LT(worst, 1e-5);
}

TEST(GradSync, RefusesFewerMicroBatchesThanOne) {
  Rng r(1);
  Net net(r);
  EXPECT_THROW(runs::GradSync(net.parameters(), {}, 0, 1), std::invalid_argument);
  EXPECT_FALSE(runs::GradSync(net.parameters(), {}, 1, 1).active());  // K = 1: the plain step
}

TEST(GradSync, MeanOverMicroBatchesFoldsInOrder) {
  Rng r(1);
  Net net(r);
  runs::GradSync sync(net.parameters(), {}, 3, 1);
  const auto m = sync.mean_over_micro({{0.1, 1e16}, {0.2, 1.0}, {0.3, -1e16}});
  EXPECT_EQ(m[0], ((0.1 + 0.2) + 0.3) / 3);
  EXPECT_EQ(m[1], ((1e16 + 1.0) + -1e16) / 3);  // 0: the order is visible in the result
}

}  // namespace
