// The fourth generation of scene families (cloister, basilica) and the surround-v4
// preset that takes them with textured materials: valid scenes for many seeds,
// cameras in the covered walkable space, lit; surround-v4 is surround-v3's frames with
// textured albedo; the older presets keep the albedo they had before textures existed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "data/dataset.h"
#include "data/exr_io.h"
#include "data/validate.h"
#include "render/dataset_writer.h"
#include "render/placement.h"
#include "render/render_view.h"
#include "render/scenes/families.h"
#include "tests/render/family_checks.h"

using namespace nns;
using namespace nns::data;
using namespace nns::render;
namespace fs = std::filesystem;

namespace {
const std::vector<std::string> kFourth = {"cloister", "basilica"};

fs::path temp_root() { return fs::temp_directory_path() / ("nnshade-v4-" + std::to_string(::getpid())); }

DatasetJob small_job(const std::string& preset, const std::string& out) {
  DatasetJob j;
  j.preset = preset;
  j.out = out;
  j.views = 8;
  j.views_per_scene = 1;
  j.width = j.height = 8;
  j.settings.ao_spp = 1, j.settings.gi_spp = 1, j.settings.light_spp = 1;
  j.progress = false;
  return j;
}

// Every view (or face) file of a dataset, sorted: train/, test/, holdout/.
std::vector<std::string> view_files(const std::string& root) {
  std::vector<std::string> out;
  DatasetListing l = list_dataset(root);
  for (const SplitListing* s : {&l.train, &l.test, &l.holdout}) {
    for (auto& v : s->views) out.push_back(v);
    for (auto& f : s->frames)
      for (auto& face : f.faces) out.push_back(face);
  }
  return out;
}

}  // namespace

TEST(SceneFamiliesV4, ReachableByNameAsTheFourthGeneration) {
  EXPECT_EQ(scene_family_names(4), kFourth);
  for (const std::string& name : kFourth) {
    EXPECT_EQ(scene_family(name).generation, 4) << name;
    EXPECT_EQ(make_family_scene(name, 3, 9).name, name + "-3");
  }
}

TEST(SceneFamiliesV4, DeterministicInTheSeed) {
  for (const std::string& name : kFourth) {
    Scene a = make_family_scene(name, 0, 21), b = make_family_scene(name, 0, 21), c = make_family_scene(name, 1, 21);
    ASSERT_EQ(a.positions.size(), b.positions.size()) << name;
    EXPECT_EQ(std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(Vec3)), 0) << name;
    ASSERT_EQ(a.materials.size(), b.materials.size()) << name;
    EXPECT_EQ(std::memcmp(a.materials.data(), b.materials.data(), a.materials.size() * sizeof(Material)), 0) << name;
    EXPECT_TRUE(a.positions.size() != c.positions.size() || a.positions[7].x != c.positions[7].x) << name;
  }
}

// 20 instances of each family: geometry and light; a camera region that is a real box
// whose floor corners stand on the floor under a roof (both families are covered
// spaces: a walk, a nave); two placed cameras each clear of geometry by 25 cm, over the
// floor and under a roof; most placements meet every rule of the dataset.
TEST(SceneFamiliesV4, ValidScenesAndCamerasInsideForManySeeds) {
  for (const std::string& name : kFourth) {
    int accepted = 0, tried = 0;
    for (int instance = 0; instance < 20; ++instance) {
      Scene s = make_family_scene(name, instance, 13);
      ASSERT_GT(s.triangles.size(), 100u) << s.name;
      ASSERT_FALSE(s.suns.empty() && s.points.empty() && s.rects.empty()) << s.name << " has no light";
      const CameraRegion& cr = s.cameras;
      ASSERT_TRUE(cr.min.x < cr.max.x && cr.min.y < cr.max.y && cr.min.z < cr.max.z) << s.name << ": empty camera box";
      RayTracer rt(s);
      for (float fx : {0.0f, 1.0f})
        for (float fz : {0.0f, 1.0f}) {
          const Vec3 p(cr.min.x + fx * (cr.max.x - cr.min.x), cr.min.y, cr.min.z + fz * (cr.max.z - cr.min.z));
          Hit down = rt.intersect(p, {0, -1, 0}), up = rt.intersect(p, {0, 1, 0});
          ASSERT_TRUE(down.valid() && up.valid()) << s.name << ": camera box corner without floor or roof";
          EXPECT_LT(down.position.y, 0.2f) << s.name << ": camera box corner over something";
          EXPECT_GT(up.position.y, cr.max.y) << s.name << ": camera box reaches into the ceiling";
        }
      Rng rng(uint64_t(instance) + 50);
      for (int k = 0; k < 2; ++k, ++tried) {
        Camera cam = place_camera(rt, 32, 32, 90, rng);
        ProbeResult p = probe_view(rt, cam);
        accepted += acceptable(p, {});
        EXPECT_GE(p.nearest, 0.25f) << s.name << ": camera against or inside geometry";
        Hit down = rt.intersect(cam.eye, {0, -1, 0});
        ASSERT_TRUE(down.valid()) << s.name << ": nothing under the camera";
        EXPECT_LT(down.position.y, 1.1f) << s.name << ": camera over a wall or a pew";
        EXPECT_GT(down.position.y, -0.05f) << s.name << ": camera over a hole in the floor";
        EXPECT_TRUE(rt.intersect(cam.eye, {0, 1, 0}).valid()) << s.name << ": no roof over the camera";
      }
    }
    EXPECT_GE(accepted, tried * 4 / 5) << name << ": " << accepted << " of " << tried << " placements acceptable";
  }
}

// Lit through openings: indirect light in view, and occlusion.
TEST(SceneFamiliesV4, RenderLitViewsWithIndirectLight) {
  for (const std::string& name : kFourth) nns::testing::expect_lit_view_with_indirect_light(name);
}

// surround-v4 over generations 1-4, recorded in metadata.txt; for the same families
// and seed its frames are surround-v3's (same names, depth, normals) with textured
// albedo.
TEST(RenderDatasetV4, SurroundV4IsSurroundV3WithTexturesAndTheFourthGeneration) {
  const fs::path root = temp_root();
  fs::remove_all(root);
  DatasetJob all = small_job("surround-v4", (root / "all").string());
  all.views = 30;
  DatasetReport r = render_dataset(all);
  ValidationReport v = validate_dataset(all.out, {});
  EXPECT_TRUE(v.clean());
  EXPECT_EQ(v.metadata["preset"], "surround-v4");
  EXPECT_NE(v.metadata.count("lighting-variation"), 0u);
  EXPECT_NE(v.metadata.count("texture-variation"), 0u);
  for (const std::string& f : kFourth) {
    bool rendered = false;
    for (auto& scene : r.train_scenes) rendered |= scene.rfind(f + "-", 0) == 0;
    EXPECT_TRUE(rendered) << f << " not rendered by surround-v4";
  }

  DatasetJob v3 = small_job("surround-v3", (root / "v3").string());
  DatasetJob v4 = small_job("surround-v4", (root / "v4").string());
  v3.families = v4.families = {"room", "corridor", "cloister"};
  render_dataset(v3);
  render_dataset(v4);
  const std::vector<std::string> a = view_files(v3.out), b = view_files(v4.out);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_FALSE(a.empty());
  int albedo_differs = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(fs::path(a[i]).lexically_relative(v3.out), fs::path(b[i]).lexically_relative(v4.out));
    View x = read_view(a[i]), y = read_view(b[i]);
    EXPECT_EQ(x.channel("Z"), y.channel("Z")) << a[i] << ": the cameras moved";
    EXPECT_EQ(x.channel("N.Y"), y.channel("N.Y")) << a[i];
    albedo_differs += x.channel("albedo.G") != y.channel("albedo.G");
  }
  EXPECT_GT(albedo_differs, int(a.size()) / 2) << albedo_differs << " of " << a.size() << " faces textured";
  fs::remove_all(root);
}
