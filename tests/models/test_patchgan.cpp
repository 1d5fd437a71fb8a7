#include <gtest/gtest.h>

#include "models/gi/patchgan.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::testing;

TEST(PatchGan, OutputShapeIsPix2pixs30x30At256) {
  Rng rng(1);
  PatchGan<float> d({15, 8, 3}, rng);
  Var<float> y = d.forward(Var<float>(Tensor<float>::zeros({1, 15, 256, 256})));
  EXPECT_EQ(y.shape(), (Shape{1, 1, 30, 30}));
  y = d.forward(Var<float>(Tensor<float>::zeros({2, 15, 64, 96})));
  EXPECT_EQ(y.shape(), (Shape{2, 1, 6, 10}));
}

// Table 4.5 of the thesis: 2,778,817 parameters for 15 channels, ndf 64, 3 layers, with
// a bias on every conv; ours has none on the three convs followed by BN (128+256+512).
TEST(PatchGan, ThesisSizedDiscriminatorMatchesTable45MinusBiases) {
  Rng rng(1);
  PatchGan<float> d({15, 64, 3}, rng);
  EXPECT_EQ(d.parameter_count(), 2778817 - (128 + 256 + 512));
}

// One logit of the 3-layer PatchGAN sees a 70x70 patch: measured by back-propagating
// from a single central logit (eval mode: BN with running statistics does not mix
// pixels) and finding the extent of the non-zero input gradient.
TEST(PatchGan, ReceptiveFieldIs70) {
  EXPECT_EQ(PatchGan<float>::receptive_field(3), 70);
  Rng rng(2);
  PatchGan<double> d({1, 4, 3}, rng);
  d.eval();
  VarD x(random_tensor({1, 1, 160, 160}, rng), true);
  VarD y = d.forward(x);
  TensorD seed = TensorD::zeros(y.shape());
  const int64_t oh = y.size(2), ow = y.size(3);
  seed[(oh / 2) * ow + ow / 2] = 1;
  y.backward(seed);
  int64_t x0 = 1000, x1 = -1, y0 = 1000, y1 = -1;
  for (int64_t r = 0; r < 160; ++r)
    for (int64_t c = 0; c < 160; ++c)
      if (x.grad()[r * 160 + c] != 0) {
        y0 = std::min(y0, r), y1 = std::max(y1, r), x0 = std::min(x0, c), x1 = std::max(x1, c);
      }
  EXPECT_EQ(y1 - y0 + 1, 70);
  EXPECT_EQ(x1 - x0 + 1, 70);
}

TEST(PatchGan, GradCheckTrainingMode) {
  Rng rng(3);
  PatchGan<double> d({4, 2, 2}, rng);
  std::vector<VarD> inputs = {VarD(random_tensor({1, 4, 24, 20}, rng), true)};
  // pix2pix's N(0, 0.02) weights make every gradient smaller than gradcheck's absolute
  // floor (1e-7), where any answer passes: use O(1) gradients instead.
  for (auto& p : d.parameters()) {
    VarD q = p;
    if (q.shape().dim() >= 2) q.value() = random_tensor(q.shape(), rng, 0.4);
    else q.value() = random_tensor(q.shape(), rng, 0.5);
    inputs.push_back(q);
  }
  gradcheck([&](std::vector<VarD>& in) { return d.forward(in[0]); }, inputs);
}
