#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/kernels/gemm_precision.h"
#include "models/nnao/nnao_fast_step.h"
#include "models/nnao/nnao_loss.h"
#include "models/nnao/nnao_model.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::testing;

TEST(NnaoModel, ShapesAndParameterNames) {
  Rng rng(1);
  nnao::NnaoNet<float> net(rng, {31, 4, 0.5});
  // The paper's theta: W0 (3844x4), W1, W2 (4x4), W3 (4x1), biases, alpha, beta.
  EXPECT_EQ(net.parameter_count(), 3844 * 4 + 4 + 2 * (16 + 4) + 4 + 1 + 2 * (4 * 3 + 1));
  std::vector<std::string> names;
  for (auto& [n, v] : net.named_parameters()) names.push_back(n);
  EXPECT_EQ(names.front(), "fc0.weight");
  net.eval();
  Var<float> y = net.forward(Var<float>(Tensor<float>::zeros({3, 3844})));
  EXPECT_EQ(y.shape(), (Shape{3, 1}));
}

TEST(NnaoModel, GradCheckWholeNetworkAndLoss) {
  // Dropout off (p = 0) so the function is deterministic; the L1 term is included.
  Rng rng(3);
  nnao::NnaoNet<double> net(rng, {3, 3, 0.0});
  auto params = net.parameters();
  std::vector<VarD> in = {VarD(random_tensor({5, 36}, rng), true)};
  for (auto& p : params) in.push_back(p);
  TensorD y = random_tensor({5, 1}, rng);
  gradcheck([&](std::vector<VarD>& v) { return nnao::nnao_loss(net.forward(v[0]), VarD(y), params, 0.01); }, in);
}

namespace {

// The fused step against the autograd graph on the same batch and dropout mask, in the
// given precision; *grads gets the fused step's gradients.
void check_fused_matches_autograd(Precision precision, std::vector<std::vector<float>>* grads = nullptr) {
  const ScopedGemmPrecision mode(precision);
  const int w = 9, H = 4, B = 16;
  const int64_t F = int64_t(w) * w * 4;
  Rng init_a(5), init_b(5);
  nnao::NnaoNet<float> a(init_a, {w, H, 0.5}), b(init_b, {w, H, 0.5});
  Rng data(9);
  std::vector<float> x(static_cast<size_t>(B * F)), y(static_cast<size_t>(B));
  for (auto& v : x) v = float(data.normal());
  for (auto& v : y) v = float(data.normal());
  // Reference: the autograd graph.
  Tensor<float> xt({B, F}), yt({B, 1});
  std::copy(x.begin(), x.end(), xt.data());
  std::copy(y.begin(), y.end(), yt.data());
  auto pa = a.parameters();
  Var<float> loss = nnao::nnao_loss(a.forward(Var<float>(xt)), Var<float>(yt), pa, 0.01f);
  loss.backward();
  // Fused.
  nnao::NnaoFastStep fast(b, B);
  float lf = fast.forward_backward(x.data(), y.data(), 0.01f);
  EXPECT_NEAR(lf, loss.value()[0], 1e-4 * std::abs(loss.value()[0]));
  auto pb = b.parameters();
  ASSERT_EQ(pa.size(), pb.size());
  for (size_t i = 0; i < pa.size(); ++i) {
    ASSERT_TRUE(pa[i].grad().defined());
    const auto& ga = pa[i].grad();
    const auto& gb = pb[i].grad();
    double scale = 1e-6;
    for (int64_t k = 0; k < ga.numel(); ++k) scale = std::max(scale, double(std::abs(ga[k])));
    for (int64_t k = 0; k < ga.numel(); ++k)
      ASSERT_NEAR(gb[k], ga[k], 1e-4 * scale) << "parameter " << i << " index " << k;
  }
  // Both drew one seed from their dropout Rng: the generators stay in step.
  EXPECT_EQ(a.named_rngs()[0].second->state(), b.named_rngs()[0].second->state());
  if (grads)
    for (auto& p : pb) grads->emplace_back(p.grad().data(), p.grad().data() + p.grad().numel());
}

}  // namespace

TEST(NnaoModel, FusedStepMatchesAutograd) { check_fused_matches_autograd(Precision::fp32); }

// --precision bf16: both paths round the same operands (the fused step itself, the
// autograd path in its GEMMs), so they agree as closely as in fp32 — and differ from fp32
// by far more than that, so a path that skipped the rounding could not pass.
TEST(NnaoModel, FusedStepMatchesAutogradInBf16) {
  std::vector<std::vector<float>> bf16, fp32;
  check_fused_matches_autograd(Precision::bf16, &bf16);
  check_fused_matches_autograd(Precision::fp32, &fp32);
  ASSERT_EQ(bf16.size(), fp32.size());
  double worst = 0;
  for (size_t i = 0; i < bf16.size(); ++i) {
    double scale = 1e-6;
    for (float g : fp32[i]) scale = std::max(scale, double(std::abs(g)));
    for (size_t k = 0; k < bf16[i].size(); ++k)
      worst = std::max(worst, std::abs(double(bf16[i][k]) - fp32[i][k]) / scale);
  }
  EXPECT_GT(worst, 1e-3);
}
