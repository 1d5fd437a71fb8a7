// The third generation of scene families (corridor, courtyard, multiroom) and the
// surround-v3 preset that takes them: reachable by name, deterministic, cameras inside
// the walkable space, lit, and recorded in the dataset's metadata; the floor plans
// they stand on close their walls.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "data/validate.h"
#include "render/dataset_writer.h"
#include "render/placement.h"
#include "render/render_view.h"
#include "render/scenes/families.h"
#include "tests/render/family_checks.h"
#include "render/scenes/floor_plan.h"

using namespace nns;
using namespace nns::data;
using namespace nns::render;
namespace fs = std::filesystem;

namespace {
const std::vector<std::string> kThird = {"corridor", "courtyard", "multiroom"};

bool same_bytes(const void* a, const void* b, size_t n) { return n == 0 || std::memcmp(a, b, n) == 0; }
}  // namespace

TEST(SceneFamiliesV3, ReachableByNameAsTheThirdGeneration) {
  EXPECT_EQ(scene_family_names(3), kThird);
  for (const std::string& name : kThird) {
    EXPECT_EQ(scene_family(name).generation, 3) << name;
    EXPECT_EQ(make_family_scene(name, 2, 9).name, name + "-2");
  }
}

// Same (family, instance, seed): the same geometry, materials, lights and camera
// region, bit for bit; another instance: another scene.
TEST(SceneFamiliesV3, DeterministicInTheSeed) {
  for (const std::string& name : kThird) {
    Scene a = make_family_scene(name, 0, 21), b = make_family_scene(name, 0, 21), c = make_family_scene(name, 1, 21);
    ASSERT_EQ(a.positions.size(), b.positions.size()) << name;
    EXPECT_TRUE(same_bytes(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(Vec3))) << name;
    ASSERT_EQ(a.normals.size(), b.normals.size()) << name;
    EXPECT_TRUE(same_bytes(a.normals.data(), b.normals.data(), a.normals.size() * sizeof(Vec3))) << name;
    ASSERT_EQ(a.materials.size(), b.materials.size()) << name;
    EXPECT_TRUE(same_bytes(a.materials.data(), b.materials.data(), a.materials.size() * sizeof(Material))) << name;
    ASSERT_EQ(a.points.size(), b.points.size()) << name;
    ASSERT_EQ(a.rects.size(), b.rects.size()) << name;
    EXPECT_TRUE(same_bytes(a.rects.data(), b.rects.data(), a.rects.size() * sizeof(RectLight))) << name;
    EXPECT_EQ(a.cameras.min.x, b.cameras.min.x) << name;
    EXPECT_TRUE(a.positions.size() != c.positions.size() || a.positions[7].x != c.positions[7].x) << name;
  }
}

// Cameras stand in the walkable space: placed by the dataset's rules (nothing within
// 25 cm in any axis direction, not facing a close wall, not mostly sky or one plane),
// with a floor under the eye (not a void, not the top of a wall: the lowest walls are
// 2.5 m, the tallest furniture, shrubs and fountains below 1.5 m) and, indoors, a
// ceiling over it. Several instances and several cameras each, since the
// plans differ (a T or a turn, 3 to 6 rooms, arcades or not).
TEST(SceneFamiliesV3, CamerasStandInsideTheWalkableSpace) {
  for (const std::string& name : kThird) {
    int accepted = 0, tried = 0;
    for (int instance = 0; instance < 4; ++instance) {
      Scene s = make_family_scene(name, instance, 5);
      ASSERT_FALSE(s.suns.empty() && s.points.empty() && s.rects.empty()) << s.name << " has no light";
      RayTracer rt(s);
      Rng rng(uint64_t(instance) + 100);
      for (int k = 0; k < 5; ++k, ++tried) {
        Camera cam = place_camera(rt, 32, 32, 90, rng);
        ProbeResult p = probe_view(rt, cam);
        accepted += acceptable(p, {});
        EXPECT_GE(p.nearest, 0.25f) << s.name << ": camera against or inside geometry";
        Hit down = rt.intersect(cam.eye, {0, -1, 0});
        ASSERT_TRUE(down.valid()) << s.name << ": nothing under the camera at y " << cam.eye.y;
        EXPECT_LT(down.position.y, 1.5f) << s.name << ": camera over a wall";
        EXPECT_GT(down.position.y, -0.05f) << s.name << ": camera over a hole in the floor";
        if (name != "courtyard") {
          EXPECT_TRUE(rt.intersect(cam.eye, {0, 1, 0}).valid()) << s.name << ": no roof over the camera";
        }
      }
    }
    // Placement may fall back to its best try; most views must meet every rule.
    EXPECT_GE(accepted, tried * 4 / 5) << name << ": " << accepted << " of " << tried << " placements acceptable";
  }
}

// Every family renders a lit view with light that is not all direct: there is
// indirect light to learn, and occlusion.
TEST(SceneFamiliesV3, RenderLitViewsWithIndirectLight) {
  for (const std::string& name : kThird) nns::testing::expect_lit_view_with_indirect_light(name);
}

// The plan's walls close: from inside a room of a plan with no openings every ray
// hits a wall, a floor or the roof (none escapes through a corner), and a doorway
// between two rooms lets a ray through.
TEST(FloorPlan, WallsCloseAndDoorwaysOpen) {
  FloorPlan p;
  p.thick = 0.3f, p.height = 2.5f;
  p.spaces = {{-3, -2, 0, 2}, {0, -2, 4, 2}};
  ASSERT_TRUE(shared_edge(p.spaces[0], p.spaces[1]).has_value());
  EXPECT_EQ(outer_edges(p, 0).size(), 3u);  // the shared wall is not an outside wall
  Scene closed;
  closed.name = "plan";
  uint32_t m = closed.add_material({});
  build_plan(closed, p, m, m, m);
  RayTracer rt(closed);
  Rng rng(3);
  int escaped = 0;
  for (int i = 0; i < 4000; ++i) {
    Vec3 d = normalize(Vec3(float(rng.normal()), float(rng.normal()), float(rng.normal())));
    escaped += !rt.intersect({-1.4f, 1.2f, 0.3f}, d).valid();
  }
  EXPECT_EQ(escaped, 0);
  EXPECT_LT(rt.intersect({-1, 1, 0}, {1, 0, 0}).t, 1.2f);  // the shared wall stops it
  p.holes.push_back({false, 0, {-0.5f, 0.5f, 0, 2.1f}});
  Scene open;
  open.name = "plan";
  build_plan(open, p, open.add_material({}), 0, 0);
  EXPECT_GT(RayTracer(open).intersect({-1, 1, 0}, {1, 0, 0}).t, 4.0f);  // through the door, to the far wall
  // Overlapping openings on one wall are a bug of the generator, not a plan to build.
  p.holes.push_back({false, 0, {0.2f, 0.9f, 0, 2.1f}});
  Scene bad;
  bad.add_material({});
  EXPECT_THROW(build_plan(bad, p, 0, 0, 0), std::logic_error);
}

// surround-v3: surround-v2's settings over generations 1-3; metadata.txt and
// dataset-info name the new families; surround-v2 keeps its two generations.
TEST(RenderDatasetV3, PresetTakesTheThirdGenerationAndRecordsIt) {
  const fs::path root = fs::temp_directory_path() / ("nnshade-v3-" + std::to_string(::getpid()));
  fs::remove_all(root);
  auto job = [&](const std::string& preset) {
    DatasetJob j;
    j.preset = preset;
    j.out = (root / preset).string();
    j.views = 30;
    j.views_per_scene = 1;
    j.width = j.height = 8;
    j.settings.ao_spp = 2, j.settings.gi_spp = 2, j.settings.light_spp = 1;
    j.progress = false;
    return j;
  };
  DatasetReport r = render_dataset(job("surround-v3"));
  ValidationReport v = validate_dataset((root / "surround-v3").string(), {});
  EXPECT_TRUE(v.clean());
  EXPECT_EQ(v.metadata["preset"], "surround-v3");
  EXPECT_NE(v.metadata.count("lighting-variation"), 0u);  // surround-v2's per-scene variation
  for (const std::string& f : kThird) {
    const auto& train = v.split_families["train"];
    EXPECT_NE(std::find(train.begin(), train.end(), f), train.end()) << f << " not in train/";
    bool rendered = false;
    for (auto& scene : r.train_scenes) rendered |= scene.rfind(f + "-", 0) == 0;
    EXPECT_TRUE(rendered) << f;
  }
  char* buf = nullptr;
  size_t len = 0;
  FILE* out = open_memstream(&buf, &len);
  print_report(out, v);
  std::fclose(out);
  const std::string printed(buf, len);
  std::free(buf);
  EXPECT_NE(printed.find("preset surround-v3"), std::string::npos) << printed;
  EXPECT_NE(printed.find("multiroom"), std::string::npos) << printed;

  render_dataset(job("surround-v2"));
  ValidationReport v2 = validate_dataset((root / "surround-v2").string(), {});
  for (auto& [split, fams] : v2.split_families)
    for (const std::string& f : kThird)
      EXPECT_EQ(std::find(fams.begin(), fams.end(), f), fams.end()) << f << " in " << split;
  fs::remove_all(root);
}
