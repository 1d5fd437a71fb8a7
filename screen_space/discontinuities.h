#pragma once
// Where the screen-space surface breaks, and how far each pixel is from such a break:
// the pixels where screen-space methods fail (eval-ao's halo band) and where contact
// shadows and creases live (eval-gi's distance bands).
//
//   discontinuity_pixels(w, h, differ)  both pixels of every 4-neighbour pair that
//                                       `differ(i, j)` says lie on different surfaces
//   chebyshev_distance(seeds, w, h)     per pixel, max(|dx|, |dy|) to the nearest seed: the
//                                       half-width of the smallest square window around the
//                                       pixel that holds one (two-pass chamfer, exact for L∞)
//   surface_break(g, depth_ratio, crease_cos)  the `differ` of a G-buffer: sky against
//                                       geometry, a depth jump of more than `depth_ratio`
//                                       relative to the nearer pixel, or normals more than
//                                       acos(crease_cos) apart (a crease)
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "screen_space/gbuffer.h"

namespace nns::screen_space {

template <class Differ>
std::vector<uint8_t> discontinuity_pixels(int w, int h, Differ&& differ) {
  std::vector<uint8_t> mark(size_t(w) * size_t(h), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int64_t i = int64_t(y) * w + x;
      if (x + 1 < w && differ(i, i + 1)) mark[size_t(i)] = mark[size_t(i + 1)] = 1;
      if (y + 1 < h && differ(i, i + w)) mark[size_t(i)] = mark[size_t(i + w)] = 1;
    }
  return mark;
}

// No seed at all: every distance is kNoSeed.
inline constexpr int kNoSeed = std::numeric_limits<int>::max() / 2;

inline std::vector<int> chebyshev_distance(const std::vector<uint8_t>& seeds, int w, int h) {
  std::vector<int> d(seeds.size());
  for (size_t i = 0; i < seeds.size(); ++i) d[i] = seeds[i] ? 0 : kNoSeed;
  auto at = [&](int x, int y) -> int& { return d[size_t(y) * size_t(w) + size_t(x)]; };
  // Forward pass takes the four neighbours already visited (left, up-left, up, up-right),
  // the backward pass the other four; with unit steps in all eight directions the result
  // is the L∞ distance (Rosenfeld and Pfaltz's chessboard transform).
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int& v = at(x, y);
      if (x > 0) v = std::min(v, at(x - 1, y) + 1);
      if (y > 0) {
        v = std::min(v, at(x, y - 1) + 1);
        if (x > 0) v = std::min(v, at(x - 1, y - 1) + 1);
        if (x + 1 < w) v = std::min(v, at(x + 1, y - 1) + 1);
      }
    }
  for (int y = h - 1; y >= 0; --y)
    for (int x = w - 1; x >= 0; --x) {
      int& v = at(x, y);
      if (x + 1 < w) v = std::min(v, at(x + 1, y) + 1);
      if (y + 1 < h) {
        v = std::min(v, at(x, y + 1) + 1);
        if (x + 1 < w) v = std::min(v, at(x + 1, y + 1) + 1);
        if (x > 0) v = std::min(v, at(x - 1, y + 1) + 1);
      }
    }
  return d;
}

// A relative depth threshold rather than a world-space one, so it needs no scene scale;
// a plane seen at a grazing angle far off can exceed it between rows (its depth grows
// fast), which marks the far floor near the horizon as broken too.
inline auto surface_break(const GBuffer& g, float depth_ratio, float crease_cos) {
  return [&g, depth_ratio, crease_cos](int64_t i, int64_t j) {
    const bool si = g.sky(i), sj = g.sky(j);
    if (si || sj) return si != sj;
    const float zi = g.z[i], zj = g.z[j];
    if (std::abs(zi - zj) > depth_ratio * std::min(zi, zj)) return true;
    return dot(g.normal(i), g.normal(j)) < crease_cos;
  };
}

}  // namespace nns::screen_space
