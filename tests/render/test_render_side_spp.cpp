// surround-v5's speed setting: the side faces' AO / env rays (side_spp), per face size.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/thread_pool.h"
#include "data/dataset.h"
#include "data/exr_io.h"
#include "render/dataset_writer.h"
#include "render/render_view.h"
#include "render/scenes/builder.h"
#include "render/surround.h"

using namespace nns;
using namespace nns::data;
using namespace nns::render;

namespace {
// A sunlit floor and a wall standing on it, under a gradient sky.
Scene floor_and_wall() {
  Scene s;
  s.name = "floor-wall";
  const float big = 1e4f;
  uint32_t mf = s.add_material({{0.6f, 0.6f, 0.6f}, {}}), mw = s.add_material({{0.8f, 0.8f, 0.8f}, {}});
  add_quad(s, {0, 0, -big}, {big, 0, 0}, {0, 0, 2 * big}, mf);
  add_quad(s, {0, 0, -big}, {0, big, 0}, {0, 0, 2 * big}, mw);
  s.suns.push_back({normalize({1, 2, 0.3f}), {2, 1.5f, 1}, 0});
  s.sky = Sky{{0.2f, 0.5f, 2.0f}, {0.6f, 0.6f, 0.3f}, {0, 0, 0}};
  return s;
}
}  // namespace

// side_spp sets the side faces' AO and env rays (AO is a multiple of 1 / side_spp
// there) and leaves the front face alone, bit for bit.
TEST(RenderSideSpp, SideSppSetsTheSideFacesRaysOnly) {
  Scene s = floor_and_wall();
  s.ao_radius = 3;
  RayTracer rt(s);
  Camera front = Camera::look_at({1.5f, 1, 0.3f}, {0, 1, 0.3f});
  RenderSettings rs;
  rs.ao_spp = 32, rs.gi_spp = 8, rs.light_spp = 1, rs.bounces = 2;
  set_num_threads(2);
  auto plain = render_surround(rt, front, 12, rs, 7);
  rs.side_spp = 3;
  auto fewer = render_surround(rt, front, 12, rs, 7);
  for (auto& [name, plane] : plain[0].channels) EXPECT_EQ(plane, fewer[0].channel(name)) << name;
  int fractional = 0;
  for (size_t f = 1; f < 6; ++f)
    for (float ao : fewer[f].channel("AO")) {
      const float k = ao * 3;
      EXPECT_NEAR(k, std::round(k), 1e-5f) << "face " << f;
      fractional += std::fabs(ao * 32 - std::round(ao * 32)) > 1e-3f;
    }
  EXPECT_GT(fractional, 0) << "AO in thirds, not in 32nds";
  EXPECT_NE(plain[2].channel("env.B"), fewer[2].channel("env.B"));
}

// surround-v5's side rays halve per doubling of the face, never more than surround-v4's.
TEST(RenderSideSpp, SurroundV5SideRaysPerFaceSize) {
  EXPECT_EQ(surround_v5_side_spp(64), 64);
  EXPECT_EQ(surround_v5_side_spp(32), 64);
  EXPECT_EQ(surround_v5_side_spp(128), 32);
  EXPECT_EQ(surround_v5_side_spp(256), 16);
  EXPECT_EQ(surround_v5_side_spp(1024), 8);
  DatasetJob job;
  job.preset = "surround-v5";
  job.width = job.height = 128;
  job.settings.gi_spp = 256;
  apply_preset(job);
  EXPECT_EQ(job.settings.side_spp, 32);
  EXPECT_TRUE(job.vary_textures && job.vary_lighting);
  DatasetJob v4 = job;
  v4.preset = "surround-v4";
  v4.settings = RenderSettings();
  apply_preset(v4);
  EXPECT_EQ(v4.settings.side_spp, 0);
}

// surround-v5 renders surround-v4's frames: the same names, the front face bit for bit,
// the side faces' G-buffer and direct light too; only their AO and env differ (fewer
// rays at a face of 128, set small here by --side-spp); metadata.txt says so.
TEST(RenderSideSpp, SurroundV5IsSurroundV4sFramesWithFewerSideRays) {
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("nnshade-side-spp-" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  auto job = [&](const std::string& preset) {
    DatasetJob j;
    j.preset = preset;
    j.out = (root / preset).string();
    j.views = 3, j.views_per_scene = 1, j.width = j.height = 10;
    j.families = {"window-room", "cloister"};
    j.settings.ao_spp = 16, j.settings.gi_spp = 8, j.settings.light_spp = 1;
    if (preset == "surround-v5") j.settings.side_spp = 4;
    j.progress = false;
    render_dataset(j);
    return list_dataset(j.out);
  };
  DatasetListing v4 = job("surround-v4"), v5 = job("surround-v5");
  ASSERT_EQ(v4.train.frames.size(), v5.train.frames.size());
  int ao_differs = 0;
  for (size_t f = 0; f < v4.train.frames.size(); ++f)
    for (size_t face = 0; face < 6; ++face) {
      View a = read_view(v4.train.frames[f].faces[face]), b = read_view(v5.train.frames[f].faces[face]);
      EXPECT_EQ(a.scene, b.scene);
      for (auto& [name, plane] : a.channels) {
        const bool side_ray = face != 0 && (name == "AO" || name.rfind("env.", 0) == 0);
        if (!side_ray) EXPECT_EQ(plane, b.channel(name)) << name << " of face " << face;
        else if (name == "AO") ao_differs += plane != b.channel(name);
      }
    }
  EXPECT_GT(ao_differs, 0);
  std::ifstream meta(root / "surround-v5" / kMetadataFile);
  std::stringstream text;
  text << meta.rdbuf();
  EXPECT_NE(text.str().find("side-spp: 4 AO and env rays"), std::string::npos) << text.str();
  std::filesystem::remove_all(root);
}
