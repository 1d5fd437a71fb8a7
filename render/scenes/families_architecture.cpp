// Architectural families of the second generation: arcades of round columns and
// arches under barrel vaults, and halls of groin-vaulted bays on piers.
#include "render/scenes/families.h"
#include "render/scenes/arches.h"
#include "render/scenes/family_kit.h"

namespace nns::render {

// Columns, arches and barrel vaults (declared in arches.h: the generation-4 halls use
// them too).
// A round column: a square plinth, a torus-like base moulding, a shaft with entasis
// (slightly swollen a third of the way up), a capital flaring to a square abacus.
void add_column(Scene& s, Vec3 base, float r, float h, uint32_t m, const SceneStyle& st) {
  add_box(s, base - Vec3(r * 1.4f, 0, r * 1.4f), base + Vec3(r * 1.4f, 0.12f, r * 1.4f), m);
  std::vector<ProfilePoint> prof = {{0, 0.12f}, {r * 1.25f, 0.12f}, {r * 1.25f, 0.12f}};
  for (int i = 0; i <= 4; ++i) {  // a half-round moulding
    float a = -kPi / 2 + kPi * float(i) / 4;
    prof.push_back({r + 0.25f * r * std::cos(a), 0.12f + 0.12f * r + 0.12f * r * std::sin(a)});
  }
  float shaft0 = 0.12f + 0.24f * r, shaft1 = h - 0.3f * r - 0.1f;
  for (int i = 0; i <= 6; ++i) {
    float t = float(i) / 6;
    prof.push_back(
        {r * (1 + 0.04f * std::sin(kPi * std::min(1.0f, t * 1.5f))) * (1 - 0.12f * t), shaft0 + (shaft1 - shaft0) * t});
  }
  prof.push_back({r * 0.88f, shaft1});
  prof.push_back({r * 1.3f, h - 0.1f});
  prof.push_back({r * 1.3f, h - 0.1f});
  prof.push_back({0, h - 0.1f});
  add_lathe(s, base, {0, 1, 0}, prof, st.segments(24), m, st.smooth);
  add_box(s, base + Vec3(-r * 1.4f, h - 0.1f, -r * 1.4f), base + Vec3(r * 1.4f, h, r * 1.4f), m);
}

// The wall piece above one opening: a half-circle arch of radius r in a rectangle
// span x rise (the arch centred at u = 0, springing at v = 0), extruded along `depth`.
// The corners of the rectangle are profile points so its edges stay straight.
void add_arch_piece(Scene& s, Vec3 origin, Vec3 eu, Vec3 ev, Vec3 depth, float span, float rise, float r, int steps,
                    uint32_t m, const SceneStyle& st) {
  std::vector<float> angles;
  for (int i = 0; i <= steps; ++i) angles.push_back(kPi * float(i) / float(steps));
  float corner = std::atan2(rise, span / 2);
  angles.push_back(corner);
  angles.push_back(kPi - corner);
  std::sort(angles.begin(), angles.end());
  std::vector<ProfilePoint> outer, inner;
  for (float a : angles) {
    float c = std::cos(a), sn = std::sin(a);
    float t = std::min(std::fabs(c) > 1e-6f ? span / 2 / std::fabs(c) : 1e30f, sn > 1e-6f ? rise / sn : 1e30f);
    outer.push_back({t * c, t * sn});
    inner.push_back({r * c, r * sn});
  }
  add_band_extrusion(s, outer, inner, origin, eu, ev, depth, m, st.smooth, false);
}

// Half-round barrel vault shell of inner radius r and thickness th, its axis along
// `axis` (unit, horizontal) from `start` for `len`, springing at start's height.
void add_barrel_vault(Scene& s, Vec3 start, Vec3 axis, float len, float r, float th, int steps, uint32_t m,
                      const SceneStyle& st) {
  std::vector<ProfilePoint> outer, inner;
  for (int i = 0; i <= steps; ++i) {
    float a = kPi * float(i) / float(steps);
    outer.push_back({(r + th) * std::cos(a), (r + th) * std::sin(a)});
    inner.push_back({r * std::cos(a), r * std::sin(a)});
  }
  Vec3 across = normalize(cross({0, 1, 0}, axis));
  add_band_extrusion(s, outer, inner, start, across, {0, 1, 0}, axis * len, m, st.smooth, st.smooth);
}

// An arcade: a row of round columns carrying arches (one storey or two), a walkway
// behind under a barrel vault, a flat ceiling or the open sky, and a back wall with
// doors. The arches' soffits, the column bases and the vault's springing are the
// curved creases SSAO gets wrong.
Scene make_arcade(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  uint32_t ground = s.add_material(random_material(rng, 0.2f, 0.55f));
  add_quad(s, {-60, 0, -60}, {120, 0, 0}, {0, 0, 120}, ground);
  uint32_t stone = s.add_material(random_material(rng, 0.45f, 0.85f));
  uint32_t wall_m = s.add_material(random_material(rng, 0.4f, 0.8f));
  int bays = 4 + int(rng.below(5));
  float spacing = float(rng.uniform(2.2, 3.6)) * st.scale, r = float(rng.uniform(0.16, 0.3)) * st.scale;
  float hcol = float(rng.uniform(2.6, 4.0)) * st.scale, depth_walk = float(rng.uniform(2.5, 4.5));
  float thick = float(rng.uniform(0.4, 0.7)), x0 = -spacing * float(bays) / 2;
  int storeys = 1 + int(rng.below(2));
  float arch_r = spacing / 2 - r * 1.4f, rise = arch_r + float(rng.uniform(0.4, 0.9));
  float z_front = 0, z_back = -depth_walk - thick;
  float y = 0, sc = 1;
  for (int storey = 0; storey < storeys; ++storey) {
    for (int i = 0; i <= bays; ++i)
      add_column(s, {x0 + spacing * float(i), y, z_front - thick / 2}, r * sc, hcol * sc, stone, st);
    for (int i = 0; i < bays; ++i)
      add_arch_piece(s, {x0 + spacing * (float(i) + 0.5f), y + hcol * sc, z_front}, {1, 0, 0}, {0, 1, 0},
                     {0, 0, -thick}, spacing, rise, arch_r, st.segments(16), stone, st);
    y += hcol * sc + rise;
    add_box(s, {x0 - r * 2, y, z_front - thick}, {-x0 + r * 2, y + 0.35f, z_front + 0.05f}, stone);  // cornice
    y += 0.35f;
    sc *= 0.75f;
    if (storey + 1 < storeys)  // the upper floor over the walkway
      add_box(s, {x0 - r * 2, y - 0.35f, z_back}, {-x0 + r * 2, y - 0.05f, z_front - thick}, stone);
  }
  // Back wall with door openings.
  std::vector<Opening> doors;
  for (int i = 0; i < bays; ++i)
    if (rng.below(2)) {
      float c = x0 + spacing * (float(i) + 0.5f), w = float(rng.uniform(0.4, 0.7));
      doors.push_back({c - w, c + w, 0, float(rng.uniform(2.0, 2.6))});
    }
  add_wall(s, true, z_back - 0.2f, x0 - r * 2, -x0 + r * 2, y + 0.5f, 0.4f, doors, wall_m);
  // Ceiling of the (ground-floor) walkway.
  float spring = hcol + rise + 0.35f;
  int roof = int(rng.below(3));
  float half_walk = (z_front - thick - z_back) / 2;
  if (roof == 0 && storeys == 1)
    add_barrel_vault(s, {x0 - r * 2, spring, z_back + half_walk}, {1, 0, 0}, -2 * x0 + 4 * r, half_walk, 0.2f,
                     st.segments(24), stone, st);
  else if (roof == 1 || storeys == 2)
    add_box(s, {x0 - r * 2, spring - 0.3f, z_back}, {-x0 + r * 2, spring, z_front - thick}, stone);
  outdoor_lighting(s, rng);
  s.cameras = {{x0, 0.8f, z_back + 0.6f}, {-x0, 2.2f, 6}, -25, 25};
  return s;
}

// A vaulted hall (crypt, cloister, undercroft): a grid of square bays, each under a
// groin vault (or, along one row, a barrel vault), resting on round or square piers,
// walled round, lit by lamps. The groins are creases that meet at curved angles.
Scene make_vaults(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  int nx = 2 + int(rng.below(3)), nz = 2 + int(rng.below(3));
  float R = float(rng.uniform(1.4, 2.8)) * st.scale, H = float(rng.uniform(1.8, 3.2));
  float hx = R * float(nx), hz = R * float(nz);
  uint32_t stone = s.add_material(random_material(rng, 0.45f, 0.85f));
  uint32_t floor = s.add_material(random_material(rng, 0.2f, 0.6f));
  uint32_t wall = s.add_material(random_material(rng, 0.4f, 0.8f));
  add_box(s, {-hx - 0.5f, -0.1f, -hz - 0.5f}, {hx + 0.5f, 0, hz + 0.5f}, floor);
  add_wall(s, true, -hz - 0.15f, -hx - 0.3f, hx + 0.3f, H + R + 0.3f, 0.3f, {}, wall);
  add_wall(s, true, hz + 0.15f, -hx - 0.3f, hx + 0.3f, H + R + 0.3f, 0.3f, {}, wall);
  add_wall(s, false, -hx - 0.15f, -hz, hz, H + R + 0.3f, 0.3f, {}, wall);
  add_wall(s, false, hx + 0.15f, -hz, hz, H + R + 0.3f, 0.3f, {}, wall);
  add_box(s, {-hx - 0.3f, H + R + 0.3f, -hz - 0.3f}, {hx + 0.3f, H + R + 0.5f, hz + 0.3f}, wall);  // roof
  int barrel_row = rng.below(3) == 0 ? int(rng.below(uint64_t(nz))) : -1;
  for (int j = 0; j < nz; ++j) {
    float cz = -hz + R * (2 * float(j) + 1);
    if (j == barrel_row) {
      add_barrel_vault(s, {-hx, H, cz}, {1, 0, 0}, 2 * hx, R, 0.15f, st.segments(24), stone, st);
      continue;
    }
    for (int i = 0; i < nx; ++i)
      add_groin_vault(s, {-hx + R * (2 * float(i) + 1), H, cz}, R, st.smooth ? 16 : 8, stone, st.smooth);
  }
  // Spandrel fill above the vault's edge arches along the walls is the wall itself;
  // piers at every bay corner (inside and along the walls).
  bool round = rng.below(2);
  float pr = R * float(rng.uniform(0.1, 0.18));
  for (int j = 0; j <= nz; ++j)
    for (int i = 0; i <= nx; ++i) {
      Vec3 p(-hx + 2 * R * float(i), 0, -hz + 2 * R * float(j));
      if (round) add_round_cylinder(s, p, p + Vec3(0, H, 0), pr, st.segments(20), stone, st.smooth);
      else add_bevelled_box(s, p + Vec3(0, H / 2, 0), {pr, H / 2, pr}, pr * 0.25f, 0, stone, st.smooth, 2);
      add_box(s, p - Vec3(pr * 1.5f, 0, pr * 1.5f), p + Vec3(pr * 1.5f, 0.15f, pr * 1.5f), stone);
    }
  for (int k = scaled_count(3, st.density); k > 0; --k) {  // tombs, benches, barrels
    uint32_t m = s.add_material(random_material(rng));
    Vec3 c(float(rng.uniform(-hx + 0.8, hx - 0.8)), 0, float(rng.uniform(-hz + 0.8, hz - 0.8)));
    if (rng.below(2)) {
      Vec3 half(float(rng.uniform(0.3, 1.0)), float(rng.uniform(0.2, 0.5)), float(rng.uniform(0.3, 0.6)));
      add_bevelled_box(s, c + Vec3(0, half.y, 0), half, 0.04f, float(rng.uniform(0, kPi)), m, st.smooth, 2);
    } else {
      add_turned_object(s, rng, c, float(rng.uniform(0.2, 0.4)), float(rng.uniform(0.5, 1.0)), m, st);
    }
  }
  s.sky = Sky::constant({0, 0, 0});
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < nz; ++j)
      if (rng.below(2) || (i == 0 && j == 0))
        s.points.push_back({{-hx + R * (2 * float(i) + 1), H * 0.8f, -hz + R * (2 * float(j) + 1)}, Vec3(3, 2.6f, 2)});
  s.cameras = {{-hx + 0.4f, 0.6f, -hz + 0.4f}, {hx - 0.4f, H * 0.9f, hz - 0.4f}, -25, 35};
  return s;
}

}  // namespace nns::render

namespace nns::render {

namespace {
// A parked car along z: a rounded body, a rounded cabin, four round wheels.
void add_car(Scene& s, Rng& rng, Vec3 c, const SceneStyle& st) {
  uint32_t paint = s.add_material(random_material(rng, 0.2f, 0.8f));
  uint32_t tyre = s.add_material({{0.05f, 0.05f, 0.05f}, {}});
  float L = float(rng.uniform(1.9, 2.4)), W = 0.85f, r = 0.32f;
  add_bevelled_box(s, c + Vec3(0, r + 0.3f, 0), {W, 0.32f, L}, 0.12f, 0, paint, st.smooth);
  add_bevelled_box(s, c + Vec3(0, r + 0.85f, float(rng.uniform(-0.3, 0.2))), {W * 0.9f, 0.28f, L * 0.5f}, 0.15f, 0,
                   paint, st.smooth);
  for (int i = 0; i < 4; ++i) {
    Vec3 w = c + Vec3((i & 1 ? 1 : -1) * (W - 0.12f), r, (i & 2 ? 1 : -1) * (L - 0.55f));
    add_round_cylinder(s, w - Vec3(0.13f, 0, 0), w + Vec3(0.13f, 0, 0), r, st.segments(20), tyre, st.smooth);
  }
}
}  // namespace

// A street canyon: facades on both sides with recessed windows and doors, balconies
// with railings, a kerb and pavements, parked cars (rounded bodies on round wheels),
// lamp posts and bollards: the repeated recesses and contact shadows of the city
// scenes real engines render.
Scene make_street(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  float half_w = float(rng.uniform(4, 8)), len = 40, walk = float(rng.uniform(1.5, 3));
  uint32_t road = s.add_material(random_material(rng, 0.15f, 0.35f));
  uint32_t pave = s.add_material(random_material(rng, 0.35f, 0.6f));
  uint32_t glass = s.add_material(random_material(rng, 0.1f, 0.3f));
  uint32_t iron = s.add_material(random_material(rng, 0.1f, 0.4f));
  add_quad(s, {-60, 0, -60}, {120, 0, 0}, {0, 0, 120}, road);
  for (float side : {-1.0f, 1.0f}) {
    float kerb = side * (half_w - walk);
    add_box(s, {std::min(kerb, side * half_w), 0, -len}, {std::max(kerb, side * half_w), 0.15f, len}, pave);
    for (float z = -len; z < len;) {
      float bw = std::min(len - z, float(rng.uniform(6, 14))), bh = float(rng.uniform(8, 20));
      uint32_t m = s.add_material(random_material(rng, 0.35f, 0.85f));
      float thick = 0.4f, fh = float(rng.uniform(2.8, 3.5)), ww = float(rng.uniform(0.6, 1.1));
      float x = side * (half_w + thick / 2), recess = float(rng.uniform(0.1, 0.3));
      int cols = std::max(1, int(bw / float(rng.uniform(1.8, 3.0))));
      int floors = std::max(2, int(bh / fh));
      for (int f = 0; f < floors; ++f) {
        float y0 = 0.15f + fh * float(f), y1 = y0 + fh;
        std::vector<Opening> holes;
        for (int c = 0; c < cols; ++c) {
          float zc = z + bw * (float(c) + 0.5f) / float(cols);
          bool door = f == 0 && rng.below(3) == 0;
          Opening o{zc - ww / 2, zc + ww / 2, door ? y0 : y0 + 0.9f, y0 + 2.3f};
          holes.push_back(o);
          // The glass (or the door) sits back in the wall: a recess with a deep sill.
          float xb = side * (half_w + thick + recess);
          add_box(s, {std::min(xb, xb + side * 0.05f), o.y0, o.a0}, {std::max(xb, xb + side * 0.05f), o.y1, o.a1},
                  glass);
          float xi = side * (half_w + thick), lo = std::min(xi, xb), hi = std::max(xi, xb);
          add_box(s, {lo, o.y0, o.a0 - 0.05f}, {hi, o.y1, o.a0}, m);  // reveals
          add_box(s, {lo, o.y0, o.a1}, {hi, o.y1, o.a1 + 0.05f}, m);
          add_box(s, {lo, o.y1, o.a0}, {hi, o.y1 + 0.05f, o.a1}, m);
          add_box(s, {lo, o.y0 - 0.05f, o.a0}, {hi, o.y0, o.a1}, m);
          if (!door && f == 0) continue;
          if (f > 0 && rng.below(4) == 0) {  // a balcony on two brackets, with a railing
            float out = side * -0.8f, xf = side * half_w;
            float bx0 = std::min(xf, xf + out), bx1 = std::max(xf, xf + out);
            add_box(s, {bx0, o.y0 - 0.12f, o.a0 - 0.4f}, {bx1, o.y0, o.a1 + 0.4f}, m);
            for (float zz : {o.a0 - 0.3f, o.a1 + 0.3f})
              add_beam(s, {xf, o.y0 - 0.6f, zz}, {xf + out * 0.9f, o.y0 - 0.12f, zz}, 0.06f, m);
            for (float zz = o.a0 - 0.35f; zz <= o.a1 + 0.36f; zz += 0.12f)
              add_round_cylinder(s, {xf + out * 0.95f, o.y0, zz}, {xf + out * 0.95f, o.y0 + 0.9f, zz}, 0.01f,
                                 st.segments(6), iron, st.smooth, false);
            add_beam(s, {xf + out * 0.95f, o.y0 + 0.9f, o.a0 - 0.4f}, {xf + out * 0.95f, o.y0 + 0.9f, o.a1 + 0.4f},
                     0.04f, iron);
          } else if (f > 0) {  // a sill
            add_box(s, {std::min(side * half_w, side * (half_w - 0.08f)), o.y0 - 0.06f, o.a0 - 0.08f},
                    {std::max(side * half_w, side * (half_w - 0.08f)), o.y0, o.a1 + 0.08f}, m);
          }
        }
        add_wall_band(s, false, x, z, z + bw, y0, y1, thick, holes, m);
      }
      add_box(s, {std::min(x, x + side * 3), 0.15f + fh * float(floors), z},
              {std::max(x, x + side * 3), 0.45f + fh * float(floors), z + bw}, m);  // roof edge / cornice
      z += bw;
    }
    for (float z = -len + float(rng.uniform(1, 6)); z < len - 3;) {  // parked cars along the kerb
      if (rng.below(3) != 0) add_car(s, rng, {kerb - side * 1.1f, 0, z + 2.2f}, st);
      z += float(rng.uniform(4.8, 7));
    }
    for (float z = -len + 3; z < len; z += float(rng.uniform(8, 14))) {  // lamp posts
      Vec3 b(kerb + side * 0.4f, 0.15f, z);
      add_round_cylinder(s, b, b + Vec3(0, 4.5f, 0), 0.06f, st.segments(12), iron, st.smooth);
      add_sphere(s, b + Vec3(0, 4.7f, 0), 0.2f, st.segments(16), iron, st.smooth);
    }
    for (int k = scaled_count(8, st.density); k > 0; --k) {  // bollards
      Vec3 b(kerb + side * 0.25f, 0.15f, float(rng.uniform(-len, len)));
      add_lathe(s, b, {0, 1, 0}, {{0.1f, 0}, {0.1f, 0.8f}, {0.1f, 0.8f}, {0.12f, 0.85f}, {0, 0.95f}}, st.segments(16),
                iron, st.smooth);
    }
  }
  outdoor_lighting(s, rng, 25, 70);
  s.cameras = {{-half_w + 0.6f, 1.0f, -25}, {half_w - 0.6f, 3.5f, 25}, -20, 20};
  return s;
}

}  // namespace nns::render
