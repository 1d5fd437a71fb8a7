// The renderer against closed forms: AO of an open plane, a crease and a closed box;
// direct light of a sun on a plane; indirect light in an emissive furnace.
#include <gtest/gtest.h>

#include <cmath>

#include "core/thread_pool.h"
#include "render/integrator.h"
#include "render/render_view.h"
#include "render/scenes/builder.h"

using namespace nns;
using namespace nns::data;
using namespace nns::render;

namespace {
// A hit at p with normal n, as the camera would produce it.
Hit hit_at(const Scene& s, Vec3 p, Vec3 n) {
  Hit h;
  h.position = p;
  h.normal = n;
  h.material = &s.materials[0];
  return h;
}

// A closed 2 m box of albedo a whose walls emit le.
Scene furnace_scene(float a, float le) {
  Scene s;
  s.name = "furnace";
  uint32_t m = s.add_material({{a, a, a}, {le, le, le}});
  add_box(s, {-1, -1, -1}, {1, 1, 1}, m);
  return s;
}

// The view rendered with 1 and with 2 threads; every plane must be bit-identical.
View render_with_1_and_2_threads(const RayTracer& rt, const Camera& cam, const RenderSettings& rs, uint64_t id) {
  set_num_threads(1);
  View a = render_view(rt, cam, rs, id);
  set_num_threads(2);
  View b = render_view(rt, cam, rs, id);
  EXPECT_EQ(a.channels.size(), b.channels.size());
  for (auto& [name, plane] : a.channels) EXPECT_EQ(plane, b.channels.at(name)) << name;
  return a;
}

Scene floor_scene(float half = 1000) {
  Scene s;
  s.name = "floor";
  uint32_t m = s.add_material({});
  add_quad(s, {-half, 0, -half}, {2 * half, 0, 0}, {0, 0, 2 * half}, m);
  return s;
}
}  // namespace

TEST(RenderAO, OpenPlaneIsUnoccluded) {
  Scene s = floor_scene();
  RayTracer rt(s);
  Rng rng(1);
  EXPECT_EQ(ambient_occlusion(rt, hit_at(s, {0.3f, 0, -0.2f}, {0, 1, 0}), 5.0f, 256, rng), 1.0f);
}

// A floor point at distance d from a perpendicular wall (normal along the floor).
// Cosine-weighted, the wall's half-space x < 0 holds exactly half the hemisphere's
// weight (the wall plane contains the normal, so the split is symmetric); rays into it
// escape only if |dir.x| < d / radius. With d = 1e-3 * radius that sliver is ~1e-3.
TEST(RenderAO, CreaseIsHalfOccluded) {
  Scene s = floor_scene();
  add_quad(s, {0, 0, -1000}, {0, 1000, 0}, {0, 0, 2000}, 0);
  RayTracer rt(s);
  Rng rng(2);
  float ao = ambient_occlusion(rt, hit_at(s, {0.001f, 0, 0}, {0, 1, 0}), 1.0f, 4096, rng);
  EXPECT_NEAR(ao, 0.5f, 0.005f);
}

TEST(RenderAO, ClosedSmallBoxIsFullyOccluded) {
  Scene s;
  s.name = "box";
  uint32_t m = s.add_material({});
  add_box(s, {-0.5f, 0, -0.5f}, {0.5f, 1, 0.5f}, m);
  RayTracer rt(s);
  Rng rng(3);
  EXPECT_EQ(ambient_occlusion(rt, hit_at(s, {0.1f, 0, 0.2f}, {0, 1, 0}), 100.0f, 256, rng), 0.0f);
  // With a radius shorter than the box, the same point is open again: the radius is honoured.
  EXPECT_EQ(ambient_occlusion(rt, hit_at(s, {0, 0, 0}, {0, 1, 0}), 0.2f, 256, rng), 1.0f);
}

// direct = color * cos(theta) for a point sun; an occluder puts the point in shadow.
TEST(RenderDirect, SunOnPlaneIsColorTimesCosine) {
  Scene s = floor_scene();
  float theta = 0.7f;
  s.suns.push_back({{std::sin(theta), std::cos(theta), 0}, {2.0f, 1.0f, 0.5f}, 0});
  RayTracer rt(s);
  Rng rng(4);
  Vec3 d = direct_light(rt, {0, 0, 0}, {0, 1, 0}, 1, rng);
  EXPECT_NEAR(d.x, 2.0f * std::cos(theta), 1e-5);
  EXPECT_NEAR(d.z, 0.5f * std::cos(theta), 1e-5);
  // A sun below the horizon gives nothing.
  s.suns[0].direction = {0, -1, 0};
  EXPECT_EQ(direct_light(rt, {0, 0, 0}, {0, 1, 0}, 1, rng).x, 0.0f);
}

TEST(RenderDirect, SunShadowAndSoftSun) {
  Scene s = floor_scene();
  add_box(s, {-1, 2, -1}, {1, 2.1f, 1}, 0);
  s.suns.push_back({{0, 1, 0}, {1, 1, 1}, 0});
  RayTracer rt(s);
  Rng rng(5);
  EXPECT_EQ(direct_light(rt, {0, 0, 0}, {0, 1, 0}, 1, rng).x, 0.0f);
  EXPECT_NEAR(direct_light(rt, {5, 0, 0}, {0, 1, 0}, 1, rng).x, 1.0f, 1e-6);
  // An unoccluded disc of angular radius a straight overhead: mean cos over the cone
  // = (1 + cos a) / 2.
  s.suns[0].angular_radius = 0.2f;
  EXPECT_NEAR(direct_light(rt, {5, 0, 0}, {0, 1, 0}, 64, rng).x, (1 + std::cos(0.2f)) / 2, 1e-3);
}

// A point light at height h over a plane: color * cos / d^2 = color * h / d^3.
TEST(RenderDirect, PointLightInverseSquare) {
  Scene s = floor_scene();
  s.points.push_back({{0, 2, 0}, {8, 8, 8}});
  RayTracer rt(s);
  Rng rng(6);
  float d = std::sqrt(4.0f + 1.5f * 1.5f);
  EXPECT_NEAR(direct_light(rt, {1.5f, 0, 0}, {0, 1, 0}, 1, rng).y, 8 * 2 / (d * d * d), 1e-5);
}

// A large rect light of radiance L close over a point approaches E/pi = L (a full
// hemisphere of radiance L); a 2x2 square at height 1 gives the form factor
// 4 * F(unit corner rectangle) = 4 * 0.13853 (parallel-rectangle closed form at a corner).
TEST(RenderDirect, RectLightFormFactor) {
  Scene s = floor_scene();
  s.rects.push_back({{-1, 1, -1}, {2, 0, 0}, {0, 0, 2}, {1, 1, 1}});  // emits downwards
  RayTracer rt(s);
  Rng rng(7);
  auto corner = [](double a, double b) {  // point below a corner of an a x b rectangle at height 1
    double A = a / std::sqrt(1 + a * a), B = b / std::sqrt(1 + b * b);
    return (A * std::atan(b / std::sqrt(1 + a * a)) + B * std::atan(a / std::sqrt(1 + b * b))) / (2 * M_PI);
  };
  EXPECT_NEAR(direct_light(rt, {0, 0, 0}, {0, 1, 0}, 4096, rng).x, 4 * corner(1, 1), 2e-3);
}

// Next-event estimation with one light per vertex (light_sample) against the closed
// form of the all-lights sum: a point sun, a rect light, point lights 10^4 apart in
// power, one below the horizon and one shut in a box (picked now and then, it gives 0:
// the estimate stays unbiased because visibility is not in the probabilities).
// N samples; the mean must lie within 4 standard errors of the closed form per channel
// (the standard error is measured from the samples: about 0.3% of the value here),
// with fixed probabilities and with the visibility learnt from earlier samples.
TEST(RenderNextEvent, OneLightConvergesToAllLights) {
  Scene s = floor_scene();
  add_box(s, {2.5f, 0, -0.5f}, {3.5f, 1, 0.5f}, 0);  // closed box round the last lamp
  float theta = 0.7f;
  s.suns.push_back({{std::sin(theta), std::cos(theta), 0}, {2.0f, 1.0f, 0.5f}, 0});
  s.points.push_back({{-20, 10, 5}, {400, 300, 200}});                      // far and strong
  s.points.push_back({{0.3f, 0.5f, -0.2f}, {0.04f, 0.05f, 0.06f}});         // near and dim
  s.points.push_back({{1, -1, 0}, {50, 50, 50}});                           // below the floor's horizon
  s.points.push_back({{3, 0.5f, 0}, {30, 30, 30}});                         // inside the box
  s.rects.push_back({{-1, 1, -1}, {2, 0, 0}, {0, 0, 2}, {0.5f, 1, 1.5f}});  // 2x2 at height 1, emits down
  RayTracer rt(s);
  auto corner = [](double a, double b) {  // as in RectLightFormFactor
    double A = a / std::sqrt(1 + a * a), B = b / std::sqrt(1 + b * b);
    return (A * std::atan(b / std::sqrt(1 + a * a)) + B * std::atan(a / std::sqrt(1 + b * b))) / (2 * M_PI);
  };
  double exact[3];
  for (int c = 0; c < 3; ++c) {
    double e = s.suns[0].color[c] * std::cos(theta) + s.rects[0].radiance[c] * 4 * corner(1, 1);
    for (int i = 0; i < 2; ++i) {  // the two lamps that reach p = origin: C h / d^3
      Vec3 to = s.points[size_t(i)].position;
      e += s.points[size_t(i)].color[c] * to.y / std::pow(double(length(to)), 3);
    }
    exact[c] = e;
  }
  // Without and with the visibility learnt over the samples (as one pixel's paths
  // learn it): the probabilities then change from sample to sample, the mean must not.
  for (bool learn : {false, true}) {
    LightVisibility vis(s);
    Rng rng(21);
    const int n = 400000;
    double sum[3] = {}, sum2[3] = {};
    int zeros = 0;
    for (int k = 0; k < n; ++k) {
      Vec3 v = light_sample(rt, {0, 0, 0}, {0, 1, 0}, rng, learn ? &vis : nullptr);
      zeros += v.x == 0;
      for (int c = 0; c < 3; ++c) sum[c] += v[c], sum2[c] += double(v[c]) * v[c];
    }
    for (int c = 0; c < 3; ++c) {
      double mean = sum[c] / n, se = std::sqrt((sum2[c] / n - mean * mean) / (n - 1));
      EXPECT_NEAR(mean, exact[c], 4 * se) << "learn " << learn << ", channel " << c << ", standard error " << se;
      EXPECT_LT(se, 0.005 * exact[c]) << c;
    }
    if (!learn) {
      // The boxed lamp is picked (about a fifth of the time: its unoccluded share)
      // and blocked.
      EXPECT_GT(zeros, n / 20);
      EXPECT_LT(zeros, n / 4);
    } else {
      // Learnt: after t blocked tries its weight is 1 / (t + 2) of the unoccluded
      // one, so it is tried about sqrt(2 x 0.19 n) times.
      EXPECT_GT(zeros, 0);
      EXPECT_LT(zeros, n / 200);
      EXPECT_EQ(vis.unblocked[4], 0.0f);  // the sun, then the lamps: index 1 + 3 is the boxed one
      EXPECT_EQ(vis.tried[4], float(zeros));
    }
  }
}

// A light whose centre is below the horizon of the normal but part of which is above
// it still gets samples: a rect light past its centre, a sun disc rising over the
// horizon. The reference is direct_light's stratified all-lights sum at high spp; each
// of the two contributes more than 8 standard errors of the one-light mean, so
// leaving either out fails.
TEST(RenderNextEvent, LightsPartlyAboveTheHorizonAreSampled) {
  Scene s;  // no geometry: every shadow ray is clear
  s.name = "empty";
  s.add_material({});
  s.rects.push_back({{-1, 1, -1}, {2, 0, 0}, {0, 0, 2}, {1, 1, 1}});  // centre straight above p
  s.suns.push_back({{0, 0.01f, 1}, {100, 100, 100}, 0.04f});          // centre 0.6 degrees up
  s.points.push_back({{0.5f, 0.3f, 0.4f}, {1, 1, 1}});                // a lamp, for competition
  Vec3 p(0, 0, 0);
  // The normal leans 97 degrees from up towards +x and 1.5 degrees down from the
  // horizon at +z: the rect centre and the sun centre are below its horizon, two rect
  // corners and a sliver of the disc above.
  Vec3 n = normalize(Vec3(std::sin(1.7f), std::cos(1.7f), -0.026f));
  ASSERT_LT(dot(n, Vec3(0, 1, 0)), 0.0f);
  ASSERT_LT(dot(n, normalize(s.suns[0].direction)), 0.0f);
  auto all_lights = [&](const Scene& sc) {
    RayTracer rt(sc);
    Rng r(22);
    return double(direct_light(rt, p, n, 65536, r).x);
  };
  Scene rect_only = s, sun_only = s;
  rect_only.suns.clear(), rect_only.points.clear();
  sun_only.rects.clear(), sun_only.points.clear();
  const double exact = all_lights(s), rect = all_lights(rect_only), sun = all_lights(sun_only);
  RayTracer rt(s);
  Rng rng(23);
  const int m = 400000;
  double sum = 0, sum2 = 0;
  for (int k = 0; k < m; ++k) {
    double v = light_sample(rt, p, n, rng).x;
    sum += v, sum2 += v * v;
  }
  double mean = sum / m, se = std::sqrt((sum2 / m - mean * mean) / (m - 1));
  EXPECT_NEAR(mean, exact, 4 * se) << "rect " << rect << ", sun " << sun << ", standard error " << se;
  EXPECT_GT(rect, 8 * se);
  EXPECT_GT(sun, 8 * se);
}

// Furnace: inside a closed box of albedo a whose walls emit Le, every path sees Le at
// every vertex, so indirect = Le * (1 + a + ... + a^(B-1)) exactly, with zero variance;
// env is 0 (no sky is reachable).
TEST(RenderIndirect, EmissiveFurnaceIsGeometricSeries) {
  float a = 0.6f, le = 0.25f;
  Scene s = furnace_scene(a, le);
  s.sky = Sky::constant({5, 5, 5});
  RayTracer rt(s);
  for (int bounces : {1, 2, 4}) {
    Rng rng(8);
    Vec3 env, ind;
    env_and_indirect(rt, hit_at(s, {0.2f, -1, 0.3f}, {0, 1, 0}), 16, bounces, rng, env, ind);
    double expect = le * (1 - std::pow(a, bounces)) / (1 - a);
    EXPECT_NEAR(ind.x, expect, 1e-5) << bounces;
    EXPECT_EQ(env.x, 0.0f);
  }
}

// Russian roulette in the furnace: paths whose throughput falls below 1 / roulette
// stop at random, so the estimate is no longer exact, but its mean is: 64 estimates
// of 1024 paths each lie around Le (1 - a^B) / (1 - a) within 4 standard errors
// (about 0.2% of it), they differ (the roulette is at work), and they cost fewer rays
// than the same paths without it.
TEST(RenderIndirect, RouletteKeepsTheFurnaceSeries) {
  float a = 0.6f, le = 0.25f;
  Scene s = furnace_scene(a, le);
  RayTracer rt(s);
  const int bounces = 4, calls = 64;
  const double expect = le * (1 - std::pow(a, bounces)) / (1 - a);
  double sum = 0, sum2 = 0;
  uint64_t rays_rr = 0, rays_plain = 0;
  for (int k = 0; k < calls; ++k) {
    Vec3 env, ind;
    Rng rng(100 + uint64_t(k));
    uint64_t r0 = RayTracer::thread_ray_count();
    env_and_indirect(rt, hit_at(s, {0.2f, -1, 0.3f}, {0, 1, 0}), 1024, bounces, rng, env, ind, 2.0f);
    rays_rr += RayTracer::thread_ray_count() - r0;
    sum += ind.x, sum2 += double(ind.x) * ind.x;
    Rng rng2(100 + uint64_t(k));
    r0 = RayTracer::thread_ray_count();
    env_and_indirect(rt, hit_at(s, {0.2f, -1, 0.3f}, {0, 1, 0}), 1024, bounces, rng2, env, ind);
    rays_plain += RayTracer::thread_ray_count() - r0;
    EXPECT_NEAR(ind.x, expect, 1e-5);
  }
  double mean = sum / calls, sd = std::sqrt(std::max(0.0, sum2 / calls - mean * mean));
  double se = sd / std::sqrt(calls - 1.0);
  EXPECT_NEAR(mean, expect, 4 * se) << "standard error " << se;
  EXPECT_GT(sd, 1e-4);
  EXPECT_LT(se, 0.002 * expect);
  EXPECT_LT(rays_rr, rays_plain * 9 / 10);
}

// Two suns and a gradient sky over a floor (y = 0, x > 0, albedo af) and a wall
// standing on it (x = 0, albedo aw). Each plane sees the other as exactly half of its
// cosine-weighted hemisphere (the other plane contains its normal) and the sky as the
// other half, and both are fully sunlit, so every point of a plane leaves the same
// radiance:
//   Lf(k) = af (Ef + Sf + Lw(k-1) / 2),  Lw(k) = aw (Ew + Sw + Lf(k-1) / 2),  L(0) = 0,
// E = sum over the suns of C cos; S = the sky's E/pi over the open half: with
// L(w) = h + (z - h) sqrt(w.y) and cosine-weighted w, E[sqrt(w.y)] is 4/5 around the
// floor's normal and 0.8 G(3/4) / (sqrt(pi) G(5/4)) = 0.610 over the wall's upper half,
// so Sf = (h + 0.8 (z - h)) / 2 and Sw = (h + 0.610 (z - h)) / 2. A wall point's env
// is Sw, its indirect after B bounces Lf(B) / 2. The sky term at the floor comes from
// the continuation rays, so it checks their distribution (cosine-weighted, stratified
// over the pixel's paths); the suns check one-light NEE (one sun 40x the other) and
// roulette. 64 estimates of 1024 paths, within 4 standard errors (< 0.6%).
TEST(RenderIndirect, SunsAndSkyBetweenFloorAndWall) {
  Scene s;
  s.name = "floor-wall";
  const float af = 0.6f, aw = 0.8f, big = 1e4f;
  uint32_t mf = s.add_material({{af, af, af}, {}}), mw = s.add_material({{aw, aw, aw}, {}});
  add_quad(s, {0, 0, -big}, {big, 0, 0}, {0, 0, 2 * big}, mf);
  add_quad(s, {0, 0, -big}, {0, big, 0}, {0, 0, 2 * big}, mw);
  s.suns.push_back({normalize({1, 2, 0.3f}), {2, 1.5f, 1}, 0});
  s.suns.push_back({normalize({3, 1, -0.5f}), {0.05f, 0.05f, 0.1f}, 0});
  s.sky = Sky{{0.2f, 0.5f, 2.0f}, {0.6f, 0.6f, 0.3f}, {0, 0, 0}};  // ground black: rays past the planes' far edges
  RayTracer rt(s);
  const double wall_half = 0.8 * std::tgamma(0.75) / (std::sqrt(M_PI) * std::tgamma(1.25));
  for (int bounces : {1, 2, 3}) {
    double expect[3], env_expect[3];
    for (int c = 0; c < 3; ++c) {
      double ef = 0, ew = 0, z = s.sky.zenith[c], h = s.sky.horizon[c];
      for (const Sun& sun : s.suns) ef += sun.color[c] * sun.direction.y, ew += sun.color[c] * sun.direction.x;
      double sf = (h + 0.8 * (z - h)) / 2, sw = (h + wall_half * (z - h)) / 2;
      double lf = 0, lw = 0;
      for (int k = 0; k < bounces; ++k) {
        double nf = af * (ef + sf + lw / 2), nw = aw * (ew + sw + lf / 2);
        lf = nf, lw = nw;
      }
      expect[c] = lf / 2, env_expect[c] = sw;
    }
    const int calls = 64;
    double sum[3] = {}, sum2[3] = {}, env_sum[3] = {};
    for (int k = 0; k < calls; ++k) {
      Rng rng(200 + uint64_t(k));
      Vec3 env, ind;
      env_and_indirect(rt, hit_at(s, {0, 1, 0}, {1, 0, 0}), 1024, bounces, rng, env, ind, 2.0f);
      for (int c = 0; c < 3; ++c) sum[c] += ind[c], sum2[c] += double(ind[c]) * ind[c], env_sum[c] += env[c];
    }
    for (int c = 0; c < 3; ++c) {
      double mean = sum[c] / calls, se = std::sqrt(std::max(0.0, sum2[c] / calls - mean * mean) / (calls - 1));
      EXPECT_NEAR(mean, expect[c], 4 * se) << "bounces " << bounces << ", channel " << c << ", standard error " << se;
      EXPECT_LT(se, 0.006 * expect[c]) << bounces << " " << c;
      EXPECT_NEAR(env_sum[c] / calls, env_expect[c], 2e-3 * env_expect[c]) << bounces << " " << c;
    }
  }
}

// Open sky, constant radiance S, over an infinite plane: env = S, indirect = 0.
TEST(RenderIndirect, ConstantSkyOverPlaneIsEnvOnly) {
  Scene s = floor_scene();
  s.sky = Sky::constant({0.5f, 1, 2});
  RayTracer rt(s);
  Rng rng(9);
  Vec3 env, ind;
  env_and_indirect(rt, hit_at(s, {0, 0, 0}, {0, 1, 0}), 64, 3, rng, env, ind);
  EXPECT_NEAR(env.z, 2.0f, 1e-6);
  EXPECT_EQ(ind.z, 0.0f);
}

// White furnace with a sky: a floor of albedo a in a crease-free world under constant
// sky S sees only sky -> env = S; inside a box with one open side, env + indirect
// stays below the sky radiance S / (1 - a) bound, and more bounces never lose light.
TEST(RenderIndirect, MoreBouncesNeverLoseLight) {
  Scene s;
  s.name = "cup";
  uint32_t m = s.add_material({{0.8f, 0.8f, 0.8f}, {}});
  add_quad(s, {-1, 0, -1}, {2, 0, 0}, {0, 0, 2}, m);
  add_quad(s, {-1, 0, -1}, {0, 2, 0}, {0, 0, 2}, m);
  add_quad(s, {1, 0, -1}, {0, 2, 0}, {0, 0, 2}, m);
  add_quad(s, {-1, 0, -1}, {2, 0, 0}, {0, 2, 0}, m);
  add_quad(s, {-1, 0, 1}, {2, 0, 0}, {0, 2, 0}, m);
  s.sky = Sky::constant({1, 1, 1});
  RayTracer rt(s);
  float prev = -1;
  for (int b : {1, 2, 3, 6}) {
    Rng rng(10);
    Vec3 env, ind;
    env_and_indirect(rt, hit_at(s, {0, 0, 0}, {0, 1, 0}), 4096, b, rng, env, ind);
    EXPECT_GT(ind.x + 1e-3f, prev);
    EXPECT_LT(env.x + ind.x, 1.0f / (1 - 0.8f));
    prev = ind.x;
  }
}

// Without bounces env is traced with packets of shadow rays; the directions (and so
// the estimate) are the same as in the full estimator.
TEST(RenderIndirect, EnvAloneMatchesEnvOfTheFullEstimator) {
  Scene s = floor_scene(30);
  add_box(s, {-1, 0, -3}, {1, 2, -1}, 0);
  s.sky = Sky{{0.2f, 0.3f, 0.9f}, {0.8f, 0.8f, 0.8f}, {0.1f, 0.1f, 0.1f}};
  RayTracer rt(s);
  Vec3 env0, ind0, env3, ind3;
  Rng a(12), b(12);
  env_and_indirect(rt, hit_at(s, {0.3f, 0, -0.5f}, {0, 1, 0}), 100, 0, a, env0, ind0);
  env_and_indirect(rt, hit_at(s, {0.3f, 0, -0.5f}, {0, 1, 0}), 100, 3, b, env3, ind3);
  EXPECT_NEAR(env0.z, env3.z, 1e-6);
  EXPECT_LT(env0.z, 0.9f * s.sky.zenith.z);  // the box hides part of the sky
  EXPECT_EQ(ind0.x, 0.0f);
  EXPECT_GT(ind3.x, 0.0f);
}

// The image does not depend on the thread count.
TEST(RenderView, IdenticalWithOneAndTwoThreads) {
  Scene s = floor_scene(20);
  add_box(s, {-1, 0, -4}, {1, 1.5f, -2}, 0);
  s.suns.push_back({normalize({1, 2, 0.5f}), {1, 1, 1}, 0.05f});
  s.sky = Sky{{0.2f, 0.3f, 0.6f}, {0.6f, 0.6f, 0.6f}, {0.1f, 0.1f, 0.1f}};
  RayTracer rt(s);
  Camera cam = Camera::look_at({0, 1.5f, 2}, {0, 0.5f, -3});
  cam.width = 24, cam.height = 16;
  RenderSettings rs;
  rs.ao_spp = 16, rs.gi_spp = 8;
  View a = render_with_1_and_2_threads(rt, cam, rs, 3);
  // A different view id gives a different noise pattern.
  View c = render_view(rt, cam, rs, 4);
  EXPECT_NE(a.channel("AO"), c.channel("AO"));
  EXPECT_EQ(a.channel("Z"), c.channel("Z"));
}

// With several lights (one picked per path vertex) and bounces, the image still does
// not depend on the thread count, bit for bit.
TEST(RenderView, IdenticalWithOneAndTwoThreadsWithManyLights) {
  Scene s = floor_scene(20);
  add_box(s, {-1, 0, -4}, {1, 1.5f, -2}, 0);
  add_quad(s, {-3, 0, -6}, {6, 0, 0}, {0, 3, 0}, 0);
  s.suns.push_back({normalize({1, 2, 0.5f}), {1, 1, 1}, 0.02f});
  s.points.push_back({{0.5f, 2, -1}, {3, 2, 1}});
  s.points.push_back({{-2, 0.5f, -5}, {0.2f, 0.2f, 0.3f}});
  s.rects.push_back({{-1, 2.5f, -3}, {2, 0, 0}, {0, 0, 1}, {2, 2, 2}});
  s.sky = Sky{{0.2f, 0.3f, 0.6f}, {0.6f, 0.6f, 0.6f}, {0.1f, 0.1f, 0.1f}};
  RayTracer rt(s);
  Camera cam = Camera::look_at({0, 1.5f, 2}, {0, 0.5f, -3});
  cam.width = 20, cam.height = 12;
  RenderSettings rs;
  rs.ao_spp = 16, rs.gi_spp = 24, rs.light_spp = 2;
  View a = render_with_1_and_2_threads(rt, cam, rs, 5);
  double ind = 0;
  for (float v : a.channel("indirect.R")) ind += v;
  EXPECT_GT(ind, 0.0);
}

// Z is planar depth and N is in camera space, per the spec's reconstruction formula.
TEST(RenderView, DepthAndNormalFollowTheSpec) {
  Scene s = floor_scene(20);
  RayTracer rt(s);
  Camera cam = Camera::look_at({0, 2, 0}, {0, 0, -4});
  cam.width = 32, cam.height = 20, cam.fov_y_deg = 50;
  RenderSettings rs;
  rs.ao = false, rs.lighting = false;
  View v = render_view(rt, cam, rs, 0);
  float th = std::tan(50 * M_PI / 360);
  int hits = 0;
  for (int py = 0; py < cam.height; ++py)
    for (int px = 0; px < cam.width; ++px) {
      float z = v.at("Z", px, py);
      if (is_sky(z)) continue;
      ++hits;
      Vec3 pc((2 * (px + 0.5f) / cam.width - 1) * th * cam.width / cam.height * z,
              (1 - 2 * (py + 0.5f) / cam.height) * th * z, -z);
      Vec3 world = cam.eye + cam.right * pc.x + cam.up * pc.y + cam.back * pc.z;
      EXPECT_NEAR(world.y, 0.0f, 1e-3f * z) << px << "," << py;
      Vec3 n_expected = cam.to_camera({0, 1, 0});
      EXPECT_NEAR(v.at("N.Y", px, py), n_expected.y, 1e-5);
      EXPECT_NEAR(v.at("N.Z", px, py), n_expected.z, 1e-5);
      EXPECT_GT(v.at("N.Z", px, py), 0.0f);
    }
  EXPECT_GT(hits, cam.width * cam.height / 3);
  EXPECT_TRUE(std::isinf(v.at("Z", 0, 0)));  // the top-left corner sees sky
}
