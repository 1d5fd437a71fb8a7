#pragma once
// Shared pieces of the second and third generations of scene families (families_*.cpp
// that use mesh_builder.h): room shells, indoor lamps, furniture made of round and
// bevelled parts, generated clutter, and the per-scene draws every such family makes
// (smooth or flat normals, density, object scale).
#include <algorithm>
#include <cmath>

#include "render/scenes/family_util.h"
#include "render/scenes/mesh_builder.h"

namespace nns::render {

// What real scenes vary and a family should not fix: whether curved parts carry
// interpolated normals (3 scenes in 4; the rest are faceted like low-poly assets),
// how much stuff there is, and how big it is.
struct SceneStyle {
  bool smooth = true;
  float density = 1;  // multiplies object counts, in [0.5, 2]
  float scale = 1;    // multiplies object sizes, in [0.7, 1.4]
  int segments(int base) const { return smooth ? base : std::max(6, base / 2); }
};
inline SceneStyle draw_style(Rng& rng) {
  SceneStyle st;
  st.smooth = rng.below(4) != 0;
  st.density = float(std::exp(rng.uniform(std::log(0.5), std::log(2.0))));
  st.scale = float(rng.uniform(0.7, 1.4));
  return st;
}
inline int scaled_count(int base, float density) { return std::max(1, int(std::lround(float(base) * density))); }

// Floor, ceiling and four walls of [-hx, hx] x [0, h] x [-hz, hz], 0.1 thick.
inline void add_room_shell(Scene& s, float hx, float hz, float h, uint32_t wall, uint32_t floor) {
  add_box(s, {-hx - 0.1f, -0.1f, -hz - 0.1f}, {hx + 0.1f, 0, hz + 0.1f}, floor);
  add_box(s, {-hx - 0.1f, h, -hz - 0.1f}, {hx + 0.1f, h + 0.1f, hz + 0.1f}, wall);
  add_wall(s, true, -hz - 0.05f, -hx, hx, h, 0.1f, {}, wall);
  add_wall(s, true, hz + 0.05f, -hx, hx, h, 0.1f, {}, wall);
  add_wall(s, false, -hx - 0.05f, -hz, hz, h, 0.1f, {}, wall);
  add_wall(s, false, hx + 0.05f, -hz, hz, h, 0.1f, {}, wall);
}

// A square ceiling lamp of side `lw` centred at `lc` (just under the ceiling): a panel
// that rays see (emission) and the rect light it stands for, facing down.
inline void add_lamp_panel(Scene& s, Vec3 lc, float lw, Vec3 radiance) {
  uint32_t lamp = s.add_material({{0.8f, 0.8f, 0.8f}, radiance * 0.25f});
  add_quad(s, lc - Vec3(lw / 2, -0.005f, lw / 2), {lw, 0, 0}, {0, 0, lw}, lamp);
  s.rects.push_back({lc - Vec3(lw / 2, 0, lw / 2), {lw, 0, 0}, {0, 0, lw}, radiance});
}
inline constexpr Vec3 kLampRadiance{12.0f, 11.4f, 10.2f};

// A ceiling lamp somewhere over the middle of the room.
inline void add_ceiling_panel(Scene& s, Rng& rng, float hx, float hz, float h) {
  float lw = float(rng.uniform(0.4, 1.0));
  Vec3 lc(float(rng.uniform(-hx / 2, hx / 2)), h - 0.01f, float(rng.uniform(-hz / 2, hz / 2)));
  add_lamp_panel(s, lc, lw, kLampRadiance);
}

// A ceiling panel and 1-2 point lamps; a black sky. Enough light for the GI presets;
// AO does not need it.
inline void indoor_lights(Scene& s, Rng& rng, float hx, float hz, float h) {
  add_ceiling_panel(s, rng, hx, hz, h);
  for (int k = 1 + int(rng.below(2)); k > 0; --k)
    s.points.push_back({{float(rng.uniform(-hx * 0.7, hx * 0.7)), float(rng.uniform(1.0, h - 0.3)),
                         float(rng.uniform(-hz * 0.7, hz * 0.7))},
                        Vec3(4.0f, 3.5f, 2.7f)});
  s.sky = Sky::constant({0, 0, 0});
}

// A random turned object (vase, bowl, bottle, lamp base): a lathe of a wobbly
// profile, `h` tall, up to `r` wide, standing on `base`.
inline void add_turned_object(Scene& s, Rng& rng, Vec3 base, float r, float h, uint32_t m, const SceneStyle& st) {
  std::vector<ProfilePoint> prof = {{0, 0}, {r * float(rng.uniform(0.5, 0.9)), 0}};
  int n = 4 + int(rng.below(4));
  for (int i = 1; i <= n; ++i) prof.push_back({r * float(rng.uniform(0.25, 1.0)), h * float(i) / float(n)});
  prof.push_back({0, h});
  add_lathe(s, base, {0, 1, 0}, prof, st.segments(24), m, st.smooth);
}

// A round table: a disc top on a pedestal (lathe with creases at the top's edges).
inline void add_round_table(Scene& s, Vec3 c, float r, float h, uint32_t m, const SceneStyle& st) {
  float t = 0.04f, foot = r * 0.45f;
  add_lathe(s, c, {0, 1, 0},
            {{0, 0},
             {foot, 0},
             {foot, 0},
             {foot * 0.8f, 0.05f},
             {0.05f, 0.12f},
             {0.04f, h - t - 0.05f},
             {0.08f, h - t},
             {r, h - t},
             {r, h - t},
             {r, h},
             {r, h},
             {0, h}},
            st.segments(32), m, st.smooth);
}

// A chair of a bevelled seat and back on four round legs, facing `yaw`.
inline void add_round_chair(Scene& s, Vec3 c, float yaw, uint32_t m, const SceneStyle& st) {
  float seat = 0.45f, w = 0.22f;
  float cy = std::cos(yaw), sy = std::sin(yaw);
  auto local = [&](float x, float z) { return c + Vec3(cy * x + sy * z, 0, -sy * x + cy * z); };
  add_bevelled_box(s, c + Vec3(0, seat, 0), {w, 0.03f, w}, 0.02f, yaw, m, st.smooth, 2);
  for (int i = 0; i < 4; ++i) {
    Vec3 p = local((i & 1 ? 1 : -1) * (w - 0.03f), (i & 2 ? 1 : -1) * (w - 0.03f));
    add_round_cylinder(s, p, p + Vec3(0, seat - 0.03f, 0), 0.018f, st.segments(10), m, st.smooth, false);
  }
  add_bevelled_box(s, local(0, -w + 0.02f) + Vec3(0, seat + 0.3f, 0), {w, 0.22f, 0.02f}, 0.015f, yaw, m, st.smooth, 2);
}

// A sofa (or armchair, when short): seat, back and arms as bevelled boxes, cushions
// as flattened blobs.
inline void add_sofa(Scene& s, Rng& rng, Vec3 c, float len, float yaw, uint32_t m, const SceneStyle& st) {
  float d = 0.45f, cy = std::cos(yaw), sy = std::sin(yaw);
  auto local = [&](float x, float y, float z) { return c + Vec3(cy * x + sy * z, y, -sy * x + cy * z); };
  float b = 0.06f;
  add_bevelled_box(s, local(0, 0.22f, 0), {len / 2, 0.22f, d}, b, yaw, m, st.smooth);
  add_bevelled_box(s, local(0, 0.55f, -d + 0.1f), {len / 2, 0.35f, 0.1f}, b, yaw, m, st.smooth);
  for (float side : {-1.0f, 1.0f})
    add_bevelled_box(s, local(side * (len / 2 - 0.1f), 0.5f, 0), {0.1f, 0.18f, d}, b, yaw, m, st.smooth);
  int cushions = int(rng.below(3));
  for (int i = 0; i < cushions; ++i) {
    float x = float(rng.uniform(-len / 2 + 0.35, len / 2 - 0.35));
    uint64_t seed = rng.next_u64();
    add_displaced_sphere(
        s, local(x, 0.62f, -d + 0.3f), {0.2f, 0.16f, 0.07f}, 2,
        [seed](Vec3 p) { return 0.1f * fbm(seed, p * 2.0f, 2); }, s.add_material(random_material(rng)), st.smooth);
  }
}

// Something generated, about `size` across, resting on the plane y = `floor_y` at
// (x, z); returns its height. The kinds span what real clutter is made of: rounded
// boxes, balls, blobs and rocks, rings, cones, turned objects, and CSG-like unions
// of overlapping parts.
inline float add_random_object(Scene& s, Rng& rng, float x, float z, float floor_y, float size, const SceneStyle& st) {
  uint32_t m = s.add_material(random_material(rng));
  Vec3 base(x, floor_y, z);
  float yaw = float(rng.uniform(0, kPi));
  switch (rng.below(8)) {
    case 0: {  // rounded box
      Vec3 half(size * float(rng.uniform(0.3, 0.6)), size * float(rng.uniform(0.2, 0.6)),
                size * float(rng.uniform(0.3, 0.6)));
      float bevel = std::min({half.x, half.y, half.z}) * float(rng.uniform(0.1, 0.6));
      add_bevelled_box(s, base + Vec3(0, half.y, 0), half, bevel, yaw, m, st.smooth);
      return 2 * half.y;
    }
    case 1: {  // ball
      float r = size * float(rng.uniform(0.2, 0.5));
      add_sphere(s, base + Vec3(0, r, 0), r, st.segments(24), m, st.smooth);
      return 2 * r;
    }
    case 2: {  // blob or rock
      float r = size * float(rng.uniform(0.25, 0.5));
      uint64_t seed = rng.next_u64();
      float amp = float(rng.uniform(0.1, 0.35)), freq = float(rng.uniform(1.0, 3.0));
      Vec3 radii(r, r * float(rng.uniform(0.5, 1.0)), r * float(rng.uniform(0.7, 1.2)));
      add_displaced_sphere(
          s, base + Vec3(0, radii.y * 0.8f, 0), radii, 3, [=](Vec3 p) { return amp * fbm(seed, p * freq, 3); }, m,
          st.smooth);
      return radii.y * 1.8f;
    }
    case 3: {  // ring lying down or standing up
      float R = size * float(rng.uniform(0.25, 0.45)), r = R * float(rng.uniform(0.15, 0.4));
      if (rng.below(2)) {
        add_torus(s, base + Vec3(0, r, 0), {0, 1, 0}, R, r, st.segments(32), st.segments(16), m, st.smooth);
        return 2 * r;
      }
      add_torus(s, base + Vec3(0, R + r, 0), {std::cos(yaw), 0, std::sin(yaw)}, R, r, st.segments(32), st.segments(16),
                m, st.smooth);
      return 2 * (R + r);
    }
    case 4: {  // cone
      float r = size * float(rng.uniform(0.2, 0.45)), h = size * float(rng.uniform(0.4, 1.0));
      add_cone(s, base, r, h, st.segments(24), m, st.smooth);
      return h;
    }
    case 5: {  // turned object
      float h = size * float(rng.uniform(0.4, 1.0));
      add_turned_object(s, rng, base, size * float(rng.uniform(0.15, 0.35)), h, m, st);
      return h;
    }
    case 6: {  // union: a box with a cylinder through it and a ball on top
      Vec3 half(size * 0.4f, size * 0.25f, size * 0.3f);
      add_bevelled_box(s, base + Vec3(0, half.y, 0), half, half.y * 0.2f, yaw, m, st.smooth, 2);
      Vec3 ax(std::cos(yaw), 0, -std::sin(yaw));
      add_round_cylinder(s, base + Vec3(0, half.y, 0) - ax * (half.x * 1.3f),
                         base + Vec3(0, half.y, 0) + ax * (half.x * 1.3f), half.y * 0.6f, st.segments(20), m,
                         st.smooth);
      add_sphere(s, base + Vec3(0, 2 * half.y + size * 0.1f, 0), size * 0.18f, st.segments(20), m, st.smooth);
      return 2 * half.y + size * 0.28f;
    }
    default: {  // lying cylinder (a log, a barrel, a pipe)
      float r = size * float(rng.uniform(0.12, 0.3)), len = size * float(rng.uniform(0.6, 1.4));
      Vec3 ax(std::cos(yaw), 0, -std::sin(yaw));
      add_round_cylinder(s, base + Vec3(0, r, 0) - ax * (len / 2), base + Vec3(0, r, 0) + ax * (len / 2), r,
                         st.segments(24), m, st.smooth);
      return 2 * r;
    }
  }
}

}  // namespace nns::render
