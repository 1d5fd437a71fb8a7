#include <gtest/gtest.h>

#include <cmath>
#include <unistd.h>

#include <filesystem>

#include "models/gi/crop.h"
#include "runs/gi/gi_samples.h"
#include "models/gi/gi_inputs.h"
#include "tests/support/gradcheck.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::runs;
using namespace nns::testing;
using nns::data::View;

namespace {

// A view whose every channel is a known function of (channel index, pixel).
View make_view(int w, int h, float base, bool with_optional = true, bool targets = true) {
  View v;
  v.width = w, v.height = h;
  v.fov_y_deg = 90;
  v.scene = "s";
  v.source = "mem.exr";
  auto set = [&](const std::string& name, float value) {
    auto& p = v.add_channel(name);
    for (size_t i = 0; i < p.size(); ++i) p[i] = value + 0.001f * float(i);
  };
  set("Z", 2 * base);
  set("N.X", 0.0f), set("N.Y", 0.0f), set("N.Z", 1.0f);
  set("albedo.R", 0.25f), set("albedo.G", 0.5f), set("albedo.B", 0.75f);
  set("direct.R", base), set("direct.G", 2 * base), set("direct.B", 0.0f);
  if (with_optional) {
    set("emission.R", 0.5f), set("emission.G", 0.0f), set("emission.B", 0.0f);
    set("env.R", 0.1f), set("env.G", 0.1f), set("env.B", 0.1f);
  }
  if (targets) set("indirect.R", 0.3f), set("indirect.G", 0.2f), set("indirect.B", 0.1f);
  v.channels["Z"][0] = INFINITY;  // one sky pixel
  return v;
}

}  // namespace

TEST(Crop2d, ForwardPicksTheRectangle) {
  Tensor<float> x({1, 2, 3, 4});
  for (int64_t i = 0; i < x.numel(); ++i) x[i] = float(i);
  Tensor<float> y = crop2d(x, Rect{1, 1, 2, 2});
  EXPECT_EQ(y.shape(), (Shape{1, 2, 2, 2}));
  EXPECT_EQ(y[0], 5.0f);
  EXPECT_EQ(y[3], 10.0f);
  EXPECT_EQ(y[4], 17.0f);
  EXPECT_THROW(crop2d(x, Rect{3, 0, 2, 1}), std::invalid_argument);
}

TEST(Crop2d, GradCheck) {
  Rng rng(1);
  std::vector<VarD> in = {VarD(random_tensor({2, 3, 5, 7}, rng), true)};
  gradcheck([](std::vector<VarD>& v) { return crop2d(v[0], Rect{2, 1, 4, 3}); }, in);
}

TEST(GiInputs, ChannelsAreMappedAsDocumented) {
  View v = make_view(4, 3, 1.0f);
  GiInputConfig cfg;
  cfg.mode = GiMode::front;
  cfg.norm.depth_max = 4.0f;
  cfg.norm.hdr_scale = 2.0f;
  GiSample s = assemble_front(v, cfg);
  ASSERT_EQ(s.input.shape(), (Shape{1, 12, 3, 4}));
  const int64_t n = 12;
  const int64_t px = 5;  // an arbitrary geometry pixel
  const float off = 0.001f * px;
  HdrMapping hdr(2.0f);
  EXPECT_FLOAT_EQ(s.input[0 * n + px], 2 * (0.25f + off) - 1);
  EXPECT_FLOAT_EQ(s.input[5 * n + px], 1.0f + off);
  EXPECT_FLOAT_EQ(s.input[6 * n + px], 2 * ((2.0f + off) / 4.0f) - 1);
  EXPECT_FLOAT_EQ(s.input[6 * n + 0], 1.0f);  // sky: as far as it gets
  // lumination = direct + emission + env
  EXPECT_FLOAT_EQ(s.input[7 * n + px], hdr.to_tanh((1 + off) + (0.5f + off) + (0.1f + off)));
  // CoordConv (x, y) in [-1, 1]: pixel 5 is (x=1, y=1) of 4x3.
  EXPECT_FLOAT_EQ(s.input[10 * n + px], 2 * (1.5f / 4) - 1);
  EXPECT_FLOAT_EQ(s.input[11 * n + px], 2 * (1.5f / 3) - 1);
  // target = direct + env + indirect (no emission); shaded = albedo * target + emission
  float t = (1 + off) + (0.1f + off) + (0.3f + off);
  EXPECT_FLOAT_EQ(s.target_linear[px], t);
  EXPECT_FLOAT_EQ(s.target[px], hdr.to_tanh(t));
  EXPECT_FLOAT_EQ(s.direct_env[px], (1 + off) + (0.1f + off));
  EXPECT_EQ(s.geometry[0], 0);
  EXPECT_EQ(s.geometry[px], 1);
  EXPECT_EQ(s.front, (Rect{0, 0, 4, 3}));
  cfg.coordconv = false;
  EXPECT_EQ(assemble_front(v, cfg).input.size(1), 10);
}

TEST(GiInputs, OptionalLightIsZeroAndNonFiniteIsRefusedByName) {
  View v = make_view(4, 3, 1.0f, /*with_optional=*/false);
  GiInputConfig cfg;
  cfg.mode = GiMode::front;
  GiSample s = assemble_front(v, cfg);
  EXPECT_FLOAT_EQ(s.input[7 * 12 + 5], HdrMapping(1.0f).to_tanh(1.005f));
  v.channels["direct.G"][7] = NAN;
  try {
    assemble_front(v, cfg);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("mem.exr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("direct.G"), std::string::npos) << e.what();
  }
  View no_target = make_view(4, 3, 1.0f, true, /*targets=*/false);
  EXPECT_THROW(assemble_front(no_target, cfg), std::runtime_error);
}

TEST(GiInputs, SurroundPutsTheFrontFaceInTheFrontRect) {
  std::array<View, 6> faces;
  for (int f = 0; f < 6; ++f) faces[size_t(f)] = make_view(8, 8, 1.0f + f, true, f == 0);
  GiInputConfig cfg;
  cfg.mode = GiMode::surround;
  GiSample s = assemble_surround(faces, cfg, "frame");
  ASSERT_EQ(s.input.shape(), (Shape{1, 12, 16, 32}));
  auto r = data::global_view_layout(8).front_rect();
  EXPECT_EQ(s.front, (Rect{r.x0, r.y0, r.w, r.h}));
  Tensor<float> front_planes = view_planes(faces[0], cfg.norm);
  Tensor<float> cropped = crop2d(s.input, s.front);
  for (int c = 0; c < 10; ++c)
    for (int64_t i = 0; i < 64; ++i) ASSERT_FLOAT_EQ(cropped[c * 64 + i], front_planes[c * 64 + i]) << c;
  // (phi, theta) straight ahead is (0.5, 0.5) -> 0 in [-1, 1], near the front's centre.
  EXPECT_NEAR(cropped[10 * 64 + 4 * 8 + 4], 0.0f, 0.15f);
  EXPECT_NEAR(cropped[11 * 64 + 4 * 8 + 4], 0.0f, 0.15f);
  // Face f's direct light sums to 64 * 3 * (1 + f) plus 3 * 0.001 * (0 + ... + 63) of
  // pixel offsets: the front holds (192 + 6.048) / (192 * 21 + 6 * 6.048).
  EXPECT_NEAR(s.front_direct_share, (192 + 6.048) / (192 * 21 + 6 * 6.048), 1e-5);
}

TEST(GiInputs, DownsampleAveragesAndKeepsSkyOnlyWhereAllSky) {
  View v = make_view(4, 4, 1.0f);
  v.channels["Z"] = {INFINITY, INFINITY, 1, 2, INFINITY, INFINITY, 3, 4, 1, 1, 1, 1, 1, 1, 1, 3};
  View d = downsample_view(v, 2);
  ASSERT_EQ(d.width, 2);
  EXPECT_TRUE(data::is_sky(d.channel("Z")[0]));
  EXPECT_FLOAT_EQ(d.channel("Z")[1], 2.5f);
  EXPECT_FLOAT_EQ(d.channel("Z")[3], 1.5f);
  const auto& a = v.channel("albedo.R");
  EXPECT_FLOAT_EQ(d.channel("albedo.R")[0], (a[0] + a[1] + a[4] + a[5]) / 4);
  float nx = d.channel("N.X")[0], ny = d.channel("N.Y")[0], nz = d.channel("N.Z")[0];
  EXPECT_NEAR(nx * nx + ny * ny + nz * nz, 1.0f, 1e-6f);  // renormalised
  EXPECT_THROW(downsample_view(v, 3), std::runtime_error);
}

// The GI tools took a NaN, zero or negative depth for sky. The contract
// (docs/dataset-format.md) has sky as +inf or >= 1e30 and everything else invalid.
TEST(GiInputs, InvalidDepthIsRefusedNotTakenForSky) {
  GiInputConfig cfg;
  cfg.mode = GiMode::front;
  for (float bad : {NAN, 0.0f, -1.0f, -INFINITY}) {
    View v = make_view(4, 4, 1.0f);
    v.channels["Z"][6] = bad;
    SCOPED_TRACE(bad);
    try {
      assemble_front(v, cfg);
      ADD_FAILURE() << "depth " << bad << " was accepted";
    } catch (const std::runtime_error& e) {
      std::string m = e.what();
      EXPECT_NE(m.find("mem.exr: channel 'Z'"), std::string::npos) << m;
      EXPECT_NE(m.find("x=2, y=1"), std::string::npos) << m;
    }
    EXPECT_THROW(downsample_view(v, 2), std::runtime_error);
  }
  View sky = make_view(4, 4, 1.0f);
  sky.channels["Z"][6] = 1e30f;
  EXPECT_NO_THROW(assemble_front(sky, cfg));
  EXPECT_NO_THROW(downsample_view(sky, 2));
}

// The same through the file reader the GI tools use (train-gan, sweep-gan, eval-gi).
TEST(GiInputs, ItemReaderRefusesInvalidDepthNamingTheFile) {
  auto dir = std::filesystem::temp_directory_path() / ("nns_gi_depth_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  View v = make_view(4, 4, 1.0f);
  v.channels["Z"][5] = -2.0f;
  std::string path = (dir / "neg.exr").string();
  data::write_view(path, v);
  for (int size : {0, 2}) {
    GiItemReader rd{GiMode::front, size};
    try {
      rd.view(path);
      ADD_FAILURE() << "negative depth accepted at --size " << size;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(path + ": channel 'Z'"), std::string::npos) << e.what();
    }
  }
  std::filesystem::remove_all(dir);
}

// gi-infer's frames have no indirect.*: assembled without targets they give the same
// input and shading planes, bit for bit, as the training path does with targets.
TEST(GiInputs, WithoutTargetsTheInputAndShadingPlanesAreBitwiseTheTrainingOnes) {
  GiInputConfig cfg;
  cfg.mode = GiMode::front;
  cfg.norm.hdr_scale = 1.7f;
  cfg.norm.depth_max = 3.0f;
  View with = make_view(4, 3, 1.0f), without = make_view(4, 3, 1.0f, true, /*targets=*/false);
  GiSample a = assemble_front(with, cfg), b = assemble_front(without, cfg, /*targets=*/false);
  auto same = [](const Tensor<float>& x, const Tensor<float>& y) {
    return x.shape() == y.shape() && std::equal(x.begin(), x.end(), y.begin());
  };
  EXPECT_TRUE(same(a.input, b.input));
  EXPECT_TRUE(same(a.albedo, b.albedo));
  EXPECT_TRUE(same(a.emission, b.emission));
  EXPECT_TRUE(same(a.direct_env, b.direct_env));
  EXPECT_EQ(a.geometry, b.geometry);
  EXPECT_FALSE(b.target.defined());
  EXPECT_FALSE(b.target_linear.defined());

  std::array<View, 6> faces, bare;
  for (int f = 0; f < 6; ++f) {
    faces[size_t(f)] = make_view(8, 8, 1.0f + f, true, f == 0);
    bare[size_t(f)] = make_view(8, 8, 1.0f + f, true, false);
  }
  cfg.mode = GiMode::surround;
  GiSample c = assemble_surround(faces, cfg, "frame"), d = assemble_surround(bare, cfg, "frame", false);
  EXPECT_TRUE(same(c.input, d.input));
  EXPECT_TRUE(same(c.direct_env, d.direct_env));
  EXPECT_EQ(c.front_direct_share, d.front_direct_share);
  EXPECT_THROW(assemble_surround(bare, cfg, "frame"), std::runtime_error);  // targets need indirect
}
