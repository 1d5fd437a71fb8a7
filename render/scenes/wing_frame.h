#pragma once
// A building wing's frame around a rectangular court (families_courtyard.cpp,
// families_halls.cpp): four wings, each the same code turned a quarter turn further.
#include <algorithm>
#include <vector>

#include "render/scenes/family_util.h"

namespace nns::render {

// A wing's frame: u across it (0 on the courtyard facade's centre line, growing away
// from the court), v along it; wing k is turned k quarter turns about +y. Boxes stay
// axis-aligned under quarter turns.
struct Wing {
  int k = 0;
  float c = 0;  // the courtyard's half-size towards this wing
  Vec3 at(float u, float y, float v) const {
    const float a = c + u;
    switch (k) {
      case 0:
        return {a, y, v};
      case 1:
        return {-v, y, a};
      case 2:
        return {-a, y, -v};
      default:
        return {v, y, -a};
    }
  }
  void box(Scene& s, float u0, float y0, float v0, float u1, float y1, float v1, uint32_t m) const {
    Vec3 a = at(u0, y0, v0), b = at(u1, y1, v1);
    add_box(s, vmin(a, b), vmax(a, b), m);
  }
  // A wall on the line u = `u` (0.4 thick) from v0 to v1, y0 to y1, with holes (a0/a1
  // along v, sorted): add_wall_band on the world line the quarter turn maps it to.
  void wall(Scene& s, float u, float v0, float v1, float y0, float y1, const std::vector<Opening>& holes,
            uint32_t m) const {
    const bool along_x = k % 2 != 0, flip = k == 1 || k == 2;  // world a = -v for k = 1, 2
    const float plane = k < 2 ? c + u : -(c + u);
    std::vector<Opening> world = holes;
    if (flip) {
      std::reverse(world.begin(), world.end());
      for (Opening& h : world) h = {-h.a1, -h.a0, h.y0, h.y1};
    }
    add_wall_band(s, along_x, plane, flip ? -v1 : v0, flip ? -v0 : v1, y0, y1, 0.4f, world, m);
  }
};

// The world directions of a wing's u (away from the court) and v (along it).
inline Vec3 wing_u(const Wing& w) {
  const Vec3 d[4] = {{1, 0, 0}, {0, 0, 1}, {-1, 0, 0}, {0, 0, -1}};
  return d[w.k & 3];
}
inline Vec3 wing_v(const Wing& w) {
  const Vec3 d[4] = {{0, 0, 1}, {-1, 0, 0}, {0, 0, -1}, {1, 0, 0}};
  return d[w.k & 3];
}

}  // namespace nns::render
