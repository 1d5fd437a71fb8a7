#pragma once
// Data augmentation by the eight symmetries of the square (four 90-degree rotations,
// each optionally mirrored), applied so that vectors stay right: a camera-space normal is
// a direction in the image plane too, so rotating the picture rotates (N.X, N.Y) and
// mirroring it negates N.X (Deep Shading, Nalbach et al. 2017, sec. 4.1). Depth, AO and
// colours are scalars per pixel and only move.
//
//   Dihedral a = Dihedral::random(rng);
//   transform_planes(names, src, w, h, a, dst);   // dst is h x w when a.swaps_axes()
//   View v2 = transform_view(v, a);                // also fovY and worldToCamera
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/rng.h"
#include "data/view.h"

namespace nns::data {

struct Dihedral {
  int quarter_turns = 0;   // counter-clockwise on screen, 0..3
  bool mirror = false;     // then mirrored left-right

  static Dihedral random(Rng& rng) {
    uint64_t r = rng.below(8);
    return {int(r & 3), (r & 4) != 0};
  }
  bool swaps_axes() const { return quarter_turns % 2 == 1; }

  // Where source pixel (x, y) of a w x h image lands.
  void map_pixel(int x, int y, int w, int h, int* ox, int* oy) const {
    for (int k = 0; k < quarter_turns; ++k) {  // one CCW turn: (x, y) -> (y, w-1-x), w <-> h
      int nx = y, ny = w - 1 - x;
      x = nx, y = ny;
      std::swap(w, h);
    }
    if (mirror) x = w - 1 - x;
    *ox = x, *oy = y;
  }
  // How an in-plane vector (vx right, vy up) turns: CCW by 90 maps (x, y) -> (-y, x).
  void map_vector(float* vx, float* vy) const {
    for (int k = 0; k < quarter_turns; ++k) {
      float t = *vx;
      *vx = -*vy, *vy = t;
    }
    if (mirror) *vx = -*vx;
  }
};

// src: C planes of h x w (names[c] is plane c's channel); dst: C planes of the
// transformed size. "N.X"/"N.Y" must both be present or both absent.
inline void transform_planes(const std::vector<std::string>& names, const float* src, int w, int h,
                             const Dihedral& a, float* dst) {
  int ix = -1, iy = -1;
  for (int c = 0; c < int(names.size()); ++c) {
    if (names[size_t(c)] == "N.X") ix = c;
    if (names[size_t(c)] == "N.Y") iy = c;
  }
  if ((ix < 0) != (iy < 0))
    throw std::invalid_argument("augmentation needs both N.X and N.Y to rotate normals, got only " +
                                std::string(ix < 0 ? "N.Y" : "N.X"));
  const int ow = a.swaps_axes() ? h : w;
  const size_t n = size_t(w) * size_t(h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int ox, oy;
      a.map_pixel(x, y, w, h, &ox, &oy);
      const size_t s = size_t(y) * size_t(w) + size_t(x), d = size_t(oy) * size_t(ow) + size_t(ox);
      for (size_t c = 0; c < names.size(); ++c) dst[c * n + d] = src[c * n + s];
      if (ix >= 0) {
        float vx = src[size_t(ix) * n + s], vy = src[size_t(iy) * n + s];
        a.map_vector(&vx, &vy);
        dst[size_t(ix) * n + d] = vx;
        dst[size_t(iy) * n + d] = vy;
      }
    }
}

// The whole view: planes, and the header that depends on orientation. A quarter turn
// of a W x H image makes the old horizontal field of view the new vertical one; the
// camera matrix gets the same in-plane rotation (and mirror) as the normals.
inline View transform_view(const View& v, const Dihedral& a) {
  View o = v;
  if (a.swaps_axes()) {
    std::swap(o.width, o.height);
    const double half = v.fov_y_deg * M_PI / 360.0;
    o.fov_y_deg = float(360.0 / M_PI * std::atan(std::tan(half) * v.width / v.height));
  }
  std::vector<std::string> names;
  for (auto& [name, plane] : v.channels) names.push_back(name);
  const size_t n = size_t(v.width) * size_t(v.height);
  std::vector<float> src(names.size() * n), dst(src.size());
  for (size_t c = 0; c < names.size(); ++c) std::copy(v.channels.at(names[c]).begin(), v.channels.at(names[c]).end(), src.begin() + long(c * n));
  const bool normals = v.has("N.X") && v.has("N.Y");
  std::vector<std::string> plane_names = names;
  if (!normals)  // rotate a lone N.X or N.Y as a scalar rather than refuse the view
    for (auto& s : plane_names)
      if (s == "N.X" || s == "N.Y") s += " (lone)";
  transform_planes(plane_names, src.data(), v.width, v.height, a, dst.data());
  for (size_t c = 0; c < names.size(); ++c)
    o.channels[names[c]].assign(dst.begin() + long(c * n), dst.begin() + long((c + 1) * n));
  if (v.world_to_camera) {
    // Rows 0 and 1 of M are the camera's x and y axes: they turn like a normal's x and y.
    auto& m = *o.world_to_camera;
    for (int col = 0; col < 4; ++col) {
      float x = m[size_t(col)], y = m[size_t(4 + col)];
      a.map_vector(&x, &y);
      m[size_t(col)] = x, m[size_t(4 + col)] = y;
    }
  }
  return o;
}

}  // namespace nns::data
