// screen_space/discontinuities.h: the chessboard distance transform against brute force,
// the surface-break test (sky, depth jump, crease), and eval-ao's halo band built on them
// against the square-window search it replaced.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "classical_ao/failure_bands.h"
#include "core/rng.h"
#include "screen_space/discontinuities.h"

using namespace nns;
using namespace nns::screen_space;
using namespace nns::classical_ao;

TEST(Discontinuities, ChebyshevDistanceMatchesBruteForce) {
  const int w = 23, h = 17;
  Rng rng(5);
  for (double density : {0.0, 0.01, 0.05, 0.3}) {
    std::vector<uint8_t> seeds(size_t(w * h));
    for (auto& s : seeds) s = rng.uniform() < density;
    const std::vector<int> d = chebyshev_distance(seeds, w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        int best = kNoSeed;
        for (int sy = 0; sy < h; ++sy)
          for (int sx = 0; sx < w; ++sx)
            if (seeds[size_t(sy * w + sx)]) best = std::min(best, std::max(std::abs(sx - x), std::abs(sy - y)));
        ASSERT_EQ(d[size_t(y * w + x)], best) << "density " << density << " at " << x << "," << y;
      }
  }
}

TEST(Discontinuities, BothPixelsOfABrokenPairAreMarked) {
  // 3 x 2: pixels 0 and 1 differ (across), 1 and 4 (down); nothing else.
  auto differ = [](int64_t i, int64_t j) { return (i == 0 && j == 1) || (i == 1 && j == 4); };
  const std::vector<uint8_t> m = discontinuity_pixels(3, 2, differ);
  EXPECT_EQ(m, (std::vector<uint8_t>{1, 1, 0, 0, 1, 0}));
}

TEST(Discontinuities, SurfaceBreakIsSkyEdgeDepthJumpOrCrease) {
  // Four pixels in a row: depth 1, 1.05, 2, sky; normals +z except pixel 1, tilted 45 degrees.
  std::vector<float> z = {1, 1.05f, 2, INFINITY}, nx = {0, 0.70710678f, 0, 0}, ny = {0, 0, 0, 0},
                     nz = {1, 0.70710678f, 1, 1};
  const GBuffer g = make_gbuffer(4, 1, 60, 1, z.data(), nx.data(), ny.data(), nz.data());
  auto loose = surface_break(g, 0.1f, std::cos(60 * 3.14159265f / 180));  // 45 degrees is no crease at 60
  EXPECT_FALSE(loose(0, 1));                                              // 5% deeper, 45 degrees apart
  EXPECT_TRUE(loose(1, 2));                                               // 2 / 1.05: a jump
  EXPECT_TRUE(loose(2, 3));                                               // geometry against sky
  auto strict = surface_break(g, 0.1f, std::cos(30 * 3.14159265f / 180));
  EXPECT_TRUE(strict(0, 1));                // 45 degrees > 30: a crease
  auto deep = surface_break(g, 0.01f, -2);  // normals never break, 1% depth does
  EXPECT_TRUE(deep(0, 1));
}

// The halo band (within 3 px of a depth jump larger than the AO radius) was a search of
// the 7 x 7 window around each pixel; it now reads the distance transform. Same masks.
TEST(Discontinuities, HaloBandEqualsTheWindowSearch) {
  const int w = 40, h = 30;
  Rng rng(11);
  std::vector<float> z(size_t(w * h)), nx(z.size(), 0), ny(z.size(), 0), nz(z.size(), 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float d = 5 + 0.01f * float(x);
      if (x > 12 && x < 20 && y > 5 && y < 22) d = 3;  // a box in front
      if (rng.uniform() < 0.02) d = 8;                 // scattered far pixels
      if (y < 3 && x > 30) d = INFINITY;               // sky in a corner
      z[size_t(y * w + x)] = d;
    }
  const GBuffer g = make_gbuffer(w, h, 60, 0.5f, z.data(), nx.data(), ny.data(), nz.data());
  const FailureBands b = failure_bands(g);
  auto jump = [&](float a, float c) {
    return data::is_sky(a) != data::is_sky(c) || (!data::is_sky(a) && std::abs(a - c) > g.radius);
  };
  int64_t halo_pixels = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y * w + x);
      bool expect = false;
      for (int sy = std::max(0, y - 3); sy <= std::min(h - 1, y + 3); ++sy)
        for (int sx = std::max(0, x - 3); sx <= std::min(w - 1, x + 3); ++sx) {
          const float s = z[size_t(sy * w + sx)];
          // (sx, sy) is an edge pixel if it differs from a 4-neighbour
          for (auto [dx, dy] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
            const int nxp = sx + dx, nyp = sy + dy;
            if (nxp >= 0 && nyp >= 0 && nxp < w && nyp < h && jump(s, z[size_t(nyp * w + nxp)])) expect = true;
          }
        }
      if (data::is_sky(z[i])) expect = false;
      ASSERT_EQ(b.masks[0][i], expect) << x << "," << y;
      halo_pixels += expect;
    }
  EXPECT_GT(halo_pixels, 100);
}
