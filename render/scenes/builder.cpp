#include "render/scenes/builder.h"

#include <cmath>

#include "render/sampling.h"

namespace nns::render {

void add_quad(Scene& s, Vec3 p, Vec3 e1, Vec3 e2, uint32_t material) {
  uint32_t b = uint32_t(s.positions.size());
  s.positions.insert(s.positions.end(), {p, p + e1, p + e1 + e2, p + e2});
  s.triangles.push_back({{b, b + 1, b + 2}, material});
  s.triangles.push_back({{b, b + 2, b + 3}, material});
}

namespace {
// A box from a centre and three (orthogonal) half-axes.
void add_parallelepiped(Scene& s, Vec3 c, Vec3 ax, Vec3 ay, Vec3 az, uint32_t m) {
  Vec3 o = c - ax - ay - az;
  Vec3 x = ax * 2, y = ay * 2, z = az * 2;
  add_quad(s, o, x, y, m);
  add_quad(s, o + z, x, y, m);
  add_quad(s, o, y, z, m);
  add_quad(s, o + x, y, z, m);
  add_quad(s, o, x, z, m);
  add_quad(s, o + y, x, z, m);
}
}  // namespace

void add_box(Scene& s, Vec3 lo, Vec3 hi, uint32_t material) {
  Vec3 h = (hi - lo) * 0.5f;
  add_parallelepiped(s, lo + h, {h.x, 0, 0}, {0, h.y, 0}, {0, 0, h.z}, material);
}

void add_box_yaw(Scene& s, Vec3 centre, Vec3 half, float yaw, uint32_t material) {
  float c = std::cos(yaw), sn = std::sin(yaw);
  add_parallelepiped(s, centre, Vec3(c, 0, -sn) * half.x, {0, half.y, 0}, Vec3(sn, 0, c) * half.z, material);
}

void add_cylinder(Scene& s, Vec3 base, float radius, float height, int sides, uint32_t material) {
  uint32_t b = uint32_t(s.positions.size());
  for (int i = 0; i < sides; ++i) {
    float a = 2 * kPi * float(i) / float(sides);
    Vec3 off(radius * std::cos(a), 0, radius * std::sin(a));
    s.positions.push_back(base + off);
    s.positions.push_back(base + off + Vec3(0, height, 0));
  }
  uint32_t cb = uint32_t(s.positions.size());
  s.positions.push_back(base);
  s.positions.push_back(base + Vec3(0, height, 0));
  for (int i = 0; i < sides; ++i) {
    uint32_t j = (i + 1) % sides;
    uint32_t a0 = b + 2 * i, a1 = a0 + 1, b0 = b + 2 * j, b1 = b0 + 1;
    s.triangles.push_back({{a0, b0, b1}, material});
    s.triangles.push_back({{a0, b1, a1}, material});
    s.triangles.push_back({{cb, b0, a0}, material});
    s.triangles.push_back({{cb + 1, a1, b1}, material});
  }
}

void add_beam(Scene& s, Vec3 a, Vec3 b, float thickness, uint32_t material) {
  Vec3 axis = (b - a) * 0.5f;
  Vec3 dir = normalize(axis);
  Frame f(dir);
  add_parallelepiped(s, a + axis, f.t * (thickness * 0.5f), f.b * (thickness * 0.5f), axis, material);
}

}  // namespace nns::render
