// model_light with mirror averaging (eval-gi and gi-infer --mirror-average): a model's light averaged with its light
// for the mirrored frame, mirrored back, is mirror-equivariant exactly (mirroring twice is the identity and float
// addition commutes), which the network alone is not.
#include <gtest/gtest.h>

#include <cstring>

#include "runs/gi/gi_samples.h"
#include "runs/gi/model_light.h"
#include "tests/support/synthetic_gi_dataset.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::runs;

namespace {

bool same(const Tensor<float>& a, const Tensor<float>& b) {
  return a.shape() == b.shape() && std::memcmp(a.data(), b.data(), size_t(a.numel()) * sizeof(float)) == 0;
}

LoadedGenerator small_generator() {
  LoadedGenerator g;
  g.inputs.mode = GiMode::surround;
  g.inputs.norm.depth_max = 6, g.inputs.norm.hdr_scale = 0.7f;
  g.config.unet.in_channels = g.inputs.channels();
  g.config.unet.ngf = 4, g.config.unet.levels = 3;
  g.config.residual = GiResidual::linear;
  g.config.hdr_scale = g.inputs.norm.hdr_scale;
  Rng rng(5);
  g.G = make_generator<float>(g.config, rng);
  return g;
}

}  // namespace

TEST(MirrorAverage, TheAveragedLightOfTheMirroredFrameIsTheMirroredLight) {
  std::array<data::View, 6> faces;
  for (int k = 0; k < 6; ++k) faces[size_t(k)] = nns::testing::make_face(8, 3, k, k == 0, 3);
  LoadedGenerator g = small_generator();
  const GiSample s = assemble_surround(faces, g.inputs, "f"), m = mirrored(s);
  // The network alone: its light for the mirrored frame is not the mirrored light.
  for (bool average : {false, true})
    EXPECT_EQ(
        same(runs::detail::flipped(model_light(g, m, true, false, average)), model_light(g, s, true, false, average)),
        average)
        << average;
}
