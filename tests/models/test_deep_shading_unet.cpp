// Deep Shading's U-Net (models/gi/deep_shading_unet.h) and the generator factory with
// the residual output (models/gi/generator.h).
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "models/gi/generator.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::testing;

namespace {

DeepShadingConfig tiny(int in = 3, int u0 = 2, int levels = 3) {
  DeepShadingConfig c;
  c.in_channels = in;
  c.u0 = u0;
  c.levels = levels;
  return c;
}

}  // namespace

TEST(DeepShadingUnet, OutputShapeAndTanhRange) {
  Rng rng(1);
  DeepShadingUnet<float> g(tiny(12, 4, 4), rng);
  Rng data(2);
  Tensor<float> x({1, 12, 16, 32});
  for (auto& v : x) v = float(3 * data.normal());
  Var<float> y = g.forward(Var<float>(x));
  EXPECT_EQ(y.shape(), (Shape{1, 3, 16, 32}));
  for (float v : y.value()) {
    ASSERT_GT(v, -1.0f);
    ASSERT_LT(v, 1.0f);
  }
  EXPECT_EQ(g.size_multiple(), 8);
  EXPECT_THROW(g.forward(Var<float>(Tensor<float>::zeros({1, 12, 12, 32}))), std::invalid_argument);
}

// 3x3 convs with bias, widths 2, 4, 8 on levels 0..2:
//  down: 3->2 (54+2), 2->4 (72+4), 4->8 (288+8)
//  up:   level 1: 8+4 -> 4 (432+4), level 0: 4+2 -> 3 out (162+3)
TEST(DeepShadingUnet, ParameterCountByHand) {
  Rng rng(1);
  DeepShadingUnet<float> g(tiny(3, 2, 3), rng);
  EXPECT_EQ(g.parameter_count(), 56 + 76 + 296 + 436 + 165);
  // No BatchNorm buffers, no dropout generators.
  EXPECT_TRUE(g.named_buffers().empty());
  EXPECT_TRUE(g.named_rngs().empty());
}

// The net is a function of its input alone: pooling and upsampling really resample (a
// change in one corner pixel reaches the far corner only through the coarse levels).
TEST(DeepShadingUnet, CoarseLevelsCarryInformationAcrossTheImage) {
  Rng rng(3);
  DeepShadingUnet<float> g(tiny(1, 4, 4), rng);
  Tensor<float> x = Tensor<float>::zeros({1, 1, 16, 16});
  NoGradGuard ng;
  auto a = g.forward(Var<float>(x)).value().clone();
  x[0] = 5.0f;
  auto b = g.forward(Var<float>(x)).value().clone();
  const int64_t far = 15 * 16 + 15;  // the opposite corner, 3x3 convs alone reach 2 px per level
  EXPECT_NE(a[far], b[far]);
}

TEST(DeepShadingUnet, GradCheckWholeNetwork) {
  Rng rng(5);
  DeepShadingUnet<double> g(tiny(3, 2, 3), rng);
  std::vector<VarD> inputs = {VarD(random_tensor({1, 3, 8, 8}, rng), true)};
  for (auto& p : g.parameters()) {
    VarD q = p;
    q.value() = random_tensor(q.shape(), rng, 0.4);
    inputs.push_back(q);
  }
  // The whole network's loss carries more round-off than one layer's: built without
  // FMA contraction (-DNNSHADE_NATIVE=OFF) a 1.5e-5 gradient's central difference was off
  // by 1.2e-8, just past the default abs_tol of 1e-8. 3e-8 still fails any real mistake.
  gradcheck([&](std::vector<VarD>& in) { return g.forward(in[0]); }, inputs, 1e-6, 1e-6, 3e-8);
}

// With every weight of the net's last conv zeroed, G = tanh(0) = 0 and
//  residual mapped: prediction = lumination channels (7-9) exactly;
//  residual linear: prediction = map(unmap(lum) + k * 0.5 / (0.5 + eps));
//  residual off:    prediction = 0.
TEST(GiGenerator, ResidualAddsTheInputLight) {
  for (GiArch arch : {GiArch::pix2pix, GiArch::deepshading}) {
    GeneratorConfig c;
    c.arch = arch;
    c.unet.in_channels = 12;
    c.unet.ngf = 2;
    c.unet.levels = 2;
    c.residual = GiResidual::mapped;
    c.hdr_scale = 0.5f;
    Rng rng(7);
    auto g = make_generator<float>(c, rng);
    for (auto& [name, p] : g->named_parameters())
      if (name == "model.up.weight" || name == "model.up.bias" || name == "up0.weight" || name == "up0.bias")
        p.value().fill(0.0f);
    Tensor<float> x({1, 12, 8, 8});
    Rng data(8);
    for (auto& v : x) v = float(data.uniform() * 2 - 1);
    NoGradGuard ng;
    g->set_test_modes(true, false);
    Tensor<float> y = generate(*g, c, Var<float>(x)).value();
    ASSERT_EQ(y.shape(), (Shape{1, 3, 8, 8}));
    for (int64_t i = 0; i < y.numel(); ++i) ASSERT_EQ(y[i], x[7 * 64 + i]) << arch_name(arch) << " " << i;
    c.residual = GiResidual::linear;
    Tensor<float> w = generate(*g, c, Var<float>(x)).value();
    const double k = 0.5, ind = k * 0.5 / (0.5 + GeneratorConfig::kLinearEps);
    for (int64_t i = 0; i < w.numel(); ++i) {
      double u = 0.5 * (x[7 * 64 + i] + 1.0), lum = k * u / (1 - u), light = lum + ind;
      ASSERT_NEAR(w[i], 2 * light / (light + k) - 1, 1e-5) << arch_name(arch) << " " << i;
    }
    c.residual = GiResidual::off;
    Tensor<float> z = generate(*g, c, Var<float>(x)).value();
    for (int64_t i = 0; i < z.numel(); ++i) ASSERT_EQ(z[i], 0.0f);
  }
}

// Both residual paths' gradients reach G's parameters (the data is a constant).
TEST(GiGenerator, ResidualGradCheck) {
  for (GiResidual mode : {GiResidual::mapped, GiResidual::linear}) {
    GeneratorConfig c;
    c.arch = GiArch::deepshading;
    c.unet.in_channels = 10;
    c.unet.ngf = 2;
    c.unet.levels = 1;
    c.residual = mode;
    c.hdr_scale = 0.7f;
    Rng rng(9);
    auto g = make_generator<double>(c, rng);
    std::vector<VarD> inputs = {VarD(random_tensor({1, 10, 4, 4}, rng), false)};
    for (auto& p : g->parameters()) {
      VarD q = p;
      q.value() = random_tensor(q.shape(), rng, 0.4);
      inputs.push_back(q);
    }
    gradcheck([&](std::vector<VarD>& in) { return generate(*g, c, in[0]); }, inputs);
  }
}

TEST(GiGenerator, ResidualNeedsTheLuminationChannels) {
  GeneratorConfig c;
  c.unet.in_channels = 6;
  c.residual = GiResidual::linear;
  Rng rng(1);
  EXPECT_THROW(make_generator<float>(c, rng), std::invalid_argument);
}
