// Runs the built `dataset-info` on small datasets with known defects and checks that
// each defect is reported with its file and channel, and the exit code.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "data/dataset.h"
#include "data/exr_io.h"
#include "report/image_write.h"
#include "tests/support/image_bytes.h"
#include "tests/support/run_command.h"

using namespace nns::data;
using namespace nns::report;
namespace fs = std::filesystem;

namespace {

const std::string kBinary = NNSHADE_BINARY_DIR "/bin/dataset-info";

using Outcome = nns::testing::CommandResult;

Outcome run(const std::string& args) { return nns::testing::run_command(kBinary + " " + args); }

// A valid NNAO view: a tilted plane facing the camera, AO in [0,1], some sky.
View nnao_view(const std::string& scene, int w = 8, int h = 6) {
  View v;
  v.width = w;
  v.height = h;
  v.fov_y_deg = 60;
  v.ao_radius = 1.0f;
  v.scene = scene;
  for (const char* c : {"Z", "N.X", "N.Y", "N.Z", "AO"}) v.add_channel(c);
  const float s = std::sqrt(0.5f);
  for (int i = 0; i < w * h; ++i) {
    v.channels["Z"][size_t(i)] = i == 0 ? INFINITY : 2.0f + 0.1f * float(i);
    v.channels["N.Y"][size_t(i)] = i == 0 ? 0 : s;
    v.channels["N.Z"][size_t(i)] = i == 0 ? 0 : s;
    v.channels["AO"][size_t(i)] = float(i % 5) / 4.0f;
  }
  return v;
}

struct Dataset {
  fs::path root;
  explicit Dataset(const std::string& name) {
    root = fs::temp_directory_path() / ("nns_test_dataset_info_" + std::to_string(getpid()) + "_" + name);
    fs::remove_all(root);
    fs::create_directories(root / "train");
    fs::create_directories(root / "test");
  }
  ~Dataset() { fs::remove_all(root); }
  std::string file(const std::string& rel) const { return (root / rel).string(); }
  void add(const std::string& rel, const View& v) {
    fs::create_directories((root / rel).parent_path());
    write_view(file(rel), v);
  }
};

bool has(const std::string& output, const std::string& needle) { return output.find(needle) != std::string::npos; }

}  // namespace

TEST(DatasetInfo, BinaryExists) { ASSERT_TRUE(fs::exists(kBinary)) << kBinary << " not built (ninja dataset-info)"; }

TEST(DatasetInfo, CleanDatasetExitsZeroWithASummary) {
  Dataset d("clean");
  d.add("train/a.exr", nnao_view("kitchen"));
  d.add("train/b.exr", nnao_view("kitchen"));
  d.add("test/c.exr", nnao_view("attic"));
  Outcome r = run("--purpose nnao " + d.root.string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "train  2 views, 0 surround frames, 1 scenes: kitchen")) << r.output;
  EXPECT_TRUE(has(r.output, "test   1 views")) << r.output;
  EXPECT_TRUE(has(r.output, "8x6 (3 files)")) << r.output;
  EXPECT_TRUE(has(r.output, "AO")) << r.output;
  EXPECT_TRUE(has(r.output, "OK: no problems found")) << r.output;
}

TEST(DatasetInfo, ReportsEachDefectWithFileAndChannel) {
  Dataset d("defects");
  d.add("train/good.exr", nnao_view("kitchen"));
  // Truncated: a valid file cut to half its size.
  d.add("train/cut.exr", nnao_view("kitchen", 64, 64));
  fs::resize_file(d.file("train/cut.exr"), fs::file_size(d.file("train/cut.exr")) / 2);
  // Not an EXR at all.
  std::ofstream(d.file("train/garbage.exr")) << "this is not an image";
  // Missing N.Z.
  View no_nz = nnao_view("kitchen");
  no_nz.channels.erase("N.Z");
  d.add("train/no_nz.exr", no_nz);
  // A NaN depth at (x=2, y=1).
  View nan_z = nnao_view("kitchen");
  nan_z.channels["Z"][1 * 8 + 2] = NAN;
  d.add("train/nan_z.exr", nan_z);
  d.add("test/t.exr", nnao_view("attic"));

  Outcome r = run("--purpose nnao " + d.root.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(has(r.output, d.file("train/cut.exr") + ": unreadable or truncated EXR")) << r.output;
  EXPECT_TRUE(has(r.output, d.file("train/garbage.exr") + ": not an OpenEXR file")) << r.output;
  EXPECT_TRUE(has(r.output, d.file("train/no_nz.exr") + ": channel 'N.Z': missing (required)")) << r.output;
  EXPECT_TRUE(has(r.output, d.file("train/nan_z.exr") + ": channel 'Z': NaN depth at 1 pixel (first at x=2, y=1)"))
      << r.output;
  EXPECT_FALSE(has(r.output, "good.exr")) << r.output;
  EXPECT_TRUE(has(r.output, "FAILED: 4 problems found")) << r.output;
}

TEST(DatasetInfo, AttributesRangesAndSplitLeaks) {
  Dataset d("attrs");
  View v = nnao_view("kitchen");
  v.ao_radius.reset();
  v.channels["AO"][3] = 1.5f;
  v.channels["N.X"][5] = 0.9f;  // |N| = 1.27 on a geometry pixel
  d.add("train/a.exr", v);
  d.add("test/b.exr", nnao_view("kitchen"));
  Outcome r = run("--purpose nnao " + d.root.string());
  EXPECT_EQ(r.code, 1) << r.output;
  std::string a = d.file("train/a.exr");
  EXPECT_TRUE(has(r.output, a + ": channel 'AO': missing header attribute 'aoRadius'")) << r.output;
  EXPECT_TRUE(has(r.output, a + ": channel 'AO': value 1.5 outside [0,1] at 1 pixel (first at x=3, y=0)")) << r.output;
  EXPECT_TRUE(has(r.output, a + ": channel 'N.X/N.Y/N.Z': non-unit normal at 1 pixel (first at x=5, y=0)")) << r.output;
  EXPECT_TRUE(has(r.output, d.file("test/b.exr") + ": scene 'kitchen' is in both train/ and test/")) << r.output;
}

TEST(DatasetInfo, PurposeDecidesRequiredChannels) {
  Dataset d("purpose");
  d.add("train/a.exr", nnao_view("kitchen"));
  d.add("test/b.exr", nnao_view("attic"));
  Outcome any = run(d.root.string());
  EXPECT_EQ(any.code, 0) << any.output;
  Outcome gi = run("--purpose gi " + d.root.string());
  EXPECT_EQ(gi.code, 1) << gi.output;
  EXPECT_TRUE(has(gi.output, d.file("train/a.exr") + ": channel 'indirect.G': missing (required for GI)")) << gi.output;
}

TEST(DatasetInfo, SurroundFrameSizeMismatchAndMissingFace) {
  Dataset d("surround");
  const char* faces[] = {"front", "back", "left", "right", "up"};  // no "down"
  for (const char* f : faces) d.add(std::string("train/f0/") + f + ".exr", nnao_view("kitchen", 4, 4));
  d.add("train/f0/left.exr", nnao_view("kitchen", 6, 6));
  d.add("test/t.exr", nnao_view("attic"));
  Outcome r = run(d.root.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(has(r.output, d.file("train/f0/down.exr") + ": surround frame misses this face")) << r.output;
  EXPECT_TRUE(has(r.output, d.file("train/f0/left.exr") + ": size 6x6 differs from " + d.file("train/f0/front.exr")))
      << r.output;
  EXPECT_TRUE(has(r.output, "1 surround frames")) << r.output;
}

TEST(DatasetInfo, MaxProblemsLimitsTheListNotTheCount) {
  Dataset d("limit");
  for (int i = 0; i < 3; ++i) {
    View v = nnao_view("kitchen");
    v.channels.erase("AO");
    d.add("train/v" + std::to_string(i) + ".exr", v);
  }
  d.add("test/t.exr", nnao_view("attic"));
  Outcome r = run("--purpose nnao --max-problems 1 " + d.root.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "... and 2 more")) << r.output;
  EXPECT_TRUE(has(r.output, "FAILED: 3 problems found")) << r.output;
}

TEST(DatasetInfo, BadUsageExitsTwo) {
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("--purpose paint /tmp").code, 2);
  EXPECT_EQ(run("--no-such-flag /tmp").code, 2);
  Outcome missing = run("/nonexistent/dataset/folder");
  EXPECT_EQ(missing.code, 2);
  EXPECT_TRUE(has(missing.output, "/nonexistent/dataset/folder: not a folder")) << missing.output;
  Outcome help = run("--help");
  EXPECT_EQ(help.code, 0);
  EXPECT_TRUE(has(help.output, "--purpose")) << help.output;
}

TEST(DatasetInfo, EmptyFolderIsAProblemNotACrash) {
  Dataset d("empty");
  Outcome r = run(d.root.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "no views found")) << r.output;
}

// A leave-families-out dataset: holdout/ is listed as a split of its own and
// metadata.txt's family lists are shown; a held-out family leaking into train/, a
// holdout/ scene of another family and a malformed metadata line are problems.
TEST(DatasetInfo, HoldoutSplitAndMetadata) {
  Dataset d("holdout");
  d.add("train/a.exr", nnao_view("room-0"));
  d.add("test/b.exr", nnao_view("room-100000"));
  d.add("holdout/c.exr", nnao_view("cave-200000"));
  d.add("holdout/d.exr", nnao_view("cave-200001"));
  auto metadata = [&](const std::string& extra) {
    std::ofstream(d.file("metadata.txt")) << "# comment\nformat: nnshade-dataset-metadata 1\npreset: nnao-v2\nseed: 7\n"
                                             "families.train: room\nfamilies.test: room\nfamilies.holdout: cave\n"
                                          << extra;
  };
  metadata("");
  Outcome r = run("--purpose nnao " + d.root.string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "(train/ + test/ + holdout/)")) << r.output;
  EXPECT_TRUE(has(r.output, "holdout 2 views, 0 surround frames, 2 scenes: cave-200000, cave-200001")) << r.output;
  EXPECT_TRUE(has(r.output, "metadata.txt: preset nnao-v2, seed 7")) << r.output;
  EXPECT_TRUE(has(r.output, "families in holdout/: cave")) << r.output;
  EXPECT_TRUE(has(r.output, "held out (leave-families-out): 1 families, only in holdout/")) << r.output;

  d.add("train/leak.exr", nnao_view("cave-3"));
  d.add("holdout/stray.exr", nnao_view("room-200000"));
  metadata("this line has no colon\n");
  r = run("--purpose nnao " + d.root.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(has(r.output, d.file("train/leak.exr") + ": scene 'cave-3' belongs to family 'cave', held out in "
                                                       "metadata.txt, but is in train/"))
      << r.output;
  EXPECT_TRUE(has(r.output, d.file("holdout/stray.exr") + ": scene 'room-200000' is in holdout/ but its family 'room'"))
      << r.output;
  EXPECT_TRUE(has(r.output, d.file("metadata.txt") + ": line 8: expected 'key: value'")) << r.output;
}

// Without metadata.txt a holdout/ folder is still a split; its scenes must not be in
// train/ or test/.
TEST(DatasetInfo, HoldoutSceneAlsoInTrainIsALeak) {
  Dataset d("holdout-leak");
  d.add("train/a.exr", nnao_view("kitchen"));
  d.add("test/b.exr", nnao_view("attic"));
  d.add("holdout/c.exr", nnao_view("kitchen"));
  Outcome r = run(d.root.string());
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_TRUE(has(r.output, d.file("holdout/c.exr") + ": scene 'kitchen' is in both holdout/ and train/")) << r.output;
}

// Many sizes (nnao-v2 varies them per view) are summarised as ranges.
TEST(DatasetInfo, ManyResolutionsAreSummarised) {
  Dataset d("sizes");
  for (int i = 0; i < 10; ++i) d.add("train/v" + std::to_string(i) + ".exr", nnao_view("kitchen", 8 + i, 6 + i / 2));
  d.add("test/t.exr", nnao_view("attic"));
  Outcome r = run(d.root.string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "resolutions: 10 sizes over 11 files, width 8-17, height 6-10")) << r.output;
}

// --contact-sheet on a rendered surround-v3 dataset: one row of three tiles per front
// view of the family asked for (albedo | shaded | indirect), the albedo tile exactly the
// file's albedo in sRGB; a family without frames is an error naming the folder.
TEST(DatasetInfo, ContactSheetDrawsTheFamilysGroundTruth) {
  const fs::path root = fs::temp_directory_path() / ("nns_test_dataset_info_" + std::to_string(getpid()) + "_sheet");
  fs::remove_all(root);
  const std::string render = NNSHADE_BINARY_DIR "/bin/render-dataset --out " + root.string() +
                             " --preset surround-v3 --families corridor,multiroom --views 4 --views-per-scene 1 "
                             "--size 8x8 --spp 2 --gi-spp 2 --test-fraction 0.01 --threads 1";
  Outcome r = nns::testing::run_command(render);
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string png = (root / "sheet.png").string();
  Outcome o = run(root.string() + " --contact-sheet " + png + " --sheet-family corridor");
  ASSERT_EQ(o.code, 0) << o.output;
  EXPECT_NE(o.output.find("contact sheet: " + png + " (2 train frames"), std::string::npos) << o.output;
  int w = 0, h = 0;
  std::vector<uint8_t> rgb = nns::testing::read_rgb8(png, &w, &h);
  const int gap = 4, F = 8;
  EXPECT_EQ(w, 2 * (3 * F + 2 * gap) + 3 * 2 * gap);
  EXPECT_EQ(h, F + 2 * gap);
  DatasetListing l = list_dataset(root.string());
  std::string first;
  for (auto& f : l.train.frames)
    if (first.empty() && scene_of(f.faces[0]).rfind("corridor-", 0) == 0) first = f.faces[0];
  ASSERT_FALSE(first.empty());
  View v = read_view(first);
  for (int y = 0; y < F; ++y)
    for (int x = 0; x < F; ++x)
      ASSERT_EQ(rgb[(size_t(gap + y) * size_t(w) + size_t(2 * gap + x)) * 3],
                srgb_encode(std::clamp(v.channel("albedo.R")[size_t(y * F + x)], 0.0f, 1.0f)))
          << x << "," << y;
  Outcome none = run(root.string() + " --contact-sheet " + png + " --sheet-family courtyard");
  EXPECT_EQ(none.code, 1) << none.output;
  EXPECT_NE(none.output.find(root.string() + ": no train view or frame with indirect.* of family 'courtyard'"),
            std::string::npos)
      << none.output;
  fs::remove_all(root);
}
