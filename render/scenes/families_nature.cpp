// Natural families of the second generation: trees, shrubs and grass (foliage),
// displaced terrain with rocks, and a cave seen from inside.
#include "render/scenes/families.h"
#include "render/scenes/family_kit.h"

namespace nns::render {

namespace {
// A leaf: a thin diamond (two triangles) around `c`, random orientation, one-sided
// thin geometry that depth buffers resolve badly.
void add_leaf(Scene& s, Rng& rng, Vec3 c, float size, uint32_t m) {
  Vec3 a = normalize(Vec3(float(rng.normal()), float(rng.normal()), float(rng.normal()))) * size;
  Vec3 b = normalize(cross(a, Vec3(float(rng.normal()), float(rng.normal()), float(rng.normal())))) * (size * 0.4f);
  uint32_t i = uint32_t(s.positions.size());
  s.positions.insert(s.positions.end(), {c - a, c + b, c + a, c - b});
  s.triangles.push_back({{i, i + 1, i + 2}, m});
  s.triangles.push_back({{i, i + 2, i + 3}, m});
}

// A branch from `a` along `dir` (unit), splitting `depth` more times; leaves at the tips.
void add_branch(Scene& s, Rng& rng, Vec3 a, Vec3 dir, float len, float r, int depth, uint32_t bark, uint32_t leaf,
                float leaf_size, float leaf_density, const SceneStyle& st) {
  Vec3 b = a + dir * len;
  add_round_cylinder(s, a, b, r, st.segments(depth > 1 ? 10 : 6), bark, st.smooth, false);
  if (depth == 0) {
    int n = scaled_count(30, leaf_density);
    for (int i = 0; i < n; ++i)
      add_leaf(
          s, rng,
          b + Vec3(float(rng.normal(0, 0.3)), float(rng.normal(0, 0.25)), float(rng.normal(0, 0.3))) * (len * 1.2f),
          leaf_size * float(rng.uniform(0.7, 1.3)), leaf);
    return;
  }
  int kids = 2 + int(rng.below(2));
  for (int k = 0; k < kids; ++k) {
    Vec3 jitter(float(rng.normal(0, 0.6)), float(rng.normal(0.3, 0.3)), float(rng.normal(0, 0.6)));
    Vec3 d = normalize(dir + jitter);
    add_branch(s, rng, b, d, len * float(rng.uniform(0.6, 0.8)), r * 0.65f, depth - 1, bark, leaf, leaf_size,
               leaf_density, st);
  }
}

float terrain_height(uint64_t seed, float x, float z, float amp, float freq, float ridge) {
  Vec3 p(x * freq, 0.5f, z * freq);
  float h = fbm(seed, p, 5);
  float rdg = 1 - std::fabs(fbm(seed ^ 0x5bd1e995ull, p * 0.7f, 4));  // ridges: creases of |noise|
  return amp * (h + ridge * rdg * rdg);
}
}  // namespace

// Foliage: trees whose branches split into thinner round branches and end in clusters
// of leaves, shrubs of leaves, grass blades, on gently rolling ground. Thousands of
// thin overlapping surfaces: the hard case for depth-buffer AO.
Scene make_foliage(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  uint64_t gseed = rng.next_u64();
  uint32_t ground = s.add_material(random_material(rng, 0.2f, 0.45f));
  add_height_field(
      s, -30, 30, -30, 30, 60, 60,
      [gseed](float x, float z) {
        return 0.6f * fbm(gseed, {x * 0.08f, 0.3f, z * 0.08f}, 3);
      },
      ground, st.smooth);
  auto ground_at = [gseed](float x, float z) { return 0.6f * fbm(gseed, {x * 0.08f, 0.3f, z * 0.08f}, 3); };
  uint32_t bark = s.add_material(
      {{float(rng.uniform(0.25, 0.45)), float(rng.uniform(0.18, 0.3)), float(rng.uniform(0.1, 0.2))}, {}});
  std::vector<uint32_t> leaves;
  for (int i = 0; i < 3; ++i)
    leaves.push_back(s.add_material(
        {{float(rng.uniform(0.1, 0.35)), float(rng.uniform(0.3, 0.6)), float(rng.uniform(0.05, 0.2))}, {}}));
  // Trees and shrubs over the camera box too, so views look into foliage, not only at
  // ground with trees in the distance.
  for (int k = scaled_count(5, st.density); k > 0; --k) {  // trees
    float x = float(rng.uniform(-9, 9)), z = float(rng.uniform(-12, 6));
    Vec3 base(x, ground_at(x, z) - 0.1f, z);
    float th = float(rng.uniform(1.0, 3.0)) * st.scale, tr = float(rng.uniform(0.08, 0.2)) * st.scale;
    add_lathe(s, base, {0, 1, 0}, {{tr * 1.5f, 0}, {tr * 1.1f, 0.3f}, {tr, th * 0.5f}, {tr * 0.8f, th}},
              st.segments(14), bark, st.smooth);
    add_branch(s, rng, base + Vec3(0, th, 0), normalize(Vec3(float(rng.normal(0, 0.2)), 1, float(rng.normal(0, 0.2)))),
               th * 0.6f, tr * 0.7f, 3, bark, leaves[rng.below(leaves.size())], float(rng.uniform(0.08, 0.2)),
               st.density, st);
  }
  for (int k = scaled_count(12, st.density); k > 0; --k) {  // shrubs
    float x = float(rng.uniform(-9, 9)), z = float(rng.uniform(-12, 6));
    float rad = float(rng.uniform(0.3, 0.9)) * st.scale;
    Vec3 c(x, ground_at(x, z) + rad * 0.7f, z);
    uint32_t m = leaves[rng.below(leaves.size())];
    for (int i = int(250 * rad * rad * 4); i > 0; --i)
      add_leaf(
          s, rng,
          c + Vec3(float(rng.normal(0, rad * 0.5)), float(rng.normal(0, rad * 0.4)), float(rng.normal(0, rad * 0.5))),
          float(rng.uniform(0.05, 0.12)), m);
  }
  uint32_t grass = s.add_material({{0.2f, 0.45f, 0.12f}, {}});
  for (int p = scaled_count(10, st.density); p > 0; --p) {  // patches of grass blades
    float cx = float(rng.uniform(-9, 9)), cz = float(rng.uniform(-12, 6)), rad = float(rng.uniform(0.5, 1.5));
    for (int i = 0; i < 250; ++i) {
      float x = cx + float(rng.normal(0, rad * 0.5)), z = cz + float(rng.normal(0, rad * 0.5));
      Vec3 b(x, ground_at(x, z) - 0.02f, z);
      float a = float(rng.uniform(0, kPi)), w = 0.012f, hh = float(rng.uniform(0.15, 0.45));
      Vec3 side(std::cos(a) * w, 0, std::sin(a) * w);
      Vec3 tip = b + Vec3(float(rng.normal(0, 0.08)), hh, float(rng.normal(0, 0.08)));
      uint32_t i0 = uint32_t(s.positions.size());
      s.positions.insert(s.positions.end(), {b - side, b + side, tip});
      s.triangles.push_back({{i0, i0 + 1, i0 + 2}, grass});
    }
  }
  outdoor_lighting(s, rng);
  s.cameras = {{-7, 0.8f, -6}, {7, 2.0f, 6}, -25, 10};
  return s;
}

// Terrain: a displaced height field (fractal noise plus sharp ridges, 2-8 m of
// relief, smooth or faceted) with half-buried rocks, seen from a few metres above the
// ground near the middle. Large curved surfaces and small bumps at every scale.
Scene make_terrain(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  uint64_t hseed = rng.next_u64();
  float amp = float(rng.uniform(2, 8)), freq = float(rng.uniform(0.03, 0.08)), ridge = float(rng.uniform(0, 1.2));
  auto height = [=](float x, float z) { return terrain_height(hseed, x, z, amp, freq, ridge); };
  uint32_t ground = s.add_material(random_material(rng, 0.25f, 0.6f));
  add_height_field(s, -50, 50, -50, 50, 200, 200, height, ground, st.smooth);
  uint32_t rock = s.add_material(random_material(rng, 0.3f, 0.6f));
  for (int k = scaled_count(60, st.density); k > 0; --k) {
    // Half of the rocks near the camera box, where they fill the foreground.
    float span = k % 2 ? 15.0f : 8.0f;
    float x = float(rng.uniform(-span, span)), z = float(rng.uniform(-span, span));
    float r = float(std::exp(rng.uniform(std::log(0.1), std::log(1.5)))) * st.scale;
    uint64_t rseed = rng.next_u64();
    Vec3 radii(r, r * float(rng.uniform(0.4, 0.9)), r * float(rng.uniform(0.6, 1.2)));
    add_displaced_sphere(
        s, {x, height(x, z) + radii.y * 0.2f, z}, radii, 2 + int(r > 0.5f),
        [rseed](Vec3 p) { return 0.3f * fbm(rseed, p * 1.5f, 3); }, rock, st.smooth);
  }
  // The camera box sits just above the highest ground under it, so no camera starts
  // underground (placement cannot tell the underside of the terrain from a floor).
  float top = -1e30f, lo = 1e30f;
  for (float x = -6; x <= 6; x += 0.25f)
    for (float z = -6; z <= 6; z += 0.25f) top = std::max(top, height(x, z)), lo = std::min(lo, height(x, z));
  outdoor_lighting(s, rng, 15, 60);
  s.cameras = {{-6, top + 0.6f, -6}, {6, top + 0.6f + std::max(1.0f, top - lo), 6}, -40, 5};
  return s;
}

// A cave from inside: a large displaced, squashed sphere with a rough floor,
// stalagmites and stalactites (cones up and down), boulders, lit by lamps. Concave
// curved walls all round: what the other families, all seen from outside, lack.
Scene make_cave(uint64_t seed) {
  Rng rng(seed);
  Scene s;
  SceneStyle st = draw_style(rng);
  Vec3 radii(float(rng.uniform(6, 12)), float(rng.uniform(3, 5)), float(rng.uniform(6, 12)));
  uint64_t wseed = rng.next_u64();
  float amp = float(rng.uniform(0.15, 0.3));
  uint32_t rock = s.add_material(random_material(rng, 0.3f, 0.65f));
  add_displaced_sphere(
      s, {0, 0, 0}, radii, 5, [=](Vec3 p) { return amp * fbm(wseed, p * 2.5f, 4); }, rock, st.smooth);
  float floor_y = -radii.y * 0.55f;
  uint64_t fseed = rng.next_u64();
  auto floor_at = [=](float x, float z) { return floor_y + 0.4f * fbm(fseed, {x * 0.3f, 0.7f, z * 0.3f}, 3); };
  add_height_field(s, -radii.x, radii.x, -radii.z, radii.z, 64, 64, floor_at, rock, st.smooth);
  for (int k = scaled_count(12, st.density); k > 0; --k) {
    float x = float(rng.uniform(-radii.x * 0.6, radii.x * 0.6)), z = float(rng.uniform(-radii.z * 0.6, radii.z * 0.6));
    float r = float(rng.uniform(0.1, 0.5)) * st.scale, h = r * float(rng.uniform(2, 6));
    if (rng.below(2)) {
      add_cone(s, {x, floor_at(x, z) - 0.05f, z}, r, h, st.segments(16), rock, st.smooth);
    } else {  // hanging: a cone pointing down from above the highest the ceiling can be
      float above = radii.y * (1 + amp), tip = radii.y * 0.6f - h;
      add_lathe(s, {x, above, z}, {0, -1, 0}, {{0, 0}, {r, 0}, {r, 0}, {0, above - tip}}, st.segments(16), rock,
                st.smooth);
    }
  }
  for (int k = scaled_count(8, st.density); k > 0; --k) {
    float x = float(rng.uniform(-radii.x * 0.6, radii.x * 0.6)), z = float(rng.uniform(-radii.z * 0.6, radii.z * 0.6));
    float r = float(rng.uniform(0.2, 1.2)) * st.scale;
    uint64_t bseed = rng.next_u64();
    add_displaced_sphere(
        s, {x, floor_at(x, z) + r * 0.3f, z}, {r, r * 0.7f, r}, 3,
        [bseed](Vec3 p) { return 0.25f * fbm(bseed, p * 2.0f, 3); }, rock, st.smooth);
  }
  s.sky = Sky::constant({0, 0, 0});
  for (int k = 2 + int(rng.below(2)); k > 0; --k)
    s.points.push_back({{float(rng.uniform(-radii.x * 0.4, radii.x * 0.4)), floor_y + 1.5f,
                         float(rng.uniform(-radii.z * 0.4, radii.z * 0.4))},
                        Vec3(6, 5, 4)});
  s.cameras = {{-radii.x * 0.45f, floor_y + 0.8f, -radii.z * 0.45f},
               {radii.x * 0.45f, floor_y + 2.2f, radii.z * 0.45f},
               -30,
               20};
  return s;
}

}  // namespace nns::render
