// The second-generation scene families and the mesh builder they stand on:
// interpolated vertex normals in the ray tracer, closed (crack-free) generated meshes,
// and every family rendering a non-degenerate, deterministic view.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <tuple>

#include "core/thread_pool.h"
#include "render/placement.h"
#include "render/render_view.h"
#include "render/scenes/builder.h"
#include "render/scenes/families.h"
#include "render/scenes/mesh_builder.h"

using namespace nns;
using namespace nns::data;
using namespace nns::render;

namespace {
// Every edge of a closed surface is shared by exactly two triangles. Edges are keyed
// by the bit patterns of their end positions, so meshes that duplicate seam vertices
// (bevelled boxes) count as closed only if the duplicates are bit-identical.
int open_edges(const Scene& s, size_t first_triangle = 0) {
  using Key = std::tuple<uint32_t, uint32_t, uint32_t>;
  auto key = [&](uint32_t i) {
    Vec3 p = s.positions[i];
    uint32_t a, b, c;
    std::memcpy(&a, &p.x, 4), std::memcpy(&b, &p.y, 4), std::memcpy(&c, &p.z, 4);
    return Key{a, b, c};
  };
  std::map<std::pair<Key, Key>, int> count;
  for (size_t t = first_triangle; t < s.triangles.size(); ++t) {
    const auto& v = s.triangles[t].v;
    for (int e = 0; e < 3; ++e) {
      Key a = key(v[size_t(e)]), b = key(v[size_t((e + 1) % 3)]);
      if (a == b) continue;  // a degenerate edge (collapsed vertex)
      count[std::minmax(a, b)]++;
    }
  }
  int open = 0;
  for (auto& [e, n] : count) open += n != 2;
  return open;
}

Scene one_material() {
  Scene s;
  s.name = "test";
  s.add_material({});
  return s;
}
}  // namespace

TEST(MeshBuilder, GeneratedMeshesAreClosed) {
  Scene s = one_material();
  add_sphere(s, {0, 0, 0}, 1, 24, 0, true);
  EXPECT_EQ(open_edges(s), 0) << "sphere";
  s = one_material();
  add_torus(s, {0, 0, 0}, {0.3f, 1, 0.2f}, 1, 0.3f, 32, 12, 0, true);
  EXPECT_EQ(open_edges(s), 0) << "torus";
  s = one_material();
  add_round_cylinder(s, {0, 0, 0}, {1, 2, 0.5f}, 0.4f, 20, 0, true);
  EXPECT_EQ(open_edges(s), 0) << "cylinder with caps";
  s = one_material();
  add_dome(s, {0, 0, 0}, 1, 32, 0, true);
  EXPECT_EQ(open_edges(s), 0) << "dome";
  s = one_material();
  add_displaced_sphere(
      s, {0, 0, 0}, {1, 0.6f, 1.2f}, 3, [](Vec3 p) { return 0.2f * fbm(5, p * 2.0f, 3); }, 0, true);
  EXPECT_EQ(open_edges(s), 0) << "displaced icosphere";
  // Seams of separately built faces: closed only because seam vertices are computed
  // bit-identically from either face, also after a rotation.
  s = one_material();
  add_bevelled_box(s, {0.3f, 1, -2}, {0.7f, 0.4f, 0.5f}, 0.12f, 0.7f, 0, true);
  EXPECT_EQ(open_edges(s), 0) << "bevelled box";
  // An open cylinder is not closed: the check can fail.
  s = one_material();
  add_round_cylinder(s, {0, 0, 0}, {0, 1, 0}, 0.4f, 20, 0, true, false);
  EXPECT_EQ(open_edges(s), 2 * 20) << "open cylinder";
}

// A rounded box seen from inside: every ray must hit it (a crack between faces would
// let some through), and from outside a ray at the centre must hit it.
TEST(MeshBuilder, BevelledBoxHasNoCracks) {
  Scene s = one_material();
  add_bevelled_box(s, {0, 0, 0}, {1, 0.5f, 0.8f}, 0.3f, 0.4f, 0, true, 4);
  RayTracer rt(s);
  Rng rng(1);
  int misses = 0;
  for (int i = 0; i < 20000; ++i) {
    Vec3 d = normalize(Vec3(float(rng.normal()), float(rng.normal()), float(rng.normal())));
    if (!rt.intersect({0.01f, 0.02f, -0.03f}, d).valid()) ++misses;
  }
  EXPECT_EQ(misses, 0);
  Hit h = rt.intersect({0, 0, 5}, {0, 0, -1});
  ASSERT_TRUE(h.valid());
  // On the flat middle of a face the interpolated normal is the face normal.
  Vec3 face(std::sin(0.4f), 0, std::cos(0.4f));
  EXPECT_GT(dot(h.normal, face), 0.9999f);
}

// Interpolated normals: on a smooth sphere the shading normal is the true sphere
// normal up to the chord error, far closer than the facet normal of a 12-sided sphere.
TEST(MeshBuilder, InterpolatedNormalsFollowTheSphere) {
  for (bool smooth : {true, false}) {
    Scene s = one_material();
    add_sphere(s, {0, 1, 0}, 1, 12, 0, smooth);
    EXPECT_EQ(s.normals.size(), smooth ? s.positions.size() : 0u);
    RayTracer rt(s);
    Rng rng(2);
    double worst = 0;
    for (int i = 0; i < 2000; ++i) {
      Vec3 o = normalize(Vec3(float(rng.normal()), float(rng.normal()), float(rng.normal()))) * 3.0f + Vec3(0, 1, 0);
      Hit h = rt.intersect(o, normalize(Vec3(0, 1, 0) - o));
      ASSERT_TRUE(h.valid());
      Vec3 truth = normalize(h.position - Vec3(0, 1, 0));
      EXPECT_NEAR(length(h.normal), 1.0f, 1e-5f);
      EXPECT_GT(dot(h.normal, truth), 0);  // facing the ray, i.e. outwards here
      worst = std::max(worst, double(std::acos(std::min(1.0f, dot(h.normal, truth)))));
    }
    // Facets of a 12-segment sphere (30-degree steps) lean up to ~20 degrees from the
    // true normal; interpolation brings that to ~6 (the error of linearly blending
    // normals 30 degrees apart, largest at the poles' fans).
    if (smooth) EXPECT_LT(worst, 0.12) << "smooth";
    else EXPECT_GT(worst, 0.2) << "flat";
  }
}

TEST(MeshBuilder, ZeroVertexNormalsKeepTrianglesFlatAndMismatchThrows) {
  Scene s = one_material();
  add_quad(s, {-1, 0, -1}, {2, 0, 0}, {0, 0, 2}, 0);  // before any smooth mesh: no normals
  add_sphere(s, {5, 1, 0}, 1, 16, 0, true);           // pads the quad's normals with zeros
  ASSERT_EQ(s.normals.size(), s.positions.size());
  EXPECT_EQ(dot(s.normals[0], s.normals[0]), 0.0f);
  // A slanted quad added after: padded when the family finishes; shaded flat.
  add_quad(s, {-1, 2, 3}, {2, 0, 0}, {0, 1, 1}, 0);
  pad_normals(s);
  RayTracer rt(s);
  Hit h = rt.intersect({0.2f, 3, 0.3f}, {0, -1, 0});
  ASSERT_TRUE(h.valid());
  EXPECT_NEAR(h.normal.y, 1.0f, 1e-6f);
  Hit slant = rt.intersect({0, 2.5f, 6}, {0, 0, -1});
  ASSERT_TRUE(slant.valid());
  EXPECT_NEAR(std::fabs(slant.normal.y), std::sqrt(0.5f), 1e-5f);
  s.normals.pop_back();
  EXPECT_THROW(RayTracer bad(s), std::runtime_error);
}

// Every second-generation family: deterministic, varied between instances, lit, with
// per-vertex normals in step with the positions, and a placed camera that is not
// inside geometry and sees occlusion. Several instances each, since a family's
// random choices (spiral or switchback, indoor or yard, smooth or flat) differ.
TEST(SceneFamiliesV2, EveryFamilyRendersANonDegenerateView) {
  auto names = scene_family_names(2);
  ASSERT_GE(names.size(), 10u);
  int smooth_scenes = 0, flat_scenes = 0;
  for (const std::string& name : names) {
    double sky_sum = 0, occluded_sum = 0;
    for (int instance = 0; instance < 3; ++instance) {
      Scene a = make_family_scene(name, instance, 3), b = make_family_scene(name, instance, 3);
      ASSERT_EQ(a.positions.size(), b.positions.size()) << a.name;
      ASSERT_EQ(std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(Vec3)), 0) << a.name;
      ASSERT_EQ(a.normals.size(), b.normals.size()) << a.name;
      ASSERT_TRUE(a.normals.empty() || a.normals.size() == a.positions.size()) << a.name;
      (a.normals.empty() ? flat_scenes : smooth_scenes)++;
      EXPECT_FALSE(a.suns.empty() && a.points.empty() && a.rects.empty()) << a.name << " has no light";
      RayTracer rt(a);
      Rng rng(9);
      Camera cam = place_camera(rt, 48, 27, 60, rng);
      ProbeResult p = probe_view(rt, cam);
      EXPECT_TRUE(acceptable(p, {})) << a.name << ": sky " << p.sky_fraction << " plane " << p.plane_fraction
                                     << " median depth " << p.median_depth << " nearest " << p.nearest;
      EXPECT_GE(p.nearest, 0.25f) << a.name << ": camera inside or against geometry";
      RenderSettings rs;
      rs.lighting = false;
      rs.ao_spp = 32;
      rs.seed = 4;
      View v = render_view(rt, cam, rs, 1);
      int sky = 0, n = 0, occluded = 0;
      double ao = 0;
      float ao_min = 1;
      for (size_t i = 0; i < v.channel("Z").size(); ++i) {
        if (is_sky(v.channel("Z")[i])) {
          ++sky;
          continue;
        }
        ao += v.channel("AO")[i], ++n;
        occluded += v.channel("AO")[i] < 0.9f;
        ao_min = std::min(ao_min, v.channel("AO")[i]);
      }
      ASSERT_GT(n, 0) << a.name << " shows no geometry";
      sky_sum += double(sky) / double(v.width * v.height);
      occluded_sum += double(occluded) / n;
      EXPECT_LT(ao_min, 0.8f) << a.name << ": nothing occluded anywhere";
      std::printf("%-14s %6zu triangles, %-12s normals, sky %2.0f%%, mean AO %.3f, AO < 0.9 on %2.0f%%\n",
                  a.name.c_str(), a.triangles.size(), a.normals.empty() ? "flat" : "interpolated",
                  100.0 * sky / double(v.width * v.height), ao / n, 100.0 * occluded / n);
    }
    EXPECT_LT(sky_sum / 3, 0.3) << name << ": mostly sky";
    // At least a tenth of the geometry visibly occluded: something to learn from.
    EXPECT_GT(occluded_sum / 3, 0.1) << name << ": little occlusion to learn from";
  }
  // Both kinds of normals occur (the per-scene draw is 3 in 4 smooth).
  EXPECT_GT(smooth_scenes, 0);
  EXPECT_GT(flat_scenes, 0);
}

// Interpolated normals do not break the renderer's thread-count invariance.
TEST(SceneFamiliesV2, SmoothSceneIdenticalWithOneAndTwoThreads) {
  Scene s;
  int instance = 0;
  do s = make_family_scene("round", instance++, 5);
  while (s.normals.empty());
  RayTracer rt(s);
  Rng rng(1);
  Camera cam = place_camera(rt, 40, 24, 70, rng);
  RenderSettings rs;
  rs.ao_spp = 16, rs.gi_spp = 4, rs.light_spp = 1, rs.seed = 3;
  set_num_threads(1);
  View one = render_view(rt, cam, rs, 7);
  set_num_threads(2);
  View two = render_view(rt, cam, rs, 7);
  for (auto& [name, plane] : one.channels) EXPECT_EQ(plane, two.channel(name)) << name;
}

// The first generation is what the nnao/gi/surround presets render by default, the
// first two what nnao-v2 and surround-v2 render; those lists must not change (their
// datasets would). Later families join a later generation.
TEST(SceneFamiliesV2, FirstTwoGenerationsAreFixed) {
  std::vector<std::string> first = {"room",  "window-room", "colonnade", "stairs",
                                    "voxel", "thin",        "floating",  "offscreen"};
  std::vector<std::string> second = {"lounge",  "clutter", "stairwell", "arcade", "vaults", "foliage",
                                     "terrain", "cave",    "round",     "pipes",  "street"};
  EXPECT_EQ(scene_family_names(1), first);
  EXPECT_EQ(scene_family_names(2), second);
  for (auto& f : scene_families()) EXPECT_TRUE(f.generation >= 1 && f.generation <= 4) << f.name;
  EXPECT_EQ(scene_families().size(),
            first.size() + second.size() + scene_family_names(3).size() + scene_family_names(4).size());
}
