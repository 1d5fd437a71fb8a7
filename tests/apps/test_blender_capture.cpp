// End to end with real Blender (Debian's `blender`, Cycles): a room the test builds
// (tests/apps/blender_room.py) goes to a dataset with the two documented commands,
//   blender -b room.blend -P tools/blender_capture.py -- capture ...
//   import-blender --out ds/train capture
// and the dataset is checked against the scene's known geometry. Skipped, saying so,
// when no `blender` is on PATH (scripts/install-deps installs it; CI runs this test).
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "data/exr_io.h"
#include "fixtures/random_nnao_blob.h"
#include "tests/support/run_command.h"

namespace fs = std::filesystem;
using nns::data::View;
using nns::testing::CommandResult;

namespace {

bool blender_on_path() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && ::access((fs::path(dir) / "blender").c_str(), X_OK) == 0) return true;
  return false;
}

const std::string kSource = NNSHADE_SOURCE_DIR;

struct Dir {
  fs::path path = fs::temp_directory_path() / ("nns_test_blender_capture_" + std::to_string(::getpid()));
  Dir() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Dir() { fs::remove_all(path); }
  std::string operator/(const std::string& s) const { return (path / s).string(); }
};

CommandResult blender(const std::string& args) {
  return nns::testing::run_command("blender -b --factory-startup " + args);
}

CommandResult capture(const std::string& blend, const std::string& args) {
  return blender(blend + " -P " + kSource + "/tools/blender_capture.py -- " + args);
}

// The room's flat surfaces (tests/apps/blender_room.py) by the way they face: those facing
// -y are the back wall (y = 2.95) or the box's front (y = 0.6); those facing +z the floor
// (z = 0) or the box's top (z = 0.8).
struct Plane {
  std::array<float, 3> normal;
  int axis;
  std::array<float, 2> at;
};
constexpr Plane kBackWall{{0, -1, 0}, 1, {2.95f, 0.6f}}, kFloor{{0, 0, 1}, 2, {0.0f, 0.8f}};

struct World {
  std::array<float, 3> position, normal;
};

// A pixel back in world space through the view's own fovY, planar Z and worldToCamera
// (a rigid matrix: its inverse is the transpose on the rotation).
World to_world(const View& v, int x, int y) {
  const auto& m = *v.world_to_camera;
  const float z = v.at("Z", x, y), t = std::tan(v.fov_y_deg * float(M_PI) / 360);
  const float c[3] = {(2 * (x + 0.5f) / float(v.width) - 1) * t * float(v.width) / float(v.height) * z,
                      (1 - 2 * (y + 0.5f) / float(v.height)) * t * z, -z};
  const float n[3] = {v.at("N.X", x, y), v.at("N.Y", x, y), v.at("N.Z", x, y)};
  World w{};
  for (int i = 0; i < 3; ++i)
    for (int r = 0; r < 3; ++r) {
      w.position[size_t(i)] += m[size_t(4 * r + i)] * (c[r] - m[size_t(4 * r + 3)]);
      w.normal[size_t(i)] += m[size_t(4 * r + i)] * n[r];
    }
  return w;
}

bool faces(const World& w, const Plane& p) {
  float d = 0;
  for (int i = 0; i < 3; ++i) d += w.normal[size_t(i)] * p.normal[size_t(i)];
  return d > 0.999f;
}

// Every pixel whose normal says "back wall" or "floor" must lie on one of its planes: checks the
// field of view, planar depth and the camera matrix that the capture note carried, and
// that normals reached camera space (else they would not rotate back onto the planes).
void expect_room_geometry(const View& v, int min_wall, int min_floor) {
  int wall = 0, floor = 0, off = 0;
  std::string first_off;
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x) {
      if (std::isinf(v.at("Z", x, y))) continue;
      const World w = to_world(v, x, y);
      for (const Plane* p : {&kBackWall, &kFloor})
        if (faces(w, *p)) {
          (p == &kBackWall ? wall : floor)++;
          const float c = w.position[size_t(p->axis)];
          if (std::abs(c - p->at[0]) > 0.01f && std::abs(c - p->at[1]) > 0.01f && off++ == 0)
            first_off = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") at " + std::to_string(c);
        }
    }
  EXPECT_GE(wall, min_wall) << v.source;
  EXPECT_GE(floor, min_floor) << v.source;
  EXPECT_EQ(off, 0) << v.source << ": pixels off their plane, first " << first_off;
}

}  // namespace

TEST(BlenderCapture, SceneToDatasetWithTwoCommands) {
  if (!blender_on_path()) GTEST_SKIP() << "no `blender` on PATH (Debian package blender, scripts/install-deps)";
  Dir d;
  CommandResult made = blender("--python " + kSource + "/tests/apps/blender_room.py -- " + (d / "room.blend"));
  ASSERT_EQ(made.code, 0) << made.output;

  // The two commands of docs/blender.md.
  CommandResult shot =
      capture(d / "room.blend",
              (d / "capture") + " --samples 32 --resolution 48x32 --ao-distance 1 --surround Front --face-size 16");
  ASSERT_EQ(shot.code, 0) << shot.output;
  CommandResult imported = nns::testing::run_app("import-blender", "--out " + (d / "ds/train") + " " + (d / "capture"));
  ASSERT_EQ(imported.code, 0) << imported.output;
  EXPECT_EQ(imported.output.find("overrides"), std::string::npos) << imported.output;

  for (const char* purpose : {"nnao", "gi"}) {
    CommandResult info = nns::testing::run_app("dataset-info", std::string("--purpose ") + purpose + " " + (d / "ds"));
    EXPECT_EQ(info.code, 0) << info.output;
  }

  // The camera came through the header note: Blender's default 50 mm lens on a 36 mm
  // sensor fits the 48 px width, so fovY = 2 atan(18/50 * 32/48).
  const View front = nns::data::read_view(d / "ds/train/Front.exr");
  EXPECT_NEAR(front.fov_y_deg, 2 * std::atan(18.0 / 50 * 32 / 48) * 180 / M_PI, 1e-3);
  EXPECT_EQ(front.scene, "room");
  ASSERT_TRUE(front.ao_radius.has_value());
  EXPECT_EQ(*front.ao_radius, 1.0f);
  ASSERT_TRUE(front.world_to_camera.has_value());
  expect_room_geometry(front, 400, 100);
  const View corner = nns::data::read_view(d / "ds/train/Corner.exr");
  expect_room_geometry(corner, 300, 100);

  // Camera space: the back wall, straight ahead of "Front", faces the camera (N.Z = 1);
  // the floor faces up (N.Y = 1). The top row is sky (above the walls; no ceiling).
  EXPECT_NEAR(front.at("N.Z", 24, 12), 1, 1e-3);
  EXPECT_NEAR(front.at("N.Y", 24, 31), 1, 1e-3);
  for (int x = 0; x < front.width; ++x) EXPECT_TRUE(std::isinf(front.at("Z", x, 0))) << x;

  // AO: 1 = unoccluded. Nothing lies within the AO distance (1) of the wall at eye height;
  // the floor where it meets the back wall is occluded. The wall row just under the sky
  // keeps its own AO: with Blender's default 1.5 px pixel filter it would be averaged with
  // the sky's 0.
  int sky_edge = 0;
  while (std::isinf(front.at("Z", 24, sky_edge))) ++sky_edge;
  EXPECT_GT(front.at("AO", 24, 12), 0.97f);
  EXPECT_GT(front.at("AO", 24, sky_edge), 0.97f) << "row " << sky_edge;
  int corner_row = front.height - 1;  // the last floor pixel below the wall, centre column
  while (front.at("N.Y", 24, corner_row - 1) > 0.99f) --corner_row;
  EXPECT_LT(front.at("AO", 24, corner_row), 0.85f) << "row " << corner_row;
  for (float a : front.channel("AO")) ASSERT_TRUE(a >= 0 && a <= 1) << a;

  // Surround frame around "Front" (eye height 1; the left wall 2.95 to the left): the
  // down face sees the floor at planar depth 1 everywhere, the left face the left wall;
  // normals in the front camera's space.
  const View down = nns::data::read_view(d / "ds/train/Front-surround/down.exr");
  EXPECT_EQ(down.fov_y_deg, 90.0f);
  for (int i = 0; i < down.width * down.height; ++i) {
    EXPECT_NEAR(down.channel("Z")[size_t(i)], 1.0f, 1e-3) << i;
    EXPECT_NEAR(down.channel("N.Y")[size_t(i)], 1.0f, 1e-3) << i;
  }
  const View left = nns::data::read_view(d / "ds/train/Front-surround/left.exr");
  EXPECT_NEAR(left.at("Z", 8, 8), 2.95f, 1e-3);
  EXPECT_NEAR(left.at("N.X", 8, 8), 1.0f, 1e-3);

  // NNAO runs on the imported views (a random model: this checks the path, not quality).
  nns::fixtures::random_nnao_blob(7, 4, 3).save(d / "m.blob");
  CommandResult eval = nns::testing::run_app(
      "eval-ao", "--data " + (d / "ds/train") + " --model " + (d / "m.blob") + " --out " + (d / "eval") +
                     " --methods NNAO,SSAO --nnao-samples 16 --previews 0 --repeat 1");
  ASSERT_EQ(eval.code, 0) << eval.output;
  std::ifstream csv(d / "eval/results.csv");
  const std::string results((std::istreambuf_iterator<char>(csv)), std::istreambuf_iterator<char>());
  EXPECT_NE(results.find("\nNNAO,"), std::string::npos) << results;
  EXPECT_EQ(results.find("nan"), std::string::npos) << results;
}

TEST(BlenderCapture, RefusesWhatItCannotCapture) {
  if (!blender_on_path()) GTEST_SKIP() << "no `blender` on PATH (Debian package blender, scripts/install-deps)";
  Dir d;
  // A scene without cameras.
  ASSERT_EQ(blender("--python-expr \"import bpy; bpy.ops.wm.read_factory_settings(use_empty=True); "
                    "bpy.ops.mesh.primitive_cube_add(); bpy.ops.wm.save_as_mainfile(filepath='" +
                    (d / "empty.blend") + "')\"")
                .code,
            0);
  CommandResult none = capture(d / "empty.blend", d / "out");
  EXPECT_EQ(none.code, 1) << none.output;
  EXPECT_NE(none.output.find("has no camera object"), std::string::npos) << none.output;
  EXPECT_FALSE(fs::exists(d / "out")) << "nothing written";

  CommandResult help = capture(d / "empty.blend", "--help");
  EXPECT_EQ(help.code, 0) << help.output;
  EXPECT_NE(help.output.find("--ao-distance"), std::string::npos) << help.output;
  CommandResult bad = capture(d / "empty.blend", (d / "out") + " --resolution 48by32");
  EXPECT_EQ(bad.code, 2) << bad.output;
  EXPECT_NE(bad.output.find("--resolution: expected WxH"), std::string::npos) << bad.output;
}
