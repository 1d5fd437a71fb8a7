#pragma once
// Pixel masks for where screen-space AO is known to fail, so eval-ao can report the
// error there separately (all exclude sky):
//  * halo:   within 3 pixels of a depth discontinuity (a neighbour whose depth differs
//            by more than the AO radius) — the dark/bright halos of SSAO;
//  * border: within 8% of the image width of the screen edge — occluders just
//            off-screen are invisible to every screen-space method;
//  * thin:   pixels of a surface less than 6 pixels across (horizontally or vertically)
//            with something farther on both sides — poles, railings, fences.
#include <cstdint>
#include <string>
#include <vector>

#include "screen_space/discontinuities.h"
#include "screen_space/gbuffer.h"

namespace nns::classical_ao {

using screen_space::chebyshev_distance;
using screen_space::discontinuity_pixels;
using screen_space::GBuffer;

struct FailureBands {
  std::vector<std::string> names = {"halo", "border", "thin"};
  std::vector<std::vector<uint8_t>> masks;  // one per name, W*H
};

inline FailureBands failure_bands(const GBuffer& g) {
  const int W = g.width, H = g.height;
  const int64_t n = g.pixels();
  auto depth = [&](int x, int y) { return g.z[int64_t(y) * W + x]; };
  auto jump = [&](float a, float b) {
    return data::is_sky(a) != data::is_sky(b) || (!data::is_sky(a) && std::abs(a - b) > g.radius);
  };
  const std::vector<int> to_edge =
      chebyshev_distance(discontinuity_pixels(W, H, [&](int64_t i, int64_t j) { return jump(g.z[i], g.z[j]); }), W, H);
  FailureBands b;
  b.masks.assign(3, std::vector<uint8_t>(size_t(n), 0));
  const int halo = 3, border = std::max(1, int(0.08 * W)), thin = 6;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int64_t i = int64_t(y) * W + x;
      if (g.sky(i)) continue;
      b.masks[0][size_t(i)] = to_edge[size_t(i)] <= halo;
      b.masks[1][size_t(i)] = x < border || y < border || x >= W - border || y >= H - border;
      // Farther (or sky) within `thin` pixels on both sides, along x or along y.
      const float z = g.z[i];
      auto farther = [&](int sx, int sy) {
        float s = depth(sx, sy);
        return data::is_sky(s) || s > z + g.radius;
      };
      auto thin_along = [&](int ddx, int ddy) {
        bool a = false, c = false;
        for (int k = 1; k <= thin && !a; ++k) {
          int sx = x - k * ddx, sy = y - k * ddy;
          if (sx < 0 || sy < 0) break;
          a = farther(sx, sy);
        }
        for (int k = 1; k <= thin && !c; ++k) {
          int sx = x + k * ddx, sy = y + k * ddy;
          if (sx >= W || sy >= H) break;
          c = farther(sx, sy);
        }
        return a && c;
      };
      b.masks[2][size_t(i)] = thin_along(1, 0) || thin_along(0, 1);
    }
  return b;
}

}  // namespace nns::classical_ao
