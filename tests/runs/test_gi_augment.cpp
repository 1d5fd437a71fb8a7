// train-gan's augmentation (runs/gi/gi_augment.h): a mirrored sample is the sample
// assembled from the mirrored frame (single views and surround cubes whose left and
// right faces differ), mirroring twice changes nothing, a symmetric cube is its own
// mirror, and jittered light is the same light times the drawn factors.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "runs/gi/gi_augment.h"
#include "runs/gi/gi_samples.h"
#include "tests/support/synthetic_gi_dataset.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::runs;
using nns::data::View;

namespace {
constexpr int kF = 8;

// A view seen in a mirror: every plane flipped left-right, normals' x negated.
View mirror_view(View v) {
  for (auto& [name, plane] : v.channels) {
    for (int r = 0; r < v.height; ++r) std::reverse(plane.begin() + r * v.width, plane.begin() + (r + 1) * v.width);
    if (name == "N.X")
      for (float& x : plane) x = -x;
  }
  return v;
}

std::array<View, 6> faces_of(int frame, int F = kF) {
  std::array<View, 6> f;
  for (int k = 0; k < 6; ++k) f[size_t(k)] = nns::testing::make_face(F, frame, k, k == 0, 3);
  f[0].world_to_camera = std::array<float, 16>{1, 0, 0, 0.5f, 0, 1, 0, -1.5f, 0, 0, 1, 2, 0, 0, 0, 1};
  return f;
}

// The mirrored cube: each face mirrored, left and right swapped (data::Face order).
std::array<View, 6> mirror_cube(const std::array<View, 6>& f) {
  return {mirror_view(f[0]), mirror_view(f[1]), mirror_view(f[3]),
          mirror_view(f[2]), mirror_view(f[4]), mirror_view(f[5])};
}

GiInputConfig config(GiMode mode) {
  GiInputConfig c;
  c.mode = mode;
  c.norm.depth_max = 6, c.norm.hdr_scale = 0.7f;
  return c;
}

bool same(const Tensor<float>& a, const Tensor<float>& b) {
  return a.shape() == b.shape() && std::memcmp(a.data(), b.data(), size_t(a.numel()) * sizeof(float)) == 0;
}

// Every tensor and mask a training step or a preview reads, bit for bit.
void expect_same_sample(const GiSample& a, const GiSample& b, const std::string& what) {
  EXPECT_TRUE(same(a.input, b.input)) << what << ": input";
  EXPECT_TRUE(same(a.target, b.target)) << what << ": target";
  EXPECT_TRUE(same(a.target_linear, b.target_linear)) << what << ": target_linear";
  EXPECT_TRUE(same(a.albedo, b.albedo)) << what << ": albedo";
  EXPECT_TRUE(same(a.emission, b.emission)) << what << ": emission";
  EXPECT_TRUE(same(a.direct_env, b.direct_env)) << what << ": direct_env";
  EXPECT_EQ(a.geometry, b.geometry) << what << ": geometry";
  EXPECT_EQ(a.front, b.front) << what;
}
}  // namespace

TEST(GiAugment, MirroredSurroundFrameIsTheFrameOfTheMirroredCube) {
  const auto faces = faces_of(1);
  ASSERT_NE(faces[2].channel("direct.R"), mirror_view(faces[3]).channel("direct.R"));  // left and right differ
  const GiSample s = assemble_surround(faces, config(GiMode::surround), "f");
  const GiSample m = mirrored(s);
  expect_same_sample(m, assemble_surround(mirror_cube(faces), config(GiMode::surround), "f"), "surround");
  EXPECT_FALSE(same(m.input, s.input));
  // The front view's geometry is the same world seen through a mirrored camera.
  EXPECT_EQ(m.front_geometry.channel("N.X"), mirror_view(faces[0]).channel("N.X"));
}

TEST(GiAugment, MirroredViewIsTheMirroredViewAssembled) {
  View v = nns::testing::make_face(kF, 2, 0, true, 5);
  v.height = kF / 2;  // not square: a single view of any shape
  for (auto& [name, plane] : v.channels) plane.resize(size_t(v.width * v.height));
  const GiSample s = assemble_front(v, config(GiMode::front));
  expect_same_sample(mirrored(s), assemble_front(mirror_view(v), config(GiMode::front)), "front");
}

TEST(GiAugment, MirroringTwiceIsTheIdentity) {
  const GiSample s = assemble_surround(faces_of(4), config(GiMode::surround), "f");
  const GiSample twice = mirrored(mirrored(s));
  expect_same_sample(twice, s, "twice");
  EXPECT_EQ(twice.front_geometry.channel("Z"), s.front_geometry.channel("Z"));
  ASSERT_TRUE(twice.front_geometry.world_to_camera.has_value());
  EXPECT_EQ(*twice.front_geometry.world_to_camera, *s.front_geometry.world_to_camera);
  EXPECT_EQ((*mirrored(s).front_geometry.world_to_camera)[3], -0.5f);  // x_cam -> -x_cam: row 0 negated
}

// A cube that a mirror maps onto itself: front, back, up and down symmetric left-right
// (normals' x antisymmetric), left the mirror image of right.
TEST(GiAugment, SymmetricCubeIsItsOwnMirror) {
  auto faces = faces_of(3);
  for (int k : {0, 1, 4, 5}) {
    View& v = faces[size_t(k)];
    const View m = mirror_view(v);
    for (auto& [name, plane] : v.channels)
      for (int y = 0; y < kF; ++y)
        for (int x = kF / 2; x < kF; ++x) plane[size_t(y * kF + x)] = m.channel(name)[size_t(y * kF + x)];
  }
  faces[2] = mirror_view(faces[3]);
  const GiSample s = assemble_surround(faces, config(GiMode::surround), "sym");
  expect_same_sample(mirrored(s), s, "symmetric");
}

// An odd face size puts the front face off the global view's centre: no mirror there.
TEST(GiAugment, OddFaceSizeIsRefused) {
  const GiSample s = assemble_surround(faces_of(0, 5), config(GiMode::surround), "odd");
  EXPECT_THROW(mirrored(s), std::invalid_argument);
}

// Light jitter: the target (and emission, direct + env) is the drawn factor times the
// original in linear light; the lumination input is the same light scaled, through the
// HDR mapping; albedo, normals, depth and coordinates do not change. And the jittered
// sample is the sample of a frame whose light channels were scaled.
TEST(GiAugment, JitteredLightIsTheSameLightScaled) {
  const auto faces = faces_of(2);
  const GiInputConfig cfg = config(GiMode::surround);
  const GiSample s = assemble_surround(faces, cfg, "f");
  Rng rng(7);
  const AugmentDraw d = draw_augment({false, 1.4, 1.2}, rng);
  EXPECT_FALSE(d.mirror);
  for (float k : d.scale) EXPECT_TRUE(k > 1 / 1.4f / 1.25f && k < 1.4f * 1.25f) << k;
  EXPECT_NE(d.scale[0], d.scale[2]);
  Rng tint_rng(7);
  const AugmentDraw t = draw_augment({false, 1, 1.2}, tint_rng);  // a tint alone does not expose
  EXPECT_NEAR(0.2126 * t.scale[0] + 0.7152 * t.scale[1] + 0.0722 * t.scale[2], 1.0, 1e-6);
  const GiSample j = augmented(s, d, cfg.norm.hdr_scale);
  const HdrMapping hdr(cfg.norm.hdr_scale);
  const int64_t n = s.target_linear.numel() / 3;
  for (int c = 0; c < 3; ++c)
    for (int64_t i = 0; i < n; ++i) {
      ASSERT_EQ(j.target_linear[c * n + i], d.scale[c] * s.target_linear[c * n + i]);
      ASSERT_EQ(j.target[c * n + i], hdr.to_tanh(j.target_linear[c * n + i]));
      ASSERT_EQ(j.emission[c * n + i], d.scale[c] * s.emission[c * n + i]);
    }
  const int64_t gn = s.input.size(2) * s.input.size(3);
  for (int ch = 0; ch < s.input.size(1); ++ch)
    if (ch < 7 || ch > 9) {
      EXPECT_EQ(std::memcmp(j.input.data() + ch * gn, s.input.data() + ch * gn, size_t(gn) * 4), 0) << "channel " << ch;
    }

  std::array<View, 6> lit = faces;
  for (auto& v : lit)
    for (auto& [name, plane] : v.channels)
      for (const char* base : {"direct.", "env.", "emission.", "indirect."})
        if (name.rfind(base, 0) == 0)
          for (float& x : plane) x *= d.scale[name.back() == 'R' ? 0 : name.back() == 'G' ? 1 : 2];
  const GiSample r = assemble_surround(lit, cfg, "f");
  double worst = 0;
  for (int64_t i = 0; i < r.input.numel(); ++i) worst = std::max(worst, double(std::fabs(r.input[i] - j.input[i])));
  EXPECT_LT(worst, 2e-6);  // the lumination through the HDR mapping and back: float rounding only
  for (int64_t i = 0; i < r.target_linear.numel(); ++i)
    ASSERT_NEAR(r.target_linear[i], j.target_linear[i], 2e-6f * std::max(1.0f, r.target_linear[i]));
}

// Off means off: a draw with nothing asked for changes nothing; the stream depends on
// (seed, epoch, position) only, and the mirror decisions do not move when jitter is on.
TEST(GiAugment, DrawsComeFromTheSamplesOwnStream) {
  int mirrored_count = 0;
  for (int64_t q = 0; q < 200; ++q) {
    Rng a = augment_rng(3, 1, q), b = augment_rng(3, 1, q);
    const AugmentDraw da = draw_augment({true, 1, 1}, a), db = draw_augment({true, 1.5, 1.3}, b);
    EXPECT_EQ(da.mirror, db.mirror);
    for (float k : da.scale) EXPECT_EQ(k, 1.0f);
    mirrored_count += da.mirror;
    Rng c = augment_rng(3, 2, q);
    (void)draw_augment({true, 1, 1}, c);
  }
  EXPECT_GT(mirrored_count, 70);  // about half of 200
  EXPECT_LT(mirrored_count, 130);
  Rng x = augment_rng(3, 1, 5), y = augment_rng(3, 2, 5);
  EXPECT_NE(x.next_u64(), y.next_u64());
  Rng off = augment_rng(1, 0, 0);
  const GiSample s = assemble_surround(faces_of(1), config(GiMode::surround), "f");
  expect_same_sample(augmented(s, draw_augment({}, off), 0.7f), s, "nothing asked for");
}
