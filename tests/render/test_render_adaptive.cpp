// surround-v5's speed settings: adaptive indirect paths (allot_paths: in proportion to
// the neighbours' std, never the pixel's own, within the budget and bounds; the adaptive
// render unbiased against a closed form and the same with 1 and 2 threads) and the side
// faces' AO / env rays (side_spp).
#include <gtest/gtest.h>

#include <cmath>

#include "core/thread_pool.h"
#include "render/adaptive_paths.h"
#include "render/dataset_writer.h"
#include "render/render_view.h"
#include "render/scenes/builder.h"
#include "render/surround.h"

using namespace nns;
using namespace nns::data;

namespace {
struct Planes {
  int w, h;
  std::vector<double> variance;
  std::vector<uint8_t> geometry;
  Planes(int w_, int h_, double v) : w(w_), h(h_), variance(size_t(w_ * h_), v), geometry(size_t(w_ * h_), 1) {}
  size_t at(int x, int y) const { return size_t(y) * size_t(w) + size_t(x); }
};

double mean_over_geometry(const Planes& p, const std::vector<int>& paths) {
  double sum = 0, n = 0;
  for (size_t i = 0; i < paths.size(); ++i)
    if (p.geometry[i]) sum += paths[i], ++n;
  return sum / n;
}
}  // namespace

TEST(AllotPaths, EqualVarianceGivesEveryPixelTheMean) {
  Planes p(12, 9, 0.3);
  std::vector<int> paths = allot_paths(p.w, p.h, p.variance, p.geometry, 16, 64, 256);
  for (int n : paths) EXPECT_EQ(n, 64);
}

TEST(AllotPaths, NoisyRegionsGetMoreWithinTheBudgetAndBounds) {
  Planes p(32, 24, 0.01);
  for (int y = 4; y < 12; ++y)
    for (int x = 6; x < 14; ++x) p.variance[p.at(x, y)] = 4.0;  // a noisy block: 20x the std
  for (int x = 0; x < p.w; ++x) p.geometry[p.at(x, 0)] = 0, p.variance[p.at(x, 0)] = 0;  // a sky row
  std::vector<int> paths = allot_paths(p.w, p.h, p.variance, p.geometry, 16, 64, 512);
  EXPECT_NEAR(mean_over_geometry(p, paths), 64, 1.0);
  for (size_t i = 0; i < paths.size(); ++i) {
    if (!p.geometry[i]) {
      EXPECT_EQ(paths[i], 0) << i;
      continue;
    }
    EXPECT_GE(paths[i], 16) << i;
    EXPECT_LE(paths[i], 512) << i;
  }
  EXPECT_GT(paths[p.at(9, 8)], 4 * paths[p.at(25, 18)]);
  EXPECT_LT(paths[p.at(25, 18)], 32);  // the quiet part: about k x 0.1, under the mean
}

// A pixel's own first paths never decide its count: a pixel whose paths varied alone
// gets what a quiet pixel far away gets, while its neighbours (which see it) get more.
TEST(AllotPaths, APixelsOwnVarianceDoesNotCount) {
  Planes p(20, 20, 1.0);
  p.variance[p.at(10, 10)] = 400.0;
  std::vector<int> paths = allot_paths(p.w, p.h, p.variance, p.geometry, 8, 48, 1000);
  EXPECT_EQ(paths[p.at(10, 10)], paths[p.at(2, 2)]);
  EXPECT_GT(paths[p.at(11, 10)], 2 * paths[p.at(2, 2)]);
  EXPECT_NEAR(mean_over_geometry(p, paths), 48, 1.0);
}

TEST(AllotPaths, LoneAndQuietPixelsAndASmallBudget) {
  Planes p(5, 5, 2.0);
  std::fill(p.geometry.begin(), p.geometry.end(), uint8_t(0));
  p.geometry[p.at(2, 2)] = 1;  // no geometry neighbour: nothing to go by, the mean
  EXPECT_EQ(allot_paths(p.w, p.h, p.variance, p.geometry, 8, 40, 200)[p.at(2, 2)], 40);
  Planes q(6, 4, 0.0);  // nothing varies: the first paths are enough
  for (int n : allot_paths(q.w, q.h, q.variance, q.geometry, 8, 40, 200)) EXPECT_EQ(n, 8);
  Planes r(6, 4, 1.0);
  r.variance[r.at(3, 2)] = 50;
  for (int n : allot_paths(r.w, r.h, r.variance, r.geometry, 32, 16, 200)) EXPECT_EQ(n, 32);  // mean <= first
  EXPECT_THROW(allot_paths(6, 4, std::vector<double>(3), r.geometry, 8, 16, 64), std::invalid_argument);
}

namespace {
// The floor-and-wall scene of test_render_analytic (RenderIndirect.SunsAndSkyBetweenFloorAndWall):
// every wall point leaves the same radiance, so every pixel of a camera that sees only the
// wall has the same expected indirect, Lf(B) / 2, and env Sw.
Scene floor_and_wall(double expect[3], double env_expect[3], int bounces) {
  Scene s;
  s.name = "floor-wall";
  const float af = 0.6f, aw = 0.8f, big = 1e4f;
  uint32_t mf = s.add_material({{af, af, af}, {}}), mw = s.add_material({{aw, aw, aw}, {}});
  add_quad(s, {0, 0, -big}, {big, 0, 0}, {0, 0, 2 * big}, mf);
  add_quad(s, {0, 0, -big}, {0, big, 0}, {0, 0, 2 * big}, mw);
  s.suns.push_back({normalize({1, 2, 0.3f}), {2, 1.5f, 1}, 0});
  s.suns.push_back({normalize({3, 1, -0.5f}), {0.05f, 0.05f, 0.1f}, 0});
  s.sky = Sky{{0.2f, 0.5f, 2.0f}, {0.6f, 0.6f, 0.3f}, {0, 0, 0}};
  const double wall_half = 0.8 * std::tgamma(0.75) / (std::sqrt(M_PI) * std::tgamma(1.25));
  for (int c = 0; c < 3; ++c) {
    double ef = 0, ew = 0, z = s.sky.zenith[c], h = s.sky.horizon[c];
    for (const Sun& sun : s.suns) ef += sun.color[c] * sun.direction.y, ew += sun.color[c] * sun.direction.x;
    double sf = (h + 0.8 * (z - h)) / 2, sw = (h + wall_half * (z - h)) / 2;
    double lf = 0, lw = 0;
    for (int k = 0; k < bounces; ++k) {
      double nf = af * (ef + sf + lw / 2), nw = aw * (ew + sw + lf / 2);
      lf = nf, lw = nw;
    }
    expect[c] = lf / 2, env_expect[c] = sw;
  }
  return s;
}
}  // namespace

// The adaptive render's mean over 8 views of 24x24 wall pixels (each pixel's count
// decided by its neighbours' first paths, which vary from pixel to pixel) is the closed
// form within 4 standard errors; the counts really differ (a pixel's estimate is its
// paths' mean, so a wrong divisor would show), and the view is the same with 1 and 2 threads.
TEST(RenderAdaptive, UnbiasedAgainstTheFloorAndWallClosedForm) {
  const int bounces = 3;
  double expect[3], env_expect[3];
  Scene s = floor_and_wall(expect, env_expect, bounces);
  RayTracer rt(s);
  Camera cam = Camera::look_at({4, 3, 0}, {0, 3, 0});
  cam.fov_y_deg = 40;
  cam.width = cam.height = 24;
  RenderSettings rs;
  rs.ao = false;
  rs.ao_spp = 1, rs.gi_spp = 24, rs.light_spp = 1, rs.bounces = bounces;
  rs.adaptive_first = 8, rs.adaptive_max = 96;
  double sum[3] = {}, sum2[3] = {}, env_sum[3] = {}, n = 0;
  set_num_threads(2);
  for (uint64_t id = 0; id < 8; ++id) {
    View v = render_view(rt, cam, rs, 40 + id);
    for (size_t i = 0; i < v.channel("Z").size(); ++i) {
      ASSERT_TRUE(std::isfinite(v.channel("Z")[i]));
      ASSERT_GT(v.channel("N.Z")[i], 0.99f) << "the camera sees only the wall";
      const char* ind[3] = {"indirect.R", "indirect.G", "indirect.B"};
      const char* env[3] = {"env.R", "env.G", "env.B"};
      for (int c = 0; c < 3; ++c) {
        const double x = v.channel(ind[c])[i];
        sum[c] += x, sum2[c] += x * x, env_sum[c] += v.channel(env[c])[i];
      }
      ++n;
    }
  }
  for (int c = 0; c < 3; ++c) {
    const double mean = sum[c] / n, se = std::sqrt(std::max(0.0, sum2[c] / n - mean * mean) / (n - 1));
    EXPECT_NEAR(mean, expect[c], 4 * se) << "channel " << c << ", standard error " << se;
    EXPECT_LT(se, 0.01 * expect[c]) << c;
    EXPECT_NEAR(env_sum[c] / n, env_expect[c], 4e-3 * env_expect[c]) << c;
  }
  set_num_threads(1);
  View one = render_view(rt, cam, rs, 40);
  set_num_threads(2);
  View two = render_view(rt, cam, rs, 40);
  for (auto& [name, plane] : one.channels) EXPECT_EQ(plane, two.channel(name)) << name;
  // Off, the same settings trace gi_spp everywhere: another image.
  RenderSettings uniform = rs;
  uniform.adaptive_first = 0;
  EXPECT_NE(render_view(rt, cam, uniform, 40).channel("indirect.R"), one.channel("indirect.R"));
}

// side_spp sets the side faces' AO and env rays (AO is a multiple of 1 / side_spp
// there) and leaves the front face alone, bit for bit.
TEST(RenderAdaptive, SideSppSetsTheSideFacesRaysOnly) {
  double expect[3], env_expect[3];
  Scene s = floor_and_wall(expect, env_expect, 2);
  s.ao_radius = 3;
  RayTracer rt(s);
  Camera front = Camera::look_at({1.5f, 1, 0.3f}, {0, 1, 0.3f});
  RenderSettings rs;
  rs.ao_spp = 32, rs.gi_spp = 8, rs.light_spp = 1, rs.bounces = 2;
  set_num_threads(2);
  auto plain = render_surround(rt, front, 12, rs, 7);
  rs.side_spp = 3;
  auto fewer = render_surround(rt, front, 12, rs, 7);
  for (auto& [name, plane] : plain[0].channels) EXPECT_EQ(plane, fewer[0].channel(name)) << name;
  int fractional = 0;
  for (size_t f = 1; f < 6; ++f)
    for (float ao : fewer[f].channel("AO")) {
      const float k = ao * 3;
      EXPECT_NEAR(k, std::round(k), 1e-5f) << "face " << f;
      fractional += std::fabs(ao * 32 - std::round(ao * 32)) > 1e-3f;
    }
  EXPECT_GT(fractional, 0) << "AO in thirds, not in 32nds";
  EXPECT_NE(plain[2].channel("env.B"), fewer[2].channel("env.B"));
}

// surround-v5's side rays keep a 64x64 face's rays per face, and never more than surround-v4's.
TEST(RenderAdaptive, SurroundV5SideRaysPerFaceSize) {
  EXPECT_EQ(surround_v5_side_spp(64), 64);
  EXPECT_EQ(surround_v5_side_spp(32), 64);
  EXPECT_EQ(surround_v5_side_spp(128), 16);
  EXPECT_EQ(surround_v5_side_spp(256), 8);
  DatasetJob job;
  job.preset = "surround-v5";
  job.width = job.height = 128;
  job.settings.gi_spp = 256;
  apply_preset(job);
  EXPECT_EQ(job.settings.adaptive_first, kSurroundV5FirstPaths);
  EXPECT_EQ(job.settings.adaptive_max, 1024);
  EXPECT_EQ(job.settings.side_spp, 16);
  EXPECT_TRUE(job.vary_textures && job.vary_lighting);
  DatasetJob v4 = job;
  v4.preset = "surround-v4";
  v4.settings = RenderSettings();
  apply_preset(v4);
  EXPECT_EQ(v4.settings.adaptive_first, 0);
  EXPECT_EQ(v4.settings.side_spp, 0);
}
