// Reprojection for eval-ao's temporal stability (classical_ao/temporal.h).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "classical_ao/temporal.h"

using namespace nns;

namespace {

// A floor at world y = -1 seen by a camera at world (cam_x, 0, 0) looking down -z
// (sky above the horizon).
data::View floor_view(int w, int h, float cam_x) {
  data::View v;
  v.width = w, v.height = h, v.fov_y_deg = 60, v.ao_radius = 1.0f, v.scene = "floor";
  auto& Z = v.add_channel("Z");
  v.add_channel("N.X");
  auto& NY = v.add_channel("N.Y");
  v.add_channel("N.Z");
  const float ty = std::tan(30 * 3.14159265f / 180);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float dy = (1 - 2 * (y + 0.5f) / h) * ty;
      Z[size_t(y) * w + x] = dy < -1e-3f ? 1.0f / -dy : INFINITY;
      NY[size_t(y) * w + x] = 1;
    }
  v.world_to_camera = std::array<float, 16>{1, 0, 0, -cam_x, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  return v;
}

Vec3 world(const screen_space::GBuffer& g, int64_t i, float cam_x) {
  Vec3 p = g.position(int(i % g.width), int(i / g.width));
  p.x += cam_x;
  return p;
}

}  // namespace

TEST(AoTemporal, ReprojectionFindsTheSameSurfacePoint) {
  const float x0 = 0.0f, x1 = 0.15f;  // the camera slides right between the frames
  auto prev = floor_view(64, 48, x0), cur = floor_view(64, 48, x1);
  auto gp = screen_space::gbuffer_from_view(prev), gc = screen_space::gbuffer_from_view(cur);
  auto map = classical_ao::reproject_to_previous(gc, cur.world_to_camera, gp, prev.world_to_camera);
  int64_t floor_px = 0, mapped = 0, shifted = 0;
  for (int64_t i = 0; i < gc.pixels(); ++i) {
    if (gc.sky(i)) {
      EXPECT_EQ(map[size_t(i)], -1);
      continue;
    }
    ++floor_px;
    const int64_t j = map[size_t(i)];
    if (j < 0) continue;
    ++mapped;
    shifted += j != i;
    // The two pixels show the same floor point, to within a pixel's footprint there.
    const float footprint = gc.z[i] * 2 * gc.sx / float(gc.width);
    const Vec3 d = world(gc, i, x1) - world(gp, j, x0);
    EXPECT_LT(length(d), 1.5f * footprint) << "pixel " << i;
  }
  EXPECT_GT(mapped, floor_px * 8 / 10);  // only the strip that entered the screen is lost
  EXPECT_LT(mapped, floor_px);
  EXPECT_GT(shifted, mapped / 2);  // the camera moved: most pixels do not map to themselves
}

TEST(AoTemporal, WithoutMatricesTheMapIsTheIdentity) {
  auto a = floor_view(32, 24, 0), b = floor_view(32, 24, 0);
  a.world_to_camera.reset();
  auto ga = screen_space::gbuffer_from_view(a), gb = screen_space::gbuffer_from_view(b);
  auto map = classical_ao::reproject_to_previous(ga, a.world_to_camera, gb, b.world_to_camera);
  for (int64_t i = 0; i < ga.pixels(); ++i) EXPECT_EQ(map[size_t(i)], ga.sky(i) ? -1 : i);
}

TEST(AoTemporal, StatisticsSeparateFlickerFromTrackingTheTruth) {
  // A method equal to the truth plus a constant has the truth's flicker and no temporal
  // error; one that alternates by 0.1 per frame has temporal error 0.1.
  std::vector<int64_t> map = {0, 1, 2, -1};
  std::vector<float> g0 = {0.2f, 0.5f, 0.9f, 1}, g1 = {0.3f, 0.5f, 0.7f, 1};
  std::vector<float> m0 = g0, m1 = g1, n0 = g0, n1 = g1;
  for (auto* v : {&m0, &m1})
    for (auto& x : *v) x += 0.05f;
  for (int i = 0; i < 3; ++i) n1[size_t(i)] += 0.1f;
  classical_ao::TemporalStats gt, m, n;
  gt.add_pair(map, g1.data(), g0.data(), g1.data(), g0.data());
  m.add_pair(map, m1.data(), m0.data(), g1.data(), g0.data());
  n.add_pair(map, n1.data(), n0.data(), g1.data(), g0.data());
  EXPECT_NEAR(gt.flicker(), (0.1 + 0 + 0.2) / 3, 1e-6);
  EXPECT_NEAR(m.flicker(), gt.flicker(), 1e-6);
  EXPECT_NEAR(m.error(), 0, 1e-6);
  EXPECT_NEAR(n.error(), 0.1, 1e-6);
  EXPECT_NEAR(gt.coverage(), 0.75, 1e-9);
}

TEST(AoTemporal, PathFramesAreRecognisedByName) {
  int f = -1;
  EXPECT_EQ(classical_ao::path_of_frame("room-100000-p00-f007", f), "room-100000-p00");
  EXPECT_EQ(f, 7);
  EXPECT_EQ(classical_ao::path_of_frame("colonnade-100000-v002", f), "");
  EXPECT_EQ(classical_ao::path_of_frame("a-f", f), "");
  EXPECT_EQ(classical_ao::path_of_frame("a-f1x", f), "");
}
