#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "nn/batchnorm.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

namespace {
VarD rv(const Shape& s, Rng& rng, double scale = 1.0) { return VarD(random_tensor(s, rng, scale), true); }
VarD gamma_near_one(int64_t C, Rng& rng) {
  TensorD t({C});
  for (auto& v : t) v = 1 + 0.3 * rng.normal();
  return VarD(t, true);
}
}  // namespace

TEST(BatchNorm, TrainForwardAndRunningStatsHandComputed) {
  // One channel, values 1, 2, 3, 6: mean 3, biased var 3.5, unbiased var 14/3.
  Var<double> x(Tensor<double>::from({4, 1}, {1, 2, 3, 6}));
  Var<double> g(Tensor<double>::from({1}, {2})), b(Tensor<double>::from({1}, {0.5}));
  TensorD rm = TensorD::zeros({1}), rvar = TensorD::ones({1});
  auto y = batch_norm(x, g, b, &rm, &rvar, true, 0.1, 1e-5);
  const double rstd = 1 / std::sqrt(3.5 + 1e-5);
  EXPECT_NEAR(y.value()[0], 2 * (1 - 3) * rstd + 0.5, 1e-12);
  EXPECT_NEAR(y.value()[3], 2 * (6 - 3) * rstd + 0.5, 1e-12);
  EXPECT_NEAR(rm[0], 0.9 * 0 + 0.1 * 3, 1e-12);
  EXPECT_NEAR(rvar[0], 0.9 * 1 + 0.1 * 14.0 / 3, 1e-12);
  // Eval uses the running statistics.
  auto e = batch_norm(x, g, b, &rm, &rvar, false, 0.1, 1e-5);
  EXPECT_NEAR(e.value()[1], 2 * (2 - rm[0]) / std::sqrt(rvar[0] + 1e-5) + 0.5, 1e-12);
}

TEST(BatchNorm, RunningStats2dOverBatchAndSpace) {
  // (N=2, C=2, 1x2): channel 0 holds 0,2 | 4,6; channel 1 holds 1,1 | 1,1.
  Var<float> x(Tensor<float>::from({2, 2, 1, 2}, {0, 2, 1, 1, 4, 6, 1, 1}));
  BatchNorm2d<float> bn(2, 1e-5, 0.5);
  bn.forward(x);
  EXPECT_FLOAT_EQ((*bn.running_mean)[0], 0.5f * 3);
  EXPECT_FLOAT_EQ((*bn.running_mean)[1], 0.5f * 1);
  EXPECT_FLOAT_EQ((*bn.running_var)[0], 0.5f + 0.5f * 20.0f / 3);  // unbiased: 20/3
  EXPECT_FLOAT_EQ((*bn.running_var)[1], 0.5f);
}

TEST(BatchNorm, GradCheckTrain2d) {
  Rng rng(41);
  std::vector<VarD> in = {rv({3, 2, 3, 5}, rng), gamma_near_one(2, rng), rv({2}, rng)};
  gradcheck([](std::vector<VarD>& v) { return batch_norm(v[0], v[1], v[2], nullptr, nullptr, true); }, in);
}

TEST(BatchNorm, GradCheckTrain1d) {
  Rng rng(42);
  std::vector<VarD> in = {rv({5, 3}, rng), gamma_near_one(3, rng), rv({3}, rng)};
  gradcheck([](std::vector<VarD>& v) { return batch_norm(v[0], v[1], v[2], nullptr, nullptr, true); }, in);
}

TEST(BatchNorm, GradCheckNoAffine) {
  Rng rng(43);
  std::vector<VarD> in = {rv({2, 3, 2, 3}, rng)};
  gradcheck([](std::vector<VarD>& v) { return batch_norm(v[0], VarD(), VarD(), nullptr, nullptr, true); }, in);
}

TEST(BatchNorm, GradCheckEval) {
  Rng rng(44);
  TensorD rm = random_tensor({3}, rng), rvar = TensorD::full({3}, 0.7);
  std::vector<VarD> in = {rv({2, 3, 2, 2}, rng), gamma_near_one(3, rng), rv({3}, rng)};
  gradcheck([&](std::vector<VarD>& v) { return batch_norm(v[0], v[1], v[2], &rm, &rvar, false); }, in);
}

TEST(BatchNorm, BatchOneSpatialOneInTrainMode) {
  // pix2pix trains at batch 1; a 1x1 map then has one value per channel: variance 0.
  Rng rng(45);
  std::vector<VarD> in = {rv({1, 4, 1, 1}, rng), gamma_near_one(4, rng), rv({4}, rng)};
  TensorD rm = TensorD::zeros({4}), rvar = TensorD::ones({4});
  auto y = batch_norm(in[0], in[1], in[2], &rm, &rvar, true);
  for (int c = 0; c < 4; ++c) {
    EXPECT_DOUBLE_EQ(y.value()[c], in[2].value()[c]);  // output = beta
    EXPECT_TRUE(std::isfinite(rvar[c]));
  }
  gradcheck([](std::vector<VarD>& v) { return batch_norm(v[0], v[1], v[2], nullptr, nullptr, true); }, in);
  // BatchNorm1d at batch 1 too.
  std::vector<VarD> in1 = {rv({1, 3}, rng), gamma_near_one(3, rng), rv({3}, rng)};
  gradcheck([](std::vector<VarD>& v) { return batch_norm(v[0], v[1], v[2], nullptr, nullptr, true); }, in1);
}

TEST(BatchNorm, ModuleModeAndNames) {
  BatchNorm2d<float> bn(3);
  auto names = bn.named_parameters();
  ASSERT_EQ(names.size(), 2u);
  EXPECT_EQ(names[0].first, "weight");
  EXPECT_EQ(names[1].first, "bias");
  auto bufs = bn.named_buffers();
  ASSERT_EQ(bufs.size(), 2u);
  EXPECT_EQ(bufs[0].first, "running_mean");
  EXPECT_EQ(bufs[1].first, "running_var");
  EXPECT_EQ(BatchNorm1d<float>(3, 1e-5, 0.1, false).named_parameters().size(), 0u);
  // Eval at batch 1 uses running stats (mean 0, var 1): output = x / sqrt(1 + eps).
  bn.eval();
  Var<float> x(Tensor<float>::from({1, 3, 1, 1}, {1, 2, 3}));
  auto y = bn.forward(x);
  EXPECT_NEAR(y.value()[2], 3 / std::sqrt(1 + 1e-5), 1e-6);
  EXPECT_FLOAT_EQ((*bn.running_mean)[0], 0);  // untouched in eval
  EXPECT_THROW(bn.forward(Var<float>(Tensor<float>::zeros({2, 3}))), std::invalid_argument);
}

TEST(BatchNorm, DeterministicAcrossThreadCounts) {
  Rng rng(46);
  Tensor<float> x({2, 16, 48, 48}), g({2, 16, 48, 48});
  for (auto& v : x) v = float(rng.normal(0.5, 2));
  for (auto& v : g) v = float(rng.normal());
  auto run = [&](int threads) {
    set_num_threads(threads);
    BatchNorm2d<float> bn(16);
    Var<float> vx(x.clone(), true);
    Var<float> y = bn.forward(vx);
    y.backward(g);
    std::vector<float> all(y.value().begin(), y.value().end());
    all.insert(all.end(), vx.grad().begin(), vx.grad().end());
    all.insert(all.end(), bn.weight.grad().begin(), bn.weight.grad().end());
    all.insert(all.end(), bn.running_var->begin(), bn.running_var->end());
    return all;
  };
  auto one = run(1), two = run(2);
  EXPECT_EQ(0, std::memcmp(one.data(), two.data(), one.size() * sizeof(float)));
}
