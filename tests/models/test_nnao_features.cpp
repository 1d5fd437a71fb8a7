#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "models/nnao/nnao_features.h"
#include "runs/ao/nnao_points.h"
#include "fixtures/synthetic_gbuffer.h"

using namespace nns;

namespace {

// The features by the slow, literal route: build each grid point in view space,
// project it with the general projection, round, clamp, read, fall off.
// `tie` marks grid points whose projection lies within 1e-3 pixel of a rounding
// boundary, where float rounding of the two routes may pick either neighbour.
std::vector<float> reference_features(const screen_space::GBuffer& g, int px, int py, int w, std::vector<bool>& tie) {
  std::vector<float> out(size_t(w) * w * 4);
  tie.assign(size_t(w) * w, false);
  const int64_t c = int64_t(py) * g.width + px;
  const double r = g.radius;
  Vec3 P = g.position(px, py);
  for (int j = 0; j < w; ++j)
    for (int i = 0; i < w; ++i) {
      double ox = w == 1 ? 0 : r * (2.0 * i / (w - 1) - 1), oy = w == 1 ? 0 : r * (1 - 2.0 * j / (w - 1));
      Vec3 S{float(P.x + ox), float(P.y + oy), P.z};
      float sx, sy;
      g.project(S, sx, sy);
      auto near_half = [](float t) { return std::abs(t - std::floor(t) - 0.5f) < 1e-3f; };
      tie[size_t(j) * w + i] = near_half(sx) || near_half(sy);
      int ix = std::clamp(int(std::lround(sx)), 0, g.width - 1);
      int iy = std::clamp(int(std::lround(sy)), 0, g.height - 1);
      int64_t s = int64_t(iy) * g.width + ix;
      float* o = &out[(size_t(j) * w + i) * 4];
      if (g.sky(s)) continue;
      Vec3 Ps = g.position(ix, iy);
      double dist = std::sqrt(double(dot(Ps - P, Ps - P)));
      double f = 1 - std::clamp(dist / r, 0.0, 1.0);
      o[0] = float(f * (g.nx[s] - g.nx[c]));
      o[1] = float(f * (g.ny[s] - g.ny[c]));
      o[2] = float(f * (g.nz[s] - g.nz[c]));
      o[3] = float(f * (g.z[s] - g.z[c]) / r);
    }
  return out;
}

}  // namespace

TEST(NnaoFeatures, MatchLiteralDefinitionEverywhere) {
  auto v = nns::fixtures::synthetic_view(64, 40, 3, 1, 0.8f);
  auto g = screen_space::gbuffer_from_view(v);
  const int w = 7;
  std::vector<float> f(size_t(nnao::feature_count(w)));
  int checked = 0;
  for (int y = 0; y < g.height; y += 3)
    for (int x = 0; x < g.width; x += 3) {
      if (g.sky(int64_t(y) * g.width + x)) continue;
      nnao::compute_features(g, x, y, w, f.data());
      std::vector<bool> tie;
      auto ref = reference_features(g, x, y, w, tie);
      for (size_t k = 0; k < f.size(); ++k)
        if (!tie[k / 4]) ASSERT_NEAR(f[k], ref[k], 2e-5) << "pixel " << x << "," << y << " k " << k;
      ++checked;
    }
  EXPECT_GT(checked, 100);
}

TEST(NnaoFeatures, FlatWallFacingTheCameraGivesZeros) {
  data::View v;
  v.width = 32, v.height = 24, v.fov_y_deg = 50, v.ao_radius = 0.5f, v.scene = "wall";
  v.add_channel("Z").assign(32 * 24, 4.0f);
  v.add_channel("N.X");
  v.add_channel("N.Y");
  v.add_channel("N.Z").assign(32 * 24, 1.0f);
  auto g = screen_space::gbuffer_from_view(v);
  std::vector<float> f(size_t(nnao::feature_count(31)));
  nnao::compute_features(g, 16, 12, 31, f.data());
  for (float x : f) EXPECT_EQ(x, 0.0f);
}

TEST(NnaoFeatures, FalloffSkyAndCentre) {
  // Centre on the floor next to the sky: sky samples and samples beyond r are zero; the
  // centre sample (same pixel) is zero; a nearby sample of a different depth is not.
  auto v = nns::fixtures::synthetic_view(64, 40, 0, 1, 1.0f);
  auto g = screen_space::gbuffer_from_view(v);
  const int w = 31;
  std::vector<float> f(size_t(nnao::feature_count(w)));
  // A floor pixel near the bottom of the screen: its grid leaves the screen (clamped).
  nnao::compute_features(g, 20, 38, w, f.data());
  const int centre = (w / 2) * w + w / 2;
  for (int c = 0; c < 4; ++c) EXPECT_EQ(f[size_t(centre * 4 + c)], 0.0f);
  int nonzero = 0;
  for (int k = 0; k < w * w; ++k) {
    float d = f[size_t(k * 4 + 3)];
    EXPECT_LE(std::abs(d), 1.0f + 1e-5f);  // |zs - z| / r * falloff never exceeds 1
    nonzero += d != 0;
  }
  EXPECT_GT(nonzero, 0);
}

TEST(NnaoPoints, HalfStorageRoundsWithinItsPrecisionAndSaturates) {
  // The training matrix is binary16: round to nearest, relative error <= 2^-11 for
  // normal values, and out-of-range values clamp to +-65504 instead of becoming inf.
  for (float v : {1.0f, -0.3337f, 3.14159f, 1e-3f, -17.25f, 60000.0f}) {
    const float r = float(runs::to_half(v));
    EXPECT_LE(std::abs(r - v), std::abs(v) * 0x1p-11f) << v;
  }
  EXPECT_EQ(float(runs::to_half(1e6f)), 65504.0f);
  EXPECT_EQ(float(runs::to_half(-INFINITY)), -65504.0f);
  std::vector<runs::Half> h = {runs::to_half(0.5f), runs::to_half(-2.0f)};
  std::vector<float> f(2);
  runs::to_float(h.data(), f.data(), 2);
  EXPECT_EQ(f, (std::vector<float>{0.5f, -2.0f}));
}
