// check_view on views in memory, and the dataset listing / scene split it relies on.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <set>

#include "data/dataset.h"
#include "data/exr_io.h"
#include "data/validate.h"

using namespace nns::data;
namespace fs = std::filesystem;

namespace {

View plane_view(const std::string& scene, int w = 4, int h = 3) {
  View v;
  v.width = w;
  v.height = h;
  v.fov_y_deg = 50;
  v.scene = scene;
  v.source = "mem.exr";
  for (const char* c : {"Z", "N.X", "N.Y", "N.Z"}) v.add_channel(c);
  for (size_t i = 0; i < size_t(w * h); ++i) {
    v.channels["Z"][i] = 3;
    v.channels["N.Z"][i] = 1;
  }
  return v;
}

std::vector<std::string> problems(const View& v, Purpose p = Purpose::any, bool is_front = true) {
  ValidationReport r;
  ProblemSink sink(r, 100);
  ValidateOptions o;
  o.purpose = p;
  check_view(v, nullptr, is_front, o, sink);
  std::vector<std::string> out;
  for (auto& pr : r.problems) out.push_back(pr.str());
  return out;
}

}  // namespace

TEST(CheckView, ValidViewHasNoProblems) { EXPECT_TRUE(problems(plane_view("s")).empty()); }

TEST(CheckView, SkyMayHaveInfDepthAndZeroNormal) {
  View v = plane_view("s");
  v.channels["Z"][0] = INFINITY;
  v.channels["Z"][1] = 2e30f;
  v.channels["N.Z"][0] = 0;
  v.channels["N.Z"][1] = 0;
  EXPECT_TRUE(problems(v).empty());
  v.channels["Z"][1] = 5;  // geometry now: its zero normal is a problem
  auto p = problems(v);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0],
            "mem.exr: channel 'N.X/N.Y/N.Z': non-unit normal at 1 pixel (first at x=1, y=0), worst length 0 (tolerance "
            "0.01)");
}

TEST(CheckView, DepthMustBePositiveAndNotNaN) {
  View v = plane_view("s");
  v.channels["Z"][5] = -1;
  v.channels["Z"][6] = -INFINITY;
  auto p = problems(v);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0], "mem.exr: channel 'Z': depth <= 0 at 2 pixels (first at x=1, y=1) (sky must be +inf or >= 1e30)");
}

TEST(CheckView, RequiredChannelsFollowThePurpose) {
  View v = plane_view("s");
  EXPECT_EQ(problems(v, Purpose::nnao), std::vector<std::string>{"mem.exr: channel 'AO': missing (required for NNAO)"});
  EXPECT_EQ(problems(v, Purpose::gi).size(), 9u);                      // albedo, direct, indirect
  EXPECT_EQ(problems(v, Purpose::gi, /*is_front=*/false).size(), 6u);  // no GI target on side faces
}

TEST(CheckView, AttributesAndRanges) {
  View v = plane_view("");
  v.fov_y_deg = 0;
  v.add_channel("AO")[2] = -0.25f;
  v.add_channel("direct.R")[0] = NAN;
  v.add_channel("indirect.G")[1] = -0.5f;
  auto p = problems(v);
  std::vector<std::string> expected = {
      "mem.exr: missing header attribute 'fovY' (float, degrees)",
      "mem.exr: missing header attribute 'scene' (string)",
      "mem.exr: channel 'AO': missing header attribute 'aoRadius' (required when AO is present)",
      "mem.exr: channel 'AO': value -0.25 outside [0,1] at 1 pixel (first at x=2, y=0)",
      "mem.exr: channel 'direct.R': NaN or Inf at 1 pixel (first at x=0, y=0)",
      "mem.exr: channel 'indirect.G': warning: negative radiance -0.5 at 1 pixel (first at x=1, y=0)",
  };
  EXPECT_EQ(p, expected);
}

// import-blender --ao-radius 1e39 wrote aoRadius=inf, which dataset-info called clean.
TEST(CheckView, NonFiniteHeaderValuesAreProblems) {
  View v = plane_view("s");
  v.add_channel("AO");
  v.ao_radius = INFINITY;
  v.world_to_camera = std::array<float, 16>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  (*v.world_to_camera)[7] = NAN;
  const std::vector<std::string> expected = {
      "mem.exr: channel 'AO': header attribute 'aoRadius' is inf, expected a finite number > 0",
      "mem.exr: header attribute 'worldToCamera' holds nan, expected finite numbers"};
  EXPECT_EQ(problems(v), expected);
}

namespace {
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("nns_test_validate_" + std::to_string(getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string file(const std::string& rel) const {
    fs::create_directories((path / rel).parent_path());
    return (path / rel).string();
  }
};
}  // namespace

TEST(Dataset, ListsSortedViewsAndFramesAndSkipsPartialFiles) {
  TempDir d;
  write_view(d.file("train/b.exr"), plane_view("s"));
  write_view(d.file("train/a.exr"), plane_view("s"));
  write_view(d.file("train/a.exr.partial-99"), plane_view("s"));
  for (const char* f : kFaceNames) write_view(d.file(std::string("train/frame1/") + f + ".exr"), plane_view("s", 4, 4));
  write_view(d.file("train/frame0/front.exr"), plane_view("s", 4, 4));
  fs::create_directories(d.path / "train" / "notes");
  fs::create_directories(d.path / "test");
  DatasetListing l = list_dataset(d.path.string());
  EXPECT_FALSE(l.flat);
  EXPECT_EQ(l.train.views, (std::vector<std::string>{d.file("train/a.exr"), d.file("train/b.exr")}));
  ASSERT_EQ(l.train.frames.size(), 2u);
  EXPECT_EQ(l.train.frames[0].dir, d.file("train/frame0"));
  EXPECT_EQ(l.train.frames[0].missing.size(), 5u);
  EXPECT_TRUE(l.train.frames[1].complete());
  EXPECT_EQ(l.train.frames[1].faces[size_t(Face::up)], d.file("train/frame1/up.exr"));
  EXPECT_EQ(l.notes.size(), 1u);  // the empty "notes" folder
  EXPECT_EQ(l.test.size(), 0u);

  auto faces = read_frame(l.train.frames[1]);
  EXPECT_EQ(faces[size_t(Face::down)].source, d.file("train/frame1/down.exr"));
  EXPECT_THROW(read_frame(l.train.frames[0]), std::runtime_error);
}

TEST(Dataset, FlatDatasetSplitsByWholeScenes) {
  TempDir d;
  const char* scenes[] = {"a", "a", "b", "b", "b", "c", "c", "d", "d", "d"};
  for (int i = 0; i < 10; ++i) write_view(d.file("v" + std::to_string(i) + ".exr"), plane_view(scenes[i]));
  DatasetListing flat = list_dataset(d.path.string());
  ASSERT_TRUE(flat.flat);
  ASSERT_EQ(flat.train.views.size(), 10u);
  DatasetListing s = split_flat_by_scene(flat, 0.3);
  EXPECT_EQ(s.train.size() + s.test.size(), 10u);
  EXPECT_GE(s.test.size(), 2u);
  EXPECT_LE(s.test.size(), 6u);
  std::set<std::string> train_scenes, test_scenes;
  for (auto& v : s.train.views) train_scenes.insert(scene_of(v));
  for (auto& v : s.test.views) test_scenes.insert(scene_of(v));
  for (auto& t : test_scenes) EXPECT_EQ(train_scenes.count(t), 0u) << "scene " << t << " on both sides";
  EXPECT_FALSE(train_scenes.empty());
  // Deterministic.
  EXPECT_EQ(split_flat_by_scene(flat, 0.3).test.views, s.test.views);
}

TEST(Dataset, SingleSceneStaysInTrainWithANote) {
  TempDir d;
  for (int i = 0; i < 3; ++i) write_view(d.file("v" + std::to_string(i) + ".exr"), plane_view("only"));
  DatasetListing s = split_flat_by_scene(list_dataset(d.path.string()), 0.5);
  EXPECT_EQ(s.train.size(), 3u);
  EXPECT_EQ(s.test.size(), 0u);
  ASSERT_EQ(s.notes.size(), 1u);
  EXPECT_NE(s.notes[0].find("a single scene"), std::string::npos);
}

TEST(Dataset, NotAFolderNamesThePath) {
  try {
    list_dataset("/nonexistent/nns");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/nns: not a folder");
  }
}

// A NaN in AO or a normal must fail validation, with the file, the channel
// and the split named, also on sky pixels and also when stored as HALF.
TEST(Dataset, NonFiniteAoAndNormalsAreRefusedNamingFileChannelAndSplit) {
  TempDir d;
  auto with_ao = [](const std::string& scene) {
    View v = plane_view(scene);
    v.ao_radius = 1.0f;
    v.add_channel("AO").assign(12, 0.5f);
    return v;
  };
  write_view(d.file("train/ok.exr"), with_ao("a"));
  View nan_normal = with_ao("a");
  nan_normal.channels["Z"][4] = INFINITY;  // sky: the normal may be zero, but not NaN
  nan_normal.channels["N.Y"][4] = NAN;
  write_view(d.file("train/n.exr"), nan_normal, {.half = true});
  View nan_ao = with_ao("b");
  nan_ao.channels["AO"][7] = NAN;
  write_view(d.file("test/ao.exr"), nan_ao);
  ValidateOptions o;
  o.purpose = Purpose::nnao;
  ValidationReport r = validate_dataset(d.path.string(), o);
  EXPECT_FALSE(r.clean());
  auto has = [&](const std::string& file, const std::string& what) {
    for (auto& p : r.problems)
      if (!p.warning && p.file == file && p.str().find(what) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(has(d.file("test/ao.exr"), "channel 'AO': NaN or Inf at 1 pixel (first at x=3, y=1) in split 'test'"));
  EXPECT_TRUE(has(d.file("train/n.exr"),
                  "channel 'N.X/N.Y/N.Z': NaN or Inf normal at 1 pixel (first at x=0, y=1) in split 'train'"));
}
