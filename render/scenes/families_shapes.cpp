// Curved-surface families of the second generation: a sculpture garden of round
// solids, and an industrial hall of pipes, tanks and gratings.
#include "render/scenes/families.h"
#include "render/scenes/family_kit.h"

namespace nns::render {

// Round solids of every size (0.2-3 m) on a plaza: spheres resting on the ground (a
// contact point AO must darken), standing and lying tori, capsules, cones, domes,
// columns, bowls (concave), and a few big walls so not everything is open sky.
Scene make_round(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  uint32_t ground = s.add_material(random_material(rng, 0.25f, 0.6f));
  add_quad(s, {-60, 0, -60}, {120, 0, 0}, {0, 0, 120}, ground);
  for (int k = 0; k < 2; ++k) {
    uint32_t m = s.add_material(random_material(rng, 0.4f, 0.8f));
    add_box_yaw(s, {float(rng.uniform(-8, 8)), 2, float(rng.uniform(-14, -8))}, {float(rng.uniform(3, 8)), 2, 0.3f},
                float(rng.uniform(-0.5, 0.5)), m);
  }
  int n = scaled_count(22, st.density);
  for (int k = 0; k < n; ++k) {
    uint32_t m = s.add_material(random_material(rng));
    float size = float(std::exp(rng.uniform(std::log(0.2), std::log(3.0)))) * st.scale;
    Vec3 c(float(rng.uniform(-8, 8)), 0, float(rng.uniform(-10, 4)));
    float yaw = float(rng.uniform(0, 2 * kPi));
    Vec3 ax(std::cos(yaw), 0, std::sin(yaw));
    switch (rng.below(8)) {
      case 0:
        add_sphere(s, c + Vec3(0, size / 2, 0), size / 2, st.segments(32), m, st.smooth);
        break;
      case 1:  // standing ring, half sunk: an arch of revolution
        add_torus(s, c + Vec3(0, size * float(rng.uniform(0.1, 0.4)), 0), ax, size / 2, size * 0.1f, st.segments(40),
                  st.segments(16), m, st.smooth);
        break;
      case 2:
        add_torus(s, c + Vec3(0, size * 0.12f, 0), {0, 1, 0}, size / 2, size * 0.12f, st.segments(40), st.segments(16),
                  m, st.smooth);
        break;
      case 3: {  // capsule lying down
        float r = size * 0.2f;
        Vec3 a = c + Vec3(0, r, 0) - ax * (size / 2), b = c + Vec3(0, r, 0) + ax * (size / 2);
        add_round_cylinder(s, a, b, r, st.segments(24), m, st.smooth, false);
        add_sphere(s, a, r, st.segments(24), m, st.smooth);
        add_sphere(s, b, r, st.segments(24), m, st.smooth);
        break;
      }
      case 4:
        add_cone(s, c, size * 0.35f, size, st.segments(32), m, st.smooth);
        break;
      case 5:
        add_dome(s, c, size / 2, st.segments(32), m, st.smooth);
        break;
      case 6:
        add_round_cylinder(s, c, c + Vec3(0, size * float(rng.uniform(0.5, 2.0)), 0), size * 0.15f, st.segments(24), m,
                           st.smooth);
        break;
      default: {  // a bowl on a foot: the inside is a concave hemisphere
        float r = size / 2;
        std::vector<ProfilePoint> prof = {{0, 0}, {r * 0.3f, 0}, {r * 0.3f, 0}, {r * 0.2f, r * 0.15f}};
        for (int i = 0; i <= 8; ++i) {  // outer wall up, then the inner wall down
          float a = -kPi / 2 + kPi / 2 * float(i) / 8;
          prof.push_back({r * std::cos(a), r * 1.15f + r * std::sin(a)});
        }
        prof.push_back({r * 0.93f, r * 1.15f});
        for (int i = 8; i >= 0; --i) {
          float a = -kPi / 2 + kPi / 2 * float(i) / 8;
          prof.push_back({i == 0 ? 0.0f : r * 0.9f * std::cos(a), r * 1.15f + r * 0.9f * std::sin(a)});
        }
        add_lathe(s, c, {0, 1, 0}, prof, st.segments(32), m, st.smooth);
      }
    }
  }
  outdoor_lighting(s, rng);
  s.cameras = {{-7, 0.6f, -6}, {7, 2.5f, 7}, -30, 10};
  return s;
}

// An industrial hall: pipe runs at several heights with ball joints and flanges,
// vertical and horizontal tanks with domed ends, I-beam columns, a raised grating
// walkway of thin parallel bars, and valve wheels (tori with spokes).
Scene make_pipes(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  float hx = float(rng.uniform(5, 9)), hz = float(rng.uniform(5, 9)), h = float(rng.uniform(4, 7));
  uint32_t wall = s.add_material(random_material(rng, 0.4f, 0.8f));
  uint32_t floor = s.add_material(random_material(rng, 0.2f, 0.5f));
  add_room_shell(s, hx, hz, h, wall, floor);
  uint32_t metal = s.add_material(random_material(rng, 0.3f, 0.7f));
  for (int k = scaled_count(4, st.density); k > 0; --k) {  // tanks
    uint32_t m = s.add_material(random_material(rng, 0.3f, 0.8f));
    float r = float(rng.uniform(0.5, 1.5)) * st.scale;
    Vec3 c(float(rng.uniform(-hx + r + 0.3, hx - r - 0.3)), 0, float(rng.uniform(-hz + r + 0.3, hz - r - 0.3)));
    if (rng.below(2)) {
      float th = std::min(h - r - 0.3f, float(rng.uniform(1.5, 4)));
      add_round_cylinder(s, c, c + Vec3(0, th, 0), r, st.segments(32), m, st.smooth);
      add_dome(s, c + Vec3(0, th, 0), r, st.segments(32), m, st.smooth);
    } else {
      float len = float(rng.uniform(2, 4)), yaw = float(rng.uniform(0, kPi));
      Vec3 ax(std::cos(yaw), 0, std::sin(yaw));
      Vec3 mid = c + Vec3(0, r + 0.4f, 0);
      add_round_cylinder(s, mid - ax * (len / 2), mid + ax * (len / 2), r, st.segments(32), m, st.smooth, false);
      add_sphere(s, mid - ax * (len / 2), r, st.segments(32), m, st.smooth);
      add_sphere(s, mid + ax * (len / 2), r, st.segments(32), m, st.smooth);
      for (float e : {-0.3f, 0.3f})  // saddles it rests on
        add_box_yaw(s, c + ax * (len * e) + Vec3(0, 0.25f, 0), {0.15f, 0.25f, r * 0.8f}, -yaw, metal);
    }
  }
  // Pipe runs: axis-aligned segments joined by balls, flanges every few metres.
  for (int k = scaled_count(7, st.density); k > 0; --k) {
    uint32_t m = s.add_material(random_material(rng, 0.2f, 0.8f));
    float r = float(rng.uniform(0.04, 0.2));
    Vec3 p(float(rng.uniform(-hx + 0.5, hx - 0.5)), float(rng.uniform(0.3, h - 0.5)),
           float(rng.uniform(-hz + 0.5, hz - 0.5)));
    for (int seg = 2 + int(rng.below(4)); seg > 0; --seg) {
      int axis = int(rng.below(3));
      float len = float(rng.uniform(1, 5)) * (rng.below(2) ? 1.0f : -1.0f);
      Vec3 q = p;
      if (axis == 0) q.x = std::clamp(p.x + len, -hx + 0.3f, hx - 0.3f);
      else if (axis == 1) q.y = std::clamp(p.y + len, 0.2f, h - 0.3f);
      else q.z = std::clamp(p.z + len, -hz + 0.3f, hz - 0.3f);
      if (length(q - p) < 0.3f) continue;
      add_round_cylinder(s, p, q, r, st.segments(16), m, st.smooth, false);
      add_sphere(s, q, r * 1.25f, st.segments(16), m, st.smooth);
      Vec3 dir = normalize(q - p);
      for (float t = 1.0f; t < length(q - p) - 0.3f; t += 1.5f)
        add_round_cylinder(s, p + dir * t, p + dir * (t + 0.05f), r * 1.5f, st.segments(16), m, st.smooth);
      p = q;
    }
  }
  for (int k = scaled_count(3, st.density); k > 0; --k) {  // valve wheels
    Vec3 c(float(rng.uniform(-hx + 1, hx - 1)), float(rng.uniform(0.8, 1.6)), float(rng.uniform(-hz + 1, hz - 1)));
    float R = float(rng.uniform(0.15, 0.35));
    add_torus(s, c, {0, 0, 1}, R, 0.02f, st.segments(24), st.segments(8), metal, st.smooth);
    for (int i = 0; i < 3; ++i) {
      float a = kPi * float(i) / 3;
      Vec3 d(std::cos(a) * R, std::sin(a) * R, 0);
      add_round_cylinder(s, c - d, c + d, 0.012f, st.segments(8), metal, st.smooth, false);
    }
    add_round_cylinder(s, c, c + Vec3(0, 0, -0.4f), 0.03f, st.segments(10), metal, st.smooth);
    add_round_cylinder(s, c + Vec3(0, 0, -0.4f), {c.x, 0, c.z - 0.4f}, 0.06f, st.segments(12), metal, st.smooth);
  }
  if (rng.below(3) != 0) {  // a raised grating walkway on I-beam posts along one wall
    float y = float(rng.uniform(1.8, std::min(3.0f, h - 1.6f))), w = float(rng.uniform(1.0, 1.6));
    float z0 = -hz + 0.1f;
    for (float x = -hx + 0.1f; x < hx - 0.1f; x += 0.04f)
      add_box(s, {x, y - 0.03f, z0}, {x + 0.008f, y, z0 + w}, metal);
    add_box(s, {-hx, y - 0.15f, z0 + w}, {hx, y - 0.03f, z0 + w + 0.02f}, metal);  // edge beam
    for (float x = -hx + 1; x < hx; x += 2.5f) {
      add_box(s, {x - 0.1f, 0, z0 + w - 0.01f}, {x + 0.1f, y - 0.15f, z0 + w + 0.01f}, metal);
      add_box(s, {x - 0.1f, 0, z0 + w - 0.1f}, {x + 0.1f, y - 0.15f, z0 + w - 0.09f}, metal);
      add_box(s, {x - 0.01f, 0, z0 + w - 0.1f}, {x + 0.01f, y - 0.15f, z0 + w}, metal);
      add_round_cylinder(s, {x, y, z0 + w}, {x, y + 1.0f, z0 + w}, 0.02f, st.segments(8), metal, st.smooth, false);
    }
    add_round_cylinder(s, {-hx, y + 1.0f, z0 + w}, {hx, y + 1.0f, z0 + w}, 0.025f, st.segments(8), metal, st.smooth);
  }
  indoor_lights(s, rng, hx, hz, h);
  s.cameras = {{-hx + 0.5f, 0.6f, -hz + 0.5f}, {hx - 0.5f, 2.2f, hz - 0.5f}, -35, 25};
  return s;
}

}  // namespace nns::render
