// Indoor families: furnished rooms lit by lamps, and rooms lit through windows by a
// sun that falls behind the camera.
#include "render/scenes/families.h"
#include "render/scenes/family_kit.h"

namespace nns::render {

namespace {
// Furniture and clutter on the floor of [-hx, hx] x [-hz, hz]: tables with things on
// them, shelves against the walls, boxes and cylinders in corners.
void furnish(Scene& s, Rng& rng, float hx, float hz, float ceiling) {
  int tables = 1 + int(rng.below(3));
  for (int i = 0; i < tables; ++i) {
    uint32_t m = s.add_material(random_material(rng));
    Vec3 c(float(rng.uniform(-hx + 1, hx - 1)), 0, float(rng.uniform(-hz + 1, hz - 1)));
    float w = float(rng.uniform(0.8, 1.8)), d = float(rng.uniform(0.6, 1.0)), h = float(rng.uniform(0.45, 0.8));
    float yaw = float(rng.uniform(0, kPi));
    add_table(s, c, w, d, h, yaw, m);
    for (int k = int(rng.below(4)); k > 0; --k) {  // clutter on the table top
      uint32_t mc = s.add_material(random_material(rng));
      float sz = float(rng.uniform(0.05, 0.18));
      add_box_yaw(s, c + Vec3(float(rng.uniform(-w / 3, w / 3)), h + sz, float(rng.uniform(-d / 3, d / 3))),
                  {sz, sz, sz * 0.7f}, float(rng.uniform(0, kPi)), mc);
    }
    for (int k = int(rng.below(3)); k > 0; --k) {  // chairs: a seat and a back
      float a = float(rng.uniform(0, 2 * kPi));
      Vec3 cc = c + Vec3(std::cos(a), 0, std::sin(a)) * (w * 0.6f + 0.3f);
      add_table(s, cc, 0.45f, 0.45f, 0.45f, a, m);
      add_box_yaw(s, cc + Vec3(std::cos(a) * 0.2f, 0.7f, std::sin(a) * 0.2f), {0.02f, 0.25f, 0.22f}, -a, m);
    }
  }
  int shelves = int(rng.below(4));
  for (int i = 0; i < shelves; ++i) {
    uint32_t m = s.add_material(random_material(rng));
    bool along_x = rng.below(2);
    float side = rng.below(2) ? 1.0f : -1.0f;
    float len = float(rng.uniform(0.8, 2.0)), h = float(rng.uniform(1.0, std::min(2.2f, ceiling - 0.2f)));
    float depth = 0.35f;
    float u = float(rng.uniform(-(along_x ? hx : hz) + len / 2 + 0.1f, (along_x ? hx : hz) - len / 2 - 0.1f));
    for (int level = 0; level <= 4; ++level) {
      float y = h * float(level) / 4;
      Vec3 c = along_x ? Vec3(u, y, side * (hz - depth / 2)) : Vec3(side * (hx - depth / 2), y, u);
      Vec3 half = along_x ? Vec3(len / 2, 0.02f, depth / 2) : Vec3(depth / 2, 0.02f, len / 2);
      add_box(s, c - half, c + half, m);
    }
    for (float end : {-1.0f, 1.0f}) {
      Vec3 c = along_x ? Vec3(u + end * len / 2, h / 2, side * (hz - depth / 2))
                       : Vec3(side * (hx - depth / 2), h / 2, u + end * len / 2);
      Vec3 half = along_x ? Vec3(0.02f, h / 2, depth / 2) : Vec3(depth / 2, h / 2, 0.02f);
      add_box(s, c - half, c + half, m);
    }
  }
  for (int k = 3 + int(rng.below(8)); k > 0; --k) {  // floor clutter
    uint32_t m = s.add_material(random_material(rng));
    Vec3 c(float(rng.uniform(-hx + 0.3, hx - 0.3)), 0, float(rng.uniform(-hz + 0.3, hz - 0.3)));
    if (rng.below(3) == 0) {
      add_cylinder(s, c, float(rng.uniform(0.08, 0.3)), float(rng.uniform(0.2, 1.2)), 12, m);
    } else {
      Vec3 half(float(rng.uniform(0.1, 0.4)), float(rng.uniform(0.1, 0.5)), float(rng.uniform(0.1, 0.4)));
      add_box_yaw(s, c + Vec3(0, half.y, 0), half, float(rng.uniform(0, kPi)), m);
    }
  }
}
}  // namespace

Scene make_room(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  float hx = float(rng.uniform(2.5, 4.5)), hz = float(rng.uniform(2.5, 4.5)), h = float(rng.uniform(2.6, 3.4));
  uint32_t wall = s.add_material(random_material(rng, 0.5f, 0.85f));
  uint32_t floor = s.add_material(random_material(rng, 0.2f, 0.6f));
  add_room_shell(s, hx, hz, h, wall, floor);
  // A pillar or a partition breaks the box into corners and occluded nooks.
  if (rng.below(2)) {
    uint32_t m = s.add_material(random_material(rng));
    float x = float(rng.uniform(-hx / 2, hx / 2));
    add_box(s, {x - 0.05f, 0, -hz}, {x + 0.05f, h * 0.7f, float(rng.uniform(-hz / 2, hz / 3))}, m);
  }
  furnish(s, rng, hx, hz, h);
  // Lamps: a ceiling panel that rays see (emission) and the rect light it stands for,
  // plus a point light; the rest of the room is lit by bounces.
  add_ceiling_panel(s, rng, hx, hz, h);
  if (rng.below(2))
    s.points.push_back({{float(rng.uniform(-hx + 0.5, hx - 0.5)), float(rng.uniform(1.2, h - 0.4)),
                         float(rng.uniform(-hz + 0.5, hz - 0.5))},
                        Vec3(4.0f, 3.5f, 2.7f)});
  s.sky = Sky::constant({0, 0, 0});
  s.cameras = {{-hx + 0.4f, 0.8f, -hz + 0.4f}, {hx - 0.4f, h - 0.6f, hz - 0.4f}, -35, 10};
  return s;
}

// Sunlight through windows in the +z wall, the camera near that wall looking into the
// room (-z): the sunlit patches on the floor come from outside the screen, and the
// light source itself is behind the camera, which is what surround-aware GI is for.
Scene make_window_room(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  float hx = float(rng.uniform(3, 5)), hz = float(rng.uniform(3, 5)), h = float(rng.uniform(2.8, 3.6));
  uint32_t wall = s.add_material(random_material(rng, 0.55f, 0.85f));
  uint32_t floor = s.add_material(random_material(rng, 0.25f, 0.6f));
  add_box(s, {-hx - 0.2f, -0.1f, -hz - 0.2f}, {hx + 0.2f, 0, hz + 0.2f}, floor);
  add_box(s, {-hx - 0.2f, h, -hz - 0.2f}, {hx + 0.2f, h + 0.15f, hz + 0.2f}, wall);
  std::vector<Opening> windows;
  int nw = 1 + int(rng.below(3));
  float span = 2 * hx / float(nw);
  for (int i = 0; i < nw; ++i) {
    float c = -hx + span * (float(i) + 0.5f), w = float(rng.uniform(0.3, 0.45)) * span;
    windows.push_back({c - w, c + w, float(rng.uniform(0.3, 0.9)), h - float(rng.uniform(0.2, 0.6))});
  }
  add_wall(s, true, hz + 0.1f, -hx - 0.2f, hx + 0.2f, h, 0.2f, windows, wall);
  add_wall(s, true, -hz - 0.1f, -hx - 0.2f, hx + 0.2f, h, 0.2f, {}, wall);
  add_wall(s, false, -hx - 0.1f, -hz, hz, h, 0.2f, {}, wall);
  add_wall(s, false, hx + 0.1f, -hz, hz, h, 0.2f, {}, wall);
  // Outside: a ground plane so light bounces in from below the windows too.
  uint32_t ground = s.add_material(random_material(rng, 0.2f, 0.5f));
  add_quad(s, {-40, -0.1f, hz + 0.2f}, {80, 0, 0}, {0, 0, 40}, ground);
  furnish(s, rng, hx, hz - 0.5f, h);
  // The sun shines in through the +z windows, downwards into the room.
  float az = float(rng.uniform(-0.6, 0.6)), el = float(rng.uniform(20, 50)) * kPi / 180;
  s.suns.push_back({{std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)}, {6, 5.6f, 5}, 0.0093f});
  s.sky = Sky{{0.3f, 0.5f, 1.0f}, {0.8f, 0.85f, 1.0f}, {0.2f, 0.18f, 0.15f}};
  s.cameras = {{-hx + 0.5f, 1.0f, 0.2f * hz}, {hx - 0.5f, h - 0.7f, hz - 0.5f}, -30, 5, 0, 100};
  return s;
}

}  // namespace nns::render
