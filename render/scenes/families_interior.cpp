// Interior families of the second generation: living rooms of round and upholstered
// furniture, rooms cluttered with random generated meshes, and stairwells (spiral and
// switchback).
#include "render/scenes/families.h"
#include "render/scenes/family_kit.h"

namespace nns::render {

// A living room: sofas and armchairs of bevelled boxes and cushions, round tables with
// turned objects on them, chairs on round legs, bookshelves of uneven books, a rug,
// floor lamps, skirting boards (long thin creases along every wall).
Scene make_lounge(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  float hx = float(rng.uniform(2.5, 5)), hz = float(rng.uniform(2.5, 5)), h = float(rng.uniform(2.5, 3.5));
  uint32_t wall = s.add_material(random_material(rng, 0.5f, 0.85f));
  uint32_t floor = s.add_material(random_material(rng, 0.2f, 0.6f));
  add_room_shell(s, hx, hz, h, wall, floor);
  uint32_t trim = s.add_material(random_material(rng, 0.5f, 0.9f));
  for (float side : {-1.0f, 1.0f}) {
    add_box(s, {-hx, 0, side * hz - 0.02f}, {hx, 0.1f, side * hz + 0.02f}, trim);
    add_box(s, {side * hx - 0.02f, 0, -hz}, {side * hx + 0.02f, 0.1f, hz}, trim);
  }
  if (rng.below(2))
    add_box(s, {float(rng.uniform(-hx / 2, 0)), 0, float(rng.uniform(-hz / 2, 0))},
            {float(rng.uniform(0.5, hx - 0.3)), 0.012f, float(rng.uniform(0.5, hz - 0.3))},
            s.add_material(random_material(rng)));
  auto spot = [&](float margin) {
    return Vec3(float(rng.uniform(-hx + margin, hx - margin)), 0, float(rng.uniform(-hz + margin, hz - margin)));
  };
  for (int k = scaled_count(2, st.density); k > 0; --k) {
    uint32_t m = s.add_material(random_material(rng, 0.2f, 0.7f));
    // Against a wall (the back towards it) or free-standing.
    float len = float(rng.uniform(0.9, 2.4)) * st.scale;
    Vec3 c = spot(1.2f);
    float yaw = float(rng.uniform(0, 2 * kPi));
    if (rng.below(2)) {
      int w = int(rng.below(4));
      yaw = float(w) * kPi / 2;
      Vec3 back(-std::sin(yaw), 0, -std::cos(yaw));  // the sofa's -z side in world
      c = c - back * dot(c, back) + back * ((w % 2 ? hx : hz) - 0.6f);
    }
    add_sofa(s, rng, c, len, yaw, m, st);
  }
  for (int k = scaled_count(2, st.density); k > 0; --k) {
    uint32_t m = s.add_material(random_material(rng));
    float r = float(rng.uniform(0.3, 0.7)) * st.scale, th = float(rng.uniform(0.45, 0.8));
    Vec3 c = spot(r + 0.3f);
    add_round_table(s, c, r, th, m, st);
    for (int i = int(rng.below(4)); i > 0; --i) {
      float a = float(rng.uniform(0, 2 * kPi)), d = float(rng.uniform(0, r * 0.6));
      add_turned_object(s, rng, c + Vec3(d * std::cos(a), th, d * std::sin(a)), float(rng.uniform(0.04, 0.12)),
                        float(rng.uniform(0.08, 0.35)), s.add_material(random_material(rng)), st);
    }
    for (int i = int(rng.below(4)); i > 0; --i) {
      float a = float(rng.uniform(0, 2 * kPi));
      add_round_chair(s, c + Vec3(std::cos(a), 0, std::sin(a)) * (r + 0.35f), kPi / 2 - a, m, st);
    }
  }
  for (int k = int(rng.below(3)); k > 0; --k) {  // bookshelf against a wall, books of uneven size
    uint32_t m = s.add_material(random_material(rng));
    bool along_x = rng.below(2);
    float side = rng.below(2) ? 1.0f : -1.0f, len = float(rng.uniform(0.8, 1.8)), sh = float(rng.uniform(1.2, h - 0.3));
    float u = float(rng.uniform(-(along_x ? hx : hz) + len / 2 + 0.1, (along_x ? hx : hz) - len / 2 - 0.1));
    float depth = 0.32f, wall_at = (along_x ? hz : hx) - depth / 2 - 0.01f;
    auto at = [&](float a, float y, float d) {
      return along_x ? Vec3(u + a, y, side * (wall_at - d)) : Vec3(side * (wall_at - d), y, u + a);
    };
    auto box = [&](Vec3 c, float ha, float hy, float hd, uint32_t mat) {
      Vec3 half = along_x ? Vec3(ha, hy, hd) : Vec3(hd, hy, ha);
      add_box(s, c - half, c + half, mat);
    };
    int levels = 3 + int(rng.below(3));
    for (int l = 0; l <= levels; ++l) box(at(0, sh * float(l) / float(levels), 0), len / 2, 0.015f, depth / 2, m);
    for (float e : {-1.0f, 1.0f}) box(at(e * len / 2, sh / 2, 0), 0.015f, sh / 2, depth / 2, m);
    for (int l = 0; l < levels; ++l) {
      float y0 = sh * float(l) / float(levels) + 0.015f, room = sh / float(levels) - 0.05f;
      for (float a = -len / 2 + 0.03f; a < len / 2 - 0.06f;) {
        float bw = float(rng.uniform(0.015, 0.05)), bh = room * float(rng.uniform(0.6, 0.95));
        if (rng.below(8) == 0) {
          a += float(rng.uniform(0.05, 0.2));
          continue;
        }  // a gap
        box(at(a + bw / 2, y0 + bh / 2, float(rng.uniform(0, 0.05))), bw / 2, bh / 2, depth * 0.4f,
            s.add_material(random_material(rng)));
        a += bw + 0.002f;
      }
    }
  }
  for (int k = int(rng.below(3)); k > 0; --k) {  // floor lamps: foot, pole, open conical shade
    uint32_t m = s.add_material(random_material(rng, 0.3f, 0.8f));
    Vec3 c = spot(0.4f);
    float lh = float(rng.uniform(1.2, 1.7));
    add_lathe(s, c, {0, 1, 0},
              {{0, 0}, {0.15f, 0}, {0.15f, 0}, {0.12f, 0.03f}, {0.015f, 0.04f}, {0.015f, lh}, {0.015f, lh}, {0, lh}},
              st.segments(20), m, st.smooth);
    add_lathe(s, c + Vec3(0, lh - 0.1f, 0), {0, 1, 0}, {{0.22f, 0}, {0.12f, 0.3f}}, st.segments(24), m, st.smooth);
  }
  for (int k = scaled_count(4, st.density); k > 0; --k) {  // things on the floor
    Vec3 c = spot(0.4f);
    add_random_object(s, rng, c.x, c.z, 0, float(rng.uniform(0.2, 0.5)) * st.scale, st);
  }
  indoor_lights(s, rng, hx, hz, h);
  s.cameras = {{-hx + 0.4f, 0.6f, -hz + 0.4f}, {hx - 0.4f, std::min(1.9f, h - 0.4f), hz - 0.4f}, -40, 10};
  return s;
}

// A room, or a yard with two walls, piled with generated objects of every kind and a
// wide range of sizes (log-uniform 0.1-1.2 m), some stacked on others.
Scene make_clutter(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  float hx = float(rng.uniform(3, 6)), hz = float(rng.uniform(3, 6));
  bool indoor = rng.below(2);
  uint32_t wall = s.add_material(random_material(rng, 0.4f, 0.85f));
  uint32_t floor = s.add_material(random_material(rng, 0.2f, 0.6f));
  float h = float(rng.uniform(2.6, 4));
  if (indoor) {
    add_room_shell(s, hx, hz, h, wall, floor);
  } else {
    add_quad(s, {-60, 0, -60}, {120, 0, 0}, {0, 0, 120}, floor);
    add_wall(s, true, -hz - 0.1f, -hx - 0.2f, hx + 0.2f, h, 0.2f, {}, wall);
    add_wall(s, false, -hx - 0.1f, -hz, hz, h, 0.2f, {}, wall);
  }
  int n = scaled_count(25, st.density);
  for (int k = 0; k < n; ++k) {
    float size = float(std::exp(rng.uniform(std::log(0.1), std::log(1.2)))) * st.scale;
    float x = float(rng.uniform(-hx + size / 2, hx - size / 2)), z = float(rng.uniform(-hz + size / 2, hz - size / 2));
    float top = add_random_object(s, rng, x, z, 0, size, st);
    if (rng.below(4) == 0 && top > 0.1f)  // a smaller thing sitting on it (rests on its top; may overlap)
      add_random_object(s, rng, x, z, top * 0.97f, size * float(rng.uniform(0.3, 0.6)), st);
  }
  if (indoor) indoor_lights(s, rng, hx, hz, h);
  else outdoor_lighting(s, rng);
  s.cameras = {
      {-hx + 0.5f, 0.5f, -hz + 0.5f}, {hx + (indoor ? -0.5f : 3.0f), 2.2f, hz + (indoor ? -0.5f : 3.0f)}, -45, 10};
  return s;
}

// A stairwell: a spiral stair round a column (cantilevered wedge treads, round posts,
// a helical handrail) or a switchback of two straight flights with a landing and
// soffits seen from below, inside a walled shaft lit from above.
Scene make_stairwell(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  bool spiral = rng.below(2);
  float rise = float(rng.uniform(0.15, 0.2));
  uint32_t stone = s.add_material(random_material(rng, 0.4f, 0.8f));
  uint32_t rail = s.add_material(random_material(rng, 0.1f, 0.5f));
  uint32_t wall = s.add_material(random_material(rng, 0.5f, 0.85f));
  uint32_t floor = s.add_material(random_material(rng, 0.2f, 0.6f));
  float hx, hz, top;
  if (spiral) {
    float R = float(rng.uniform(1.0, 1.8)), rc = float(rng.uniform(0.08, 0.2));
    int per_turn = 12 + int(rng.below(8));
    int steps = int(float(per_turn) * float(rng.uniform(1.5, 2.5)));
    top = rise * float(steps);
    hx = hz = R + float(rng.uniform(0.4, 1.5));
    add_round_cylinder(s, {0, 0, 0}, {0, top + 1.2f, 0}, rc, st.segments(20), stone, st.smooth);
    float thick = float(rng.uniform(0.05, 0.2));
    bool solid = rng.below(3) == 0;  // treads down to the one below (a stepped soffit) or floating slabs
    float a0 = float(rng.uniform(0, 2 * kPi)), da = 2 * kPi / float(per_turn);
    std::vector<Vec3> rail_points;
    for (int i = 0; i < steps; ++i) {
      float a = a0 + da * float(i), y = rise * float(i + 1);
      float mid = (rc + R) / 2, w = R * da * 0.55f;
      float yaw = -a;  // the tread's long axis points out from the column
      float hy = solid ? (rise + thick) / 2 : thick / 2;
      add_box_yaw(s, {mid * std::cos(a), y - hy, mid * std::sin(a)}, {(R - rc) / 2, hy, w}, yaw, stone);
      Vec3 post(R * 0.92f * std::cos(a), y, R * 0.92f * std::sin(a));
      if (i % 2 == 0)
        add_round_cylinder(s, post, post + Vec3(0, 0.9f, 0), 0.015f, st.segments(8), rail, st.smooth, false);
      rail_points.push_back(post + Vec3(0, 0.9f, 0));
    }
    for (size_t i = 1; i < rail_points.size(); ++i)
      add_round_cylinder(s, rail_points[i - 1], rail_points[i], 0.025f, st.segments(10), rail, st.smooth, false);
  } else {
    float width = float(rng.uniform(0.9, 1.5)), run = float(rng.uniform(0.25, 0.32));
    int steps = 8 + int(rng.below(6));
    float land = float(rng.uniform(1.0, 1.6)), flight_len = run * float(steps);
    hx = width + 0.1f + float(rng.uniform(0, 0.8));
    hz = flight_len / 2 + land + 0.3f;
    float z_land = -hz + land;  // landing occupies z in [-hz, z_land]
    float mid_h = rise * float(steps);
    top = 2 * mid_h;
    float slab = float(rng.uniform(0.12, 0.25));
    for (int flight = 0; flight < 2; ++flight) {
      // Flight 0 climbs towards -z on the +x side; flight 1 climbs back on the -x side.
      float x0 = flight == 0 ? 0.05f : -width - 0.05f;
      for (int i = 0; i < steps; ++i) {
        float y = float(flight) * mid_h + rise * float(i + 1);
        float z1 = flight == 0 ? z_land + flight_len - run * float(i) : z_land + run * float(i + 1);
        float z0 = z1 - run;
        add_box(s, {x0, y - rise - slab * 0.5f, z0}, {x0 + width, y, z1}, stone);
      }
      // Handrail on the open (inner) side.
      float xr = flight == 0 ? 0.08f : -0.08f;
      Vec3 a(xr, float(flight) * mid_h + rise + 0.9f, flight == 0 ? z_land + flight_len : z_land);
      Vec3 b(xr, float(flight + 1) * mid_h + 0.9f, flight == 0 ? z_land : z_land + flight_len);
      add_round_cylinder(s, a, b, 0.025f, st.segments(10), rail, st.smooth);
      for (int i = 0; i <= steps; i += 3) {
        Vec3 p = a + (b - a) * (float(i) / float(steps));
        add_round_cylinder(s, p - Vec3(0, 0.9f, 0), p, 0.015f, st.segments(8), rail, st.smooth, false);
      }
    }
    add_box(s, {-hx, mid_h - slab, -hz}, {hx, mid_h, z_land}, stone);          // the landing
    add_box(s, {-hx, top - slab, z_land + flight_len}, {hx, top, hz}, stone);  // the upper floor
  }
  float h = top + float(rng.uniform(1.8, 2.6));
  add_room_shell(s, hx, hz, h, wall, floor);
  // Lamps up the shaft, so every level is lit.
  indoor_lights(s, rng, hx, hz, h);
  for (float y = 1.5f; y < h; y += 2.5f) s.points.push_back({{hx * 0.8f, y, hz * 0.8f}, Vec3(2, 1.8f, 1.5f)});
  s.cameras = {{-hx + 0.3f, 0.5f, -hz + 0.3f}, {hx - 0.3f, std::max(1.0f, top), hz - 0.3f}, -50, 30};
  return s;
}

}  // namespace nns::render
