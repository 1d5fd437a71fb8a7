// Procedural material textures (render/material_texture.h): a plain material is its
// albedo bit for bit; a textured one varies within one triangle, stays in [0, 0.95],
// does not depend on the side a ray comes from; the G-buffer and every bounce of the
// integrator read the same textured albedo; the per-scene draw is deterministic.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <set>
#include <tuple>

#include "core/rng.h"
#include "render/integrator.h"
#include "render/render_view.h"
#include "render/sampling.h"
#include "render/scenes/builder.h"
#include "render/scenes/families.h"
#include "render/scenes/texture_variation.h"

using namespace nns;
using namespace nns::data;
using namespace nns::render;

namespace {
const TextureKind kKinds[] = {TextureKind::noise, TextureKind::bricks, TextureKind::tiles, TextureKind::wood,
                              TextureKind::stains};

// A texture of each kind with strong contrast and some dirt, from the preset's own draw.
MaterialTexture strong(TextureKind k, uint64_t seed) {
  Rng rng(seed);
  MaterialTexture t = draw_texture(k, rng);
  t.contrast = 0.6f;
  return t;
}

// One 40 m triangle on the floor, material 0, and a camera 3 m above looking down.
Scene floor_triangle(const Material& m) {
  Scene s;
  s.name = "tri";
  s.add_material(m);
  s.positions = {{-20, 0, -20}, {20, 0, -20}, {0, 0, 20}};
  s.triangles.push_back({{0, 1, 2}, 0});
  return s;
}
}  // namespace

TEST(MaterialTexture, PlainMaterialIsItsAlbedoBitForBit) {
  const Material m({0.31f, 0.52f, 0.77f});
  Rng rng(1);
  for (int i = 0; i < 1000; ++i) {
    Vec3 p(float(rng.uniform(-50, 50)), float(rng.uniform(-5, 20)), float(rng.uniform(-50, 50)));
    Vec3 n = normalize(Vec3(float(rng.normal()), float(rng.normal()), float(rng.normal())));
    Vec3 a = surface_albedo(m, p, n);
    ASSERT_EQ(a.x, m.albedo.x);
    ASSERT_EQ(a.y, m.albedo.y);
    ASSERT_EQ(a.z, m.albedo.z);
  }
}

// Every kind: many distinct values over one triangle seen from above, in range; the
// rendered G-buffer albedo of the same triangle varies too (and a plain one does not).
TEST(MaterialTexture, VariesWithinATriangleAndStaysInRange) {
  for (TextureKind k : kKinds) {
    const Material m({0.6f, 0.55f, 0.5f}, {}, strong(k, 7));
    Rng rng(2);
    std::set<std::tuple<float, float, float>> distinct;
    double sum = 0, sum2 = 0;
    const int n = 4000;
    for (int i = 0; i < n; ++i) {
      // Points inside the triangle, over a 4 m patch (the scale of a wall in view).
      Vec3 p(float(rng.uniform(-2, 2)), 0, float(rng.uniform(-2, 2)));
      Vec3 a = surface_albedo(m, p, {0, 1, 0});
      for (float c : {a.x, a.y, a.z})
        ASSERT_TRUE(c >= 0 && c <= kMaxTexturedAlbedo) << texture_kind_name(k) << " " << c;
      distinct.insert({a.x, a.y, a.z});
      double l = (a.x + a.y + a.z) / 3;
      sum += l, sum2 += l * l;
    }
    const double mean = sum / n, sd = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
    EXPECT_GT(distinct.size(), size_t(n / 2)) << texture_kind_name(k);
    EXPECT_GT(sd, 0.02) << texture_kind_name(k) << ": the pattern hardly changes the albedo";
    EXPECT_GT(mean, 0.15) << texture_kind_name(k) << ": the pattern darkens the base to black";

    Scene s = floor_triangle(m);
    RayTracer rt(s);
    Camera cam = Camera::from_yaw_pitch({0, 3, 0}, 0, -1.5f);
    cam.width = cam.height = 32;
    cam.fov_y_deg = 60;
    RenderSettings rs;
    rs.ao = false, rs.lighting = false;
    View v = render_view(rt, cam, rs, 1);
    std::set<float> seen(v.channel("albedo.G").begin(), v.channel("albedo.G").end());
    EXPECT_GT(seen.size(), 100u) << texture_kind_name(k) << ": G-buffer albedo constant over the triangle";
    Scene plain = floor_triangle(Material({0.6f, 0.55f, 0.5f}));
    RayTracer rp(plain);
    View vp = render_view(rp, cam, rs, 1);
    EXPECT_EQ(std::set<float>(vp.channel("albedo.G").begin(), vp.channel("albedo.G").end()).size(), 1u);
  }
}

// A surface is two-sided: rays from either side must see the same albedo, and the
// same point gives the same value every time (no global state).
TEST(MaterialTexture, SameFromBothSidesAndDeterministic) {
  Rng rng(3);
  for (TextureKind k : kKinds) {
    const MaterialTexture t = strong(k, 11);
    for (int i = 0; i < 500; ++i) {
      Vec3 p(float(rng.uniform(-30, 30)), float(rng.uniform(0, 10)), float(rng.uniform(-30, 30)));
      Vec3 n = normalize(Vec3(float(rng.normal()), float(rng.normal()), float(rng.normal())));
      Vec3 a = textured_albedo(t, {0.5f, 0.5f, 0.5f}, p, n), b = textured_albedo(t, {0.5f, 0.5f, 0.5f}, p, -n);
      Vec3 c = textured_albedo(t, {0.5f, 0.5f, 0.5f}, p, n);
      ASSERT_EQ(a.x, b.x) << texture_kind_name(k);
      ASSERT_EQ(a.z, b.z) << texture_kind_name(k);
      ASSERT_EQ(a.y, c.y) << texture_kind_name(k);
    }
  }
}

// The whole range the preset draws, on the brightest base albedo any variation gives
// (0.9), at any point and normal: finite and within [0, 0.95].
TEST(MaterialTexture, EveryDrawStaysPhysical) {
  Rng rng(4);
  for (int d = 0; d < 300; ++d) {
    MaterialTexture t = draw_texture(kKinds[d % 5], rng);
    t.dirt = d % 2 ? 0.7f : 0.0f;
    Vec3 base(float(rng.uniform(0, 0.9)), float(rng.uniform(0, 0.9)), 0.9f);
    for (int i = 0; i < 50; ++i) {
      Vec3 p(float(rng.uniform(-100, 100)), float(rng.uniform(-10, 40)), float(rng.uniform(-100, 100)));
      Vec3 n = normalize(Vec3(float(rng.normal()), float(rng.normal()), float(rng.normal())));
      Vec3 a = textured_albedo(t, base, p, n);
      for (float c : {a.x, a.y, a.z})
        ASSERT_TRUE(c >= 0 && c <= kMaxTexturedAlbedo) << texture_kind_name(t.kind) << " " << c;
    }
  }
}

// Ground truth reads the texture at every bounce. A closed 2 m box emitting Le with a
// checkered tile texture, 3 bounces, no lights: indirect at x = Le (1 + a(y) + a(y) a(z))
// averaged over cosine-sampled first and second hits y, z. Its mean, estimated here
// from the hits' textured albedo, must match the integrator's; the base albedo alone
// (what an integrator ignoring textures would use) gives Le (1 + a + a^2), far off.
TEST(MaterialTexture, IntegratorBouncesSeeTheTexture) {
  MaterialTexture t;
  t.kind = TextureKind::tiles, t.seed = 5, t.scale = 0.4f, t.aspect = 1, t.contrast = 0.5f, t.joint = 0.02f;
  t.checker = 0.7f;
  const float base = 0.8f, le = 1.0f;
  Scene s;
  s.name = "furnace";
  s.add_material(Material({base, base, base}, {le, le, le}, t));
  add_box(s, {-1, -1, -1}, {1, 1, 1}, 0);
  RayTracer rt(s);
  Hit x;
  x.position = {0.13f, -1, 0.21f};
  x.normal = {0, 1, 0};
  x.material = &s.materials[0];

  // The expectation by direct sampling of the two hits.
  Rng rng(9);
  const int n = 400000;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    Vec3 d = Frame(x.normal).to_world(cosine_hemisphere(rng.uniform_float(), rng.uniform_float()));
    Hit y = rt.intersect(RayTracer::offset(x.position, x.normal), d);
    ASSERT_TRUE(y.valid());
    Vec3 d2 = Frame(y.normal).to_world(cosine_hemisphere(rng.uniform_float(), rng.uniform_float()));
    Hit z = rt.intersect(RayTracer::offset(y.position, y.normal), d2);
    ASSERT_TRUE(z.valid());
    const float ay = surface_albedo(s.materials[0], y.position, y.normal).y;
    const float az = surface_albedo(s.materials[0], z.position, z.normal).y;
    const double v = le * (1 + ay + ay * az);
    sum += v, sum2 += v * v;
  }
  const double expect = sum / n, se_expect = std::sqrt((sum2 / n - expect * expect) / n);

  // The integrator: 16 independent estimates of 8192 paths each.
  const int runs = 16;
  double m = 0, m2 = 0;
  for (int r = 0; r < runs; ++r) {
    Rng g(100 + uint64_t(r));
    Vec3 env, ind;
    env_and_indirect(rt, x, 8192, 3, g, env, ind);
    EXPECT_EQ(env.y, 0.0f);
    m += ind.y, m2 += double(ind.y) * ind.y;
  }
  m /= runs;
  const double se_m = std::sqrt(std::max(0.0, m2 / runs - m * m) / (runs - 1));
  const double tol = 4 * std::sqrt(se_expect * se_expect + se_m * se_m);
  EXPECT_NEAR(m, expect, tol) << "integrator " << m << " vs textured expectation " << expect;
  const double plain = le * (1 + base + base * base);
  EXPECT_GT(std::fabs(plain - expect), 10 * tol) << "the texture must change the answer for this test to mean anything";
}

// The per-scene draw: deterministic in the rng, a share of the materials textured and
// the rest plain, emissive materials never, every kind drawn across scenes.
TEST(TextureVariation, DeterministicSharedAndSparesEmitters) {
  std::set<TextureKind> kinds;
  int textured = 0, plain = 0;
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    const Scene base = make_family_scene(seed % 2 ? "multiroom" : "corridor", int(seed), 3);
    Scene a = base, b = base;
    Rng ra(seed), rb(seed);
    vary_textures(a, ra);
    vary_textures(b, rb);
    ASSERT_EQ(a.materials.size(), base.materials.size());
    for (size_t i = 0; i < a.materials.size(); ++i) {
      const Material &ma = a.materials[i], &mb = b.materials[i];
      EXPECT_EQ(std::memcmp(&ma, &mb, sizeof(Material)), 0);
      EXPECT_EQ(ma.albedo.x, base.materials[i].albedo.x) << "textures keep the base albedo";
      const Vec3 e = ma.emission;
      if (e.x > 0 || e.y > 0 || e.z > 0) {
        EXPECT_EQ(ma.texture.kind, TextureKind::none) << "an emitter got a texture";
        continue;
      }
      (ma.texture.kind == TextureKind::none ? plain : textured)++;
      kinds.insert(ma.texture.kind);
    }
  }
  EXPECT_GT(textured, 2 * plain) << textured << " textured, " << plain << " plain";
  EXPECT_GT(plain, 0);
  for (TextureKind k : kKinds) EXPECT_TRUE(kinds.count(k)) << texture_kind_name(k) << " never drawn";
}
