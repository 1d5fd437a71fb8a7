#pragma once
// Temporal stability on camera paths: which pixel of the previous frame shows the same
// surface point as a pixel of this frame (reprojection with the views' worldToCamera
// matrices), and the flicker statistics eval-ao reports per method.
//
// A pixel of frame t maps to frame t-1 when it is not sky, its view-space position moved
// into the previous camera lies in front of it and projects onto the screen, and the
// previous frame's depth at that (nearest) pixel agrees with the moved point's depth to
// within 3% (otherwise the point was hidden or off-screen then: a disocclusion, skipped).
// Without matrices (or for a still camera) the map is the identity on non-sky pixels.
//
// For a method m against the ground truth g, over the mapped pixels i -> j of a pair:
//   flicker(m)     = mean |m_t(i) - m_t-1(j)|        (the ground truth's own: flicker(g))
//   temporal error = mean |(m_t(i) - m_t-1(j)) - (g_t(i) - g_t-1(j))|
// The ratio flicker(m) / flicker(g) is 1 for a method that changes exactly as much as the
// truth; the temporal error is 0 only for one that changes exactly as the truth does,
// so it also catches noise that a ratio near 1 can hide.
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "screen_space/gbuffer.h"

namespace nns::classical_ao {

using screen_space::GBuffer;

// prev_index[i] = pixel of the previous frame, or -1.
inline std::vector<int64_t> reproject_to_previous(const GBuffer& cur,
                                                  const std::optional<std::array<float, 16>>& cur_w2c,
                                                  const GBuffer& prev,
                                                  const std::optional<std::array<float, 16>>& prev_w2c) {
  std::vector<int64_t> map(size_t(cur.pixels()), -1);
  const bool same_size = cur.width == prev.width && cur.height == prev.height;
  // rel = prev_w2c * inverse(cur_w2c); both are rigid (rotation + translation).
  double rel[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  const bool warp = cur_w2c && prev_w2c;
  if (warp) {
    const auto& a = *cur_w2c;
    const auto& b = *prev_w2c;
    double inv[12];  // inverse of a rigid [R t]: [R^T, -R^T t]
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) inv[r * 4 + c] = a[size_t(c * 4 + r)];
      inv[r * 4 + 3] =
          -(double(a[size_t(0 * 4 + r)]) * a[3] + double(a[size_t(4 + r)]) * a[7] + double(a[size_t(8 + r)]) * a[11]);
    }
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) {
        double s = c == 3 ? b[size_t(r * 4 + 3)] : 0.0;
        for (int k = 0; k < 3; ++k) s += double(b[size_t(r * 4 + k)]) * inv[k * 4 + c];
        rel[r * 4 + c] = s;
      }
  } else if (!same_size) {
    return map;
  }
  for (int y = 0; y < cur.height; ++y)
    for (int x = 0; x < cur.width; ++x) {
      const int64_t i = int64_t(y) * cur.width + x;
      if (cur.sky(i)) continue;
      if (!warp) {
        if (!prev.sky(i)) map[size_t(i)] = i;
        continue;
      }
      const Vec3 p = cur.position(x, y);
      const Vec3 q{float(rel[0] * p.x + rel[1] * p.y + rel[2] * p.z + rel[3]),
                   float(rel[4] * p.x + rel[5] * p.y + rel[6] * p.z + rel[7]),
                   float(rel[8] * p.x + rel[9] * p.y + rel[10] * p.z + rel[11])};
      if (!(q.z < 0)) continue;
      float px, py;
      prev.project(q, px, py);
      if (!prev.on_screen(px, py)) continue;
      const int64_t j = prev.clamped_index(px, py);
      if (prev.sky(j) || std::abs(prev.z[j] + q.z) > 0.03f * -q.z) continue;
      map[size_t(i)] = j;
    }
  return map;
}

// Accumulates one method's (or the ground truth's) temporal statistics over frame pairs.
struct TemporalStats {
  double flicker_sum = 0, error_sum = 0, coverage_sum = 0;
  int pairs = 0;

  // m, m_prev: the method's frames t and t-1; g, g_prev: the ground truth's.
  void add_pair(const std::vector<int64_t>& map, const float* m, const float* m_prev, const float* g,
                const float* g_prev) {
    double f = 0, e = 0;
    int64_t n = 0;
    for (size_t i = 0; i < map.size(); ++i) {
      const int64_t j = map[i];
      if (j < 0) continue;
      const double dm = double(m[i]) - m_prev[j], dg = double(g[i]) - g_prev[j];
      f += std::abs(dm);
      e += std::abs(dm - dg);
      ++n;
    }
    if (!n) return;
    flicker_sum += f / double(n);
    error_sum += e / double(n);
    coverage_sum += double(n) / double(map.size());
    ++pairs;
  }
  double flicker() const { return pairs ? flicker_sum / pairs : std::nan(""); }
  double error() const { return pairs ? error_sum / pairs : std::nan(""); }
  double coverage() const { return pairs ? coverage_sum / pairs : std::nan(""); }
};

// The camera path a view belongs to, from a file stem "<scene>-pNN-fNNN": the stem
// without its frame number, and the frame number; empty when the stem has no "-f<digits>"
// suffix (a still view, not a path frame).
inline std::string path_of_frame(const std::string& stem, int& frame) {
  const size_t k = stem.rfind("-f");
  if (k == std::string::npos || k + 2 >= stem.size()) return "";
  for (size_t c = k + 2; c < stem.size(); ++c)
    if (stem[c] < '0' || stem[c] > '9') return "";
  frame = std::stoi(stem.substr(k + 2));
  return stem.substr(0, k);
}

}  // namespace nns::classical_ao
