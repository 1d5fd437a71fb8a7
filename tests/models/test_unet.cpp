#include <gtest/gtest.h>

#include <set>
#include <string>

#include "models/gi/generator.h"
#include "models/gi/unet.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::testing;

namespace {

UnetConfig tiny(int in = 3, int ngf = 2, int levels = 3) {
  UnetConfig c;
  c.in_channels = in;
  c.out_channels = 3;
  c.ngf = ngf;
  c.levels = levels;
  return c;
}

int count_with(const std::vector<std::pair<std::string, Var<float>>>& ps, const std::string& s) {
  int n = 0;
  for (auto& [name, p] : ps) n += name.find(s) != std::string::npos;
  return n;
}

}  // namespace

TEST(Unet, OutputShapeAndTanhRange) {
  Rng rng(1);
  UnetGenerator<float> g(tiny(12, 4, 4), rng);
  Rng data(2);
  Tensor<float> x({1, 12, 32, 64});
  for (auto& v : x) v = float(3 * data.normal());
  Var<float> y = g.forward(Var<float>(x));
  EXPECT_EQ(y.shape(), (Shape{1, 3, 32, 64}));
  for (float v : y.value()) {
    ASSERT_GT(v, -1.0f);
    ASSERT_LT(v, 1.0f);
  }
}

TEST(Unet, RejectsSizeNotDivisibleByTwoToTheLevels) {
  Rng rng(1);
  UnetGenerator<float> g(tiny(3, 2, 3), rng);
  EXPECT_THROW(g.forward(Var<float>(Tensor<float>::zeros({1, 3, 12, 16}))), std::invalid_argument);
  EXPECT_THROW(g.forward(Var<float>(Tensor<float>::zeros({1, 4, 16, 16}))), std::invalid_argument);
}

// Hand count for in=3... see the layer list in unet.h:
//  level 0: down 12->2 (+bias) 386, up 4->3 (+bias) 195
//  level 1: down 2->4 128, BN(4) 8, up 8->2 256, BN(2) 4
//  level 2 (innermost): down 4->8 (+bias) 520, up 8->4 512, BN(4) 8
TEST(Unet, ParameterCountByHand) {
  Rng rng(1);
  UnetGenerator<float> g(tiny(12, 2, 3), rng);
  EXPECT_EQ(g.parameter_count(), 386 + 195 + 128 + 8 + 256 + 4 + 520 + 512 + 8);
}

// The thesis's Table 4.3 counts 54,420,739 parameters for ngf 64, 8 levels, 12 -> 3
// channels, with a bias on every conv. Its table (torchinfo) leaves out the nine
// BatchNorms it marks "(recursive)" (layers 13, 16, 19, 24, 28, 32, 36: 1024 each; 39:
// 512; 42: 256 = 7936), and ours drops the bias of the 6 down convs and 7 up convs
// followed by BatchNorm (128+256+4*512 + 64+128+256+4*512 = 4928).
TEST(Unet, ThesisSizedGeneratorMatchesTable43) {
  Rng rng(1);
  UnetConfig c;  // defaults: 12 -> 3, ngf 64, 8 levels
  UnetGenerator<float> g(c, rng);
  EXPECT_EQ(g.parameter_count(), 54420739 + 7936 - 4928);
}

TEST(Unet, BiasOnlyWhereNoBatchNormFollowsAndDropoutInThreeInnermost) {
  Rng rng(1);
  UnetConfig c = tiny(12, 2, 5);
  UnetGenerator<float> g(c, rng);
  std::set<std::string> biases;
  for (auto& [name, p] : g.named_parameters())
    if (name.size() > 5 && name.ends_with(".bias") && name.find("norm") == std::string::npos) biases.insert(name);
  EXPECT_EQ(biases, (std::set<std::string>{"model.down.bias", "model.up.bias", "model.sub.sub.sub.sub.down.bias"}));
  std::set<std::string> dropouts;
  for (auto& [name, r] : g.named_rngs()) dropouts.insert(name);
  EXPECT_EQ(dropouts, (std::set<std::string>{"model.sub.sub.dropout.rng", "model.sub.sub.sub.dropout.rng",
                                             "model.sub.sub.sub.sub.dropout.rng"}));
  // BN on every level but the outermost and innermost down convs; on every up but the last.
  auto ps = g.named_parameters();
  EXPECT_EQ(count_with(ps, "down_norm.weight"), 3);
  EXPECT_EQ(count_with(ps, "up_norm.weight"), 4);
}

TEST(Unet, TestModesAreExplicit) {
  Rng rng(3);
  UnetGenerator<float> g(tiny(3, 4, 3), rng);
  Rng data(4);
  Tensor<float> x({1, 3, 16, 16});
  for (auto& v : x) v = float(data.normal());
  NoGradGuard ng;
  // Dropout on: two passes differ. Off: identical.
  g.set_test_modes(/*bn_batch_stats=*/true, /*dropout_on=*/true);
  auto a = g.forward(Var<float>(x)).value().clone();
  auto b = g.forward(Var<float>(x)).value().clone();
  bool differ = false;
  for (int64_t i = 0; i < a.numel(); ++i) differ |= a[i] != b[i];
  EXPECT_TRUE(differ);
  g.set_test_modes(true, false);
  a = g.forward(Var<float>(x)).value().clone();
  b = g.forward(Var<float>(x)).value().clone();
  for (int64_t i = 0; i < a.numel(); ++i) ASSERT_EQ(a[i], b[i]);
  // Running statistics (fresh: mean 0, var 1) give another answer than batch statistics.
  g.set_test_modes(false, false);
  auto c = g.forward(Var<float>(x)).value().clone();
  differ = false;
  for (int64_t i = 0; i < a.numel(); ++i) differ |= a[i] != c[i];
  EXPECT_TRUE(differ);
  g.train();
  EXPECT_TRUE(g.is_training());
}

// Whole-network gradient in double, training mode (BN with batch statistics at batch 1,
// dropout with a fixed mask: the generators are re-seeded before every evaluation).
TEST(Unet, GradCheckWholeNetwork) {
  Rng rng(5);
  UnetGenerator<double> g(tiny(3, 2, 3), rng);
  std::vector<Rng::State> rng_states;
  for (auto& [name, r] : g.named_rngs()) rng_states.push_back(r->state());
  std::vector<VarD> inputs = {VarD(random_tensor({1, 3, 8, 8}, rng), true)};
  // pix2pix's N(0, 0.02) weights make every gradient smaller than gradcheck's absolute
  // floor (1e-7), where any answer passes: use O(1) gradients instead.
  for (auto& p : g.parameters()) {
    VarD q = p;
    if (q.shape().dim() >= 2) q.value() = random_tensor(q.shape(), rng, 0.4);
    else q.value() = random_tensor(q.shape(), rng, 0.5);
    inputs.push_back(q);
  }
  gradcheck(
      [&](std::vector<VarD>& in) {
        size_t i = 0;
        for (auto& [name, r] : g.named_rngs()) r->set_state(rng_states[i++]);
        return g.forward(in[0]);
      },
      inputs);
}

// The frame-level head (--level-head): drawn after the U-Net and started at gain 1, so a
// generator with it predicts exactly what the same seed's generator without it does.
TEST(Unet, LevelHeadStartsAtGainOneAndLeavesTheUnetAlone) {
  GeneratorConfig with, without;
  with.unet = without.unet = tiny(10, 2, 2);
  with.unet.level_head = 4;
  with.residual = without.residual = GiResidual::linear;
  with.hdr_scale = without.hdr_scale = 0.7f;
  Rng r1(3), r2(3), rx(4);
  auto a = make_generator<float>(with, r1);
  auto b = make_generator<float>(without, r2);
  EXPECT_EQ(a->parameter_count(), b->parameter_count() + (20 * 4 + 4) + (4 * 3 + 3));
  const TensorD xd = random_tensor({1, 10, 8, 8}, rx, 0.8);
  Tensor<float> xf(xd.shape());
  for (int64_t i = 0; i < xd.numel(); ++i) xf[i] = float(xd[i]);
  Var<float> x(std::move(xf));
  Tensor<float> ya = generate(*a, with, x).value(), yb = generate(*b, without, x).value();
  for (int64_t i = 0; i < ya.numel(); ++i) ASSERT_EQ(ya[i], yb[i]) << i;
  EXPECT_FALSE(b->level_gain(x).defined());
  Tensor<float> g = a->level_gain(x).value();
  EXPECT_EQ(g.shape(), (Shape{1, 3, 1, 1}));
  for (float v : g) EXPECT_EQ(v, 1.0f);
}

// The features the head reads, on a view whose halves differ: the moments of every
// channel, and the log mean of the linear lumination and of albedo x lumination, the
// Reinhard mapping undone in units of k.
TEST(Unet, FrameLevelFeaturesAreTheMomentsAndTheLogLightEnergy) {
  const int64_t C = 10, H = 2, W = 4, n = H * W;
  Tensor<double> x({1, C, H, W});
  for (int64_t c = 0; c < C; ++c)
    for (int64_t i = 0; i < n; ++i) x[c * n + i] = 0.1 * double(c) - 0.5 + (i < n / 2 ? 0.2 : -0.2);
  // colour channel c: albedo 0.25 (left) / 0.75 (right); light u = 0.5 -> 1 k, u = 0.8 -> 4 k
  for (int c = 0; c < 3; ++c)
    for (int64_t i = 0; i < n; ++i) {
      const bool left = i % W < W / 2;
      x[(kAlbedoChannel + c) * n + i] = left ? -0.5 : 0.5;
      x[(kLuminationChannel + c) * n + i] = left ? 0.0 : 0.6;
    }
  const Tensor<double> plain = frame_level_features(x, false), f = frame_level_features(x, true);
  ASSERT_EQ(plain.shape(), (Shape{1, 2 * C}));
  ASSERT_EQ(f.shape(), (Shape{1, 2 * C + 6}));
  for (int64_t c = 0; c < C; ++c) {
    double m = 0, q = 0;
    for (int64_t i = 0; i < n; ++i) m += x[c * n + i], q += x[c * n + i] * x[c * n + i];
    EXPECT_NEAR(f[c], m / double(n), 1e-12) << c;
    EXPECT_NEAR(f[C + c], q / double(n), 1e-12) << c;
    EXPECT_EQ(f[c], plain[c]);
    EXPECT_EQ(f[C + c], plain[C + c]);
  }
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(f[2 * C + c], std::log((1.0 + 4.0) / 2 + 1e-3), 1e-9) << c;
    EXPECT_NEAR(f[2 * C + 3 + c], std::log((0.25 * 1.0 + 0.75 * 4.0) / 2 + 1e-3), 1e-9) << c;
  }
  EXPECT_THROW(frame_level_features(Tensor<double>({1, 9, 2, 2}), true), std::invalid_argument);
}

// The head's parameters and the U-Net's, through the linear residual, in double, with
// and without the energy features. The head reads the input's statistics as data (no
// gradient flows back into the input). Step 1e-4: with the energy the loss is large
// against some of these gradients (~1e-3), and at 1e-6 the central difference's
// round-off (~1e-16 of the loss / eps) reached 1e-4 of them, shrinking as eps grew
// (1.4e-4 at 1e-6, 2e-5 at 1e-5, 2.4e-6 at 1e-4): round-off, not a wrong gradient.
TEST(Unet, LevelHeadGradCheckThroughTheLinearResidual) {
  for (bool energy : {false, true}) {
    SCOPED_TRACE(energy ? "energy" : "moments");
    GeneratorConfig gc;
    gc.unet = tiny(10, 2, 2);
    gc.unet.level_head = 3;
    gc.unet.level_energy = energy;
    gc.residual = GiResidual::linear;
    gc.hdr_scale = 0.7f;
    Rng rng(6);
    auto g = make_generator<double>(gc, rng);
    std::vector<Rng::State> rng_states;
    for (auto& [name, r] : g->named_rngs()) rng_states.push_back(r->state());
    const VarD x(random_tensor({1, 10, 8, 8}, rng, 0.8));
    std::vector<VarD> inputs;
    for (auto& p : g->parameters()) {  // O(1) weights: see GradCheckWholeNetwork
      VarD q = p;
      q.value() = random_tensor(q.shape(), rng, q.shape().dim() >= 2 ? 0.4 : 0.5);
      inputs.push_back(q);
    }
    gradcheck(
        [&](std::vector<VarD>&) {
          size_t i = 0;
          for (auto& [name, r] : g->named_rngs()) r->set_state(rng_states[i++]);
          return generate(*g, gc, x);
        },
        inputs, /*tol=*/1e-6, /*eps=*/1e-4);
  }
}

// --g-norm none: no BatchNorm (no buffers), a bias on every conv; same hand count as
// ParameterCountByHand minus the BN parameters (8 + 4 + 8) plus the biases of the three
// convs that lost their BN (level 1 down 4, up 2; level 2 up 4).
TEST(Unet, WithoutBatchNormEveryConvHasABias) {
  Rng rng(1);
  UnetConfig c = tiny(12, 2, 3);
  c.batchnorm = false;
  UnetGenerator<float> g(c, rng);
  EXPECT_EQ(g.parameter_count(), 386 + 195 + 128 + 256 + 520 + 512 + 4 + 2 + 4);
  EXPECT_TRUE(g.named_buffers().empty());
  int biases = 0;
  for (auto& [name, p] : g.named_parameters()) biases += name.ends_with(".bias");
  EXPECT_EQ(biases, 6);
}
