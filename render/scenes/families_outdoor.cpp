// Outdoor families: colonnades and arches, stairs with railings, voxel worlds, thin
// geometry, large depth discontinuities, occluders just outside the screen.
#include <algorithm>

#include "render/scenes/families.h"
#include "render/scenes/family_util.h"

namespace nns::render {

namespace {
void add_ground(Scene& s, Rng& rng, float half) {
  uint32_t m = s.add_material(random_material(rng, 0.2f, 0.55f));
  add_quad(s, {-half, 0, -half}, {2 * half, 0, 0}, {0, 0, 2 * half}, m);
}

// An arch of `segments` boxes on a half circle of radius r between two piers.
void add_arch(Scene& s, Vec3 centre, float r, float thick, bool along_x, int segments, uint32_t m) {
  for (int i = 0; i < segments; ++i) {
    float a0 = kPi * float(i) / float(segments), a1 = kPi * float(i + 1) / float(segments);
    auto at = [&](float a) {
      float u = (r + thick / 2) * std::cos(a), y = (r + thick / 2) * std::sin(a);
      return along_x ? centre + Vec3(u, y, 0) : centre + Vec3(0, y, u);
    };
    Vec3 p0 = at(a0), p1 = at(a1);
    add_beam(s, p0, p1, thick, m);
  }
}
}  // namespace

Scene make_colonnade(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  add_ground(s, rng, 60);
  uint32_t stone = s.add_material(random_material(rng, 0.45f, 0.8f));
  int rows = 1 + int(rng.below(2)), cols = 5 + int(rng.below(5));
  float spacing = float(rng.uniform(2.0, 3.5)), r = float(rng.uniform(0.2, 0.4)), h = float(rng.uniform(3, 5));
  float depth = float(rng.uniform(3, 5));
  float x0 = -spacing * float(cols - 1) / 2;
  for (int row = 0; row < rows + 1; ++row) {
    float z = -depth * float(row);
    for (int c = 0; c < cols; ++c) {
      Vec3 base(x0 + spacing * float(c), 0, z);
      add_box(s, base - Vec3(r * 1.4f, 0, r * 1.4f), base + Vec3(r * 1.4f, 0.25f, r * 1.4f), stone);
      add_cylinder(s, base, r, h, 16, stone);
      add_box(s, base + Vec3(-r * 1.3f, h, -r * 1.3f), base + Vec3(r * 1.3f, h + 0.25f, r * 1.3f), stone);
      if (c + 1 < cols && rng.below(3) != 0)
        add_arch(s, base + Vec3(spacing / 2, h + 0.25f - spacing / 2 + r * 1.3f, 0), spacing / 2 - r * 1.3f, 0.3f, true,
                 10, stone);
    }
    add_box(s, {x0 - r * 2, h + 0.25f + spacing / 2, z - 0.4f}, {-x0 + r * 2, h + 0.75f + spacing / 2, z + 0.4f},
            stone);
  }
  if (rng.below(2))  // a roof over the rows: a shaded hall
    add_box(s, {x0 - 1, h + 0.75f + spacing / 2, -depth * rows - 0.5f}, {-x0 + 1, h + 1.0f + spacing / 2, 0.5f}, stone);
  if (rng.below(2))  // a back wall
    add_wall(s, true, -depth * rows - 2, x0 - 2, -x0 + 2, h + 2, 0.4f, {}, s.add_material(random_material(rng)));
  outdoor_lighting(s, rng);
  s.cameras = {{x0 - 2, 1.0f, -depth * rows - 1}, {-x0 + 2, 2.5f, 6}, -30, 20};
  return s;
}

Scene make_stairs(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  add_ground(s, rng, 60);
  int flights = 1 + int(rng.below(3));
  Vec3 at(float(rng.uniform(-2, 0)), 0, 2);
  uint32_t rail = s.add_material(random_material(rng, 0.1f, 0.4f));
  for (int f = 0; f < flights; ++f) {
    uint32_t m = s.add_material(random_material(rng, 0.35f, 0.8f));
    int steps = 6 + int(rng.below(8));
    float rise = float(rng.uniform(0.15, 0.2)), run = float(rng.uniform(0.25, 0.35)),
          width = float(rng.uniform(1.2, 2.5));
    for (int i = 0; i < steps; ++i) {
      Vec3 lo = at + Vec3(0, 0, -run * float(i + 1));
      add_box(s, lo, lo + Vec3(width, rise * float(i + 1), run), m);
    }
    float top = rise * float(steps);
    // Railing: posts on both sides and a slanted handrail.
    for (float side : {0.05f, width - 0.05f}) {
      for (int i = 0; i <= steps; i += 2) {
        Vec3 p = at + Vec3(side, rise * float(std::max(i, 1)), -run * float(i) - run / 2);
        add_beam(s, p, p + Vec3(0, 0.9f, 0), 0.04f, rail);
      }
      add_beam(s, at + Vec3(side, rise + 0.9f, -run / 2), at + Vec3(side, top + 0.9f, -run * float(steps) - run / 2),
               0.05f, rail);
    }
    // A landing block; the next flight stands on the ground beside it.
    Vec3 land_lo = at + Vec3(0, 0, -run * float(steps) - 1.5f);
    add_box(s, land_lo, land_lo + Vec3(width, top, 1.5f), m);
    at = Vec3(at.x + (rng.below(2) ? 1.0f : -1.0f) * (width + 0.3f), 0, land_lo.z + float(rng.uniform(0, 1.5)));
  }
  if (rng.below(2))  // a wall beside the stairs casts shade and adds a crease
    add_wall(s, false, -2.5f, -12, 4, 4, 0.3f, {}, s.add_material(random_material(rng)));
  outdoor_lighting(s, rng);
  s.cameras = {{-4, 0.8f, -8}, {4, 3.5f, 6}, -35, 15};
  return s;
}

// Minecraft-like: a height field of 1 m blocks (one box per column), block houses
// with door and window holes, and trees of leaf blocks.
Scene make_voxel(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  const int n = 24;
  uint32_t grass = s.add_material({{0.3f, 0.55f, 0.2f}, {}});
  uint32_t stone = s.add_material({{0.5f, 0.5f, 0.5f}, {}});
  uint32_t wood = s.add_material({{0.45f, 0.3f, 0.15f}, {}});
  uint32_t leaves = s.add_material({{0.2f, 0.45f, 0.15f}, {}});
  uint32_t plank = s.add_material({{0.7f, 0.55f, 0.35f}, {}});
  // Height from a few random bumps, quantised to blocks.
  std::vector<int> height(n * n);
  float bumps[6][4];
  for (auto& b : bumps)
    b[0] = float(rng.uniform(0, n)), b[1] = float(rng.uniform(0, n)), b[2] = float(rng.uniform(2, 6)),
    b[3] = float(rng.uniform(1, 4));
  for (int z = 0; z < n; ++z)
    for (int x = 0; x < n; ++x) {
      float hgt = 1;
      for (auto& b : bumps) {
        float dx = float(x) - b[0], dz = float(z) - b[1];
        hgt += b[3] * std::exp(-(dx * dx + dz * dz) / (2 * b[2] * b[2]));
      }
      height[z * n + x] = std::max(1, int(hgt));
    }
  auto cell = [&](int x, int z) { return Vec3(float(x - n / 2), 0, float(z - n / 2)); };
  for (int z = 0; z < n; ++z)
    for (int x = 0; x < n; ++x) {
      int hgt = height[z * n + x];
      add_box(s, cell(x, z), cell(x, z) + Vec3(1, float(hgt), 1), hgt > 3 ? stone : grass);
    }
  int houses = 1 + int(rng.below(3));
  for (int k = 0; k < houses; ++k) {
    int hx = 3 + int(rng.below(n - 10)), hz = 3 + int(rng.below(n - 10)), w = 4 + int(rng.below(3));
    int base = 0;
    for (int z = hz; z < hz + w; ++z)
      for (int x = hx; x < hx + w; ++x) base = std::max(base, height[z * n + x]);
    for (int y = 0; y < 3; ++y)
      for (int i = 0; i < w; ++i)
        for (int side = 0; side < 4; ++side) {
          int x = side == 0 ? hx + i : side == 1 ? hx + i : side == 2 ? hx : hx + w - 1;
          int z = side == 0 ? hz : side == 1 ? hz + w - 1 : side == 2 ? hz + i : hz + i;
          bool door = side == 0 && i == w / 2 && y < 2;
          bool window = y == 1 && i % 2 == 1 && side != 0 && i != 0 && i != w - 1;
          if (door || window) continue;
          Vec3 p = cell(x, z) + Vec3(0, float(base + y), 0);
          add_box(s, p, p + Vec3(1, 1, 1), plank);
        }
    Vec3 roof = cell(hx, hz) + Vec3(-0.5f, float(base + 3), -0.5f);
    add_box(s, roof, roof + Vec3(float(w) + 1, 0.5f, float(w) + 1), wood);
  }
  for (int k = 2 + int(rng.below(4)); k > 0; --k) {
    int x = int(rng.below(n - 4)) + 2, z = int(rng.below(n - 4)) + 2;
    float base = float(height[z * n + x]);
    Vec3 p = cell(x, z) + Vec3(0, base, 0);
    add_box(s, p, p + Vec3(1, 4, 1), wood);
    add_box(s, p + Vec3(-2, 3, -2), p + Vec3(3, 5, 3), leaves);
    add_box(s, p + Vec3(-1, 5, -1), p + Vec3(2, 6, 2), leaves);
  }
  outdoor_lighting(s, rng);
  s.cameras = {{-n / 2.0f + 2, 3.5f, -n / 2.0f + 2}, {n / 2.0f - 2, 8, n / 2.0f - 2}, -40, 10};
  return s;
}

// Thin geometry: poles, fences of posts and rails, wires, and leaf-like slabs that are
// thinner than a pixel's depth step, where depth-buffer methods see nothing or halos.
Scene make_thin(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  add_ground(s, rng, 60);
  uint32_t wood = s.add_material(random_material(rng, 0.3f, 0.6f));
  uint32_t metal = s.add_material(random_material(rng, 0.2f, 0.5f));
  for (int f = 0; f < 5 + int(rng.below(4)); ++f) {  // fences
    Vec3 a(float(rng.uniform(-8, 8)), 0, float(rng.uniform(-10, 0)));
    float yaw = float(rng.uniform(0, kPi)), len = float(rng.uniform(3, 8));
    Vec3 dir(std::cos(yaw), 0, std::sin(yaw));
    int posts = int(len / 0.6f);
    for (int i = 0; i <= posts; ++i)
      add_beam(s, a + dir * (0.6f * float(i)), a + dir * (0.6f * float(i)) + Vec3(0, 1.1f, 0), 0.06f, wood);
    for (float y : {0.4f, 0.95f})
      add_beam(s, a + Vec3(0, y, 0), a + dir * (0.6f * float(posts)) + Vec3(0, y, 0), 0.04f, wood);
  }
  for (int p = 0; p < 10 + int(rng.below(8)); ++p) {  // poles, some with wires between them
    Vec3 b(float(rng.uniform(-10, 10)), 0, float(rng.uniform(-11, 0)));
    add_beam(s, b, b + Vec3(0, float(rng.uniform(2.5, 5)), 0), float(rng.uniform(0.04, 0.12)), metal);
    if (p > 0 && rng.below(2)) {
      Vec3 top = b + Vec3(0, 2.4f, 0);
      add_beam(s, top, top + Vec3(float(rng.uniform(-4, 4)), float(rng.uniform(-0.3, 0.3)), float(rng.uniform(-4, 4))),
               0.015f, metal);
    }
  }
  std::vector<Vec3> bushes;
  for (int b = 0; b < 6; ++b)
    bushes.push_back({float(rng.uniform(-8, 8)), float(rng.uniform(0.6, 1.6)), float(rng.uniform(-10, 0))});
  for (int l = 0; l < 200 + int(rng.below(100)); ++l) {  // leaf slabs clustered in bushes
    uint32_t m = s.add_material(
        {{float(rng.uniform(0.1, 0.3)), float(rng.uniform(0.3, 0.6)), float(rng.uniform(0.05, 0.2))}, {}});
    Vec3 c = bushes[rng.below(bushes.size())] +
             Vec3(float(rng.normal(0, 0.5)), float(rng.normal(0, 0.4)), float(rng.normal(0, 0.5)));
    Vec3 e1 =
        normalize(Vec3(float(rng.normal()), float(rng.normal()), float(rng.normal()))) * float(rng.uniform(0.15, 0.4));
    Vec3 e2 = normalize(cross(e1, Vec3(float(rng.normal()), float(rng.normal()), float(rng.normal())))) *
              float(rng.uniform(0.08, 0.25));
    add_quad(s, c, e1, e2, m);
  }
  // A hedge row behind, so views are not all ground and sky.
  uint32_t hedge = s.add_material({{0.15f, 0.35f, 0.1f}, {}});
  add_box(s, {-20, 0, -14}, {20, float(rng.uniform(1.5, 3)), -12}, hedge);
  outdoor_lighting(s, rng);
  s.cameras = {{-7, 0.6f, -8}, {7, 1.8f, 2}, -15, 15};
  return s;
}

// Large depth discontinuities: objects floating 1-4 m from the camera in front of
// walls 10-25 m away (SSAO halos at the silhouettes).
Scene make_floating(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  add_ground(s, rng, 80);
  float far = float(rng.uniform(10, 25));
  uint32_t wall = s.add_material(random_material(rng, 0.4f, 0.8f));
  add_wall(s, true, -far, -40, 40, float(rng.uniform(6, 15)), 0.5f, {}, wall);
  if (rng.below(2)) add_wall(s, false, float(rng.uniform(-25, -10)), -far, 5, 10, 0.5f, {}, wall);
  for (int k = 0; k < 20 + int(rng.below(15)); ++k) {
    uint32_t m = s.add_material(random_material(rng));
    Vec3 c(float(rng.uniform(-5, 5)), float(rng.uniform(0.4, 3.0)), float(rng.uniform(-5, 2.5)));
    if (rng.below(2)) {
      Vec3 half(float(rng.uniform(0.15, 0.8)), float(rng.uniform(0.15, 0.8)), float(rng.uniform(0.15, 0.8)));
      add_box_yaw(s, c, half, float(rng.uniform(0, kPi)), m);
    } else {
      add_cylinder(s, c, float(rng.uniform(0.1, 0.5)), float(rng.uniform(0.3, 1.8)), 16, m);
    }
  }
  outdoor_lighting(s, rng);
  s.cameras = {{-3, 1.0f, 3.5f}, {3, 2.5f, 7}, -15, 10, 0, 60};
  return s;
}

// Occluders just outside the screen: overhangs above the camera region and tall walls
// beside it, so the visible floor is darkened by geometry no screen-space method sees.
Scene make_offscreen(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  add_ground(s, rng, 60);
  // Canopies first, then walls and low blocks beneath and around them.
  for (int k = 0; k < 3 + int(rng.below(3)); ++k) {
    uint32_t m = s.add_material(random_material(rng));
    Vec3 c(float(rng.uniform(-5, 5)), 0, float(rng.uniform(-5, 5)));
    float w = float(rng.uniform(1.5, 4)), d = float(rng.uniform(1.5, 4)), y = float(rng.uniform(2.2, 3.2));
    add_box(s, c + Vec3(-w, y, -d), c + Vec3(w, y + 0.3f, d), m);
    add_beam(s, c + Vec3(-w + 0.1f, 0, -d + 0.1f), c + Vec3(-w + 0.1f, y, -d + 0.1f), 0.12f, m);
    add_beam(s, c + Vec3(w - 0.1f, 0, d - 0.1f), c + Vec3(w - 0.1f, y, d - 0.1f), 0.12f, m);
  }
  for (int k = 0; k < 3 + int(rng.below(3)); ++k) {  // tall walls
    uint32_t m = s.add_material(random_material(rng));
    Vec3 c(float(rng.uniform(-7, 7)), 2.5f, float(rng.uniform(-7, 7)));
    add_box_yaw(s, c, {float(rng.uniform(1, 4)), 2.5f, 0.2f}, float(rng.uniform(0, kPi)), m);
  }
  for (int k = 0; k < 10 + int(rng.below(10)); ++k) {  // low blocks: what the overhangs shade
    uint32_t m = s.add_material(random_material(rng));
    Vec3 half(float(rng.uniform(0.2, 0.8)), float(rng.uniform(0.2, 0.6)), float(rng.uniform(0.2, 0.8)));
    Vec3 c(float(rng.uniform(-7, 7)), half.y, float(rng.uniform(-7, 7)));
    add_box_yaw(s, c, half, float(rng.uniform(0, kPi)), m);
  }
  outdoor_lighting(s, rng);
  s.cameras = {{-6, 0.8f, -6}, {6, 1.9f, 6}, -30, 5};
  return s;
}

}  // namespace nns::render
