// metadata.txt's per-split counts ("views.train: 3", written by render-dataset from its
// plan before the first view) against the folders: a frame or view removed (a render
// that did not finish) or one added (a copy, another render's) is an error naming the
// split and both counts; a dataset without the keys (rendered before they existed) is not.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "data/dataset.h"
#include "data/validate.h"
#include "render/dataset_writer.h"

using namespace nns::data;
using namespace nns::render;
namespace fs = std::filesystem;

namespace {
fs::path temp_root() { return fs::temp_directory_path() / ("nnshade-split-counts-" + std::to_string(::getpid())); }

fs::path temp_dir(const std::string& name) {
  fs::path d = temp_root() / name;
  fs::remove_all(d);
  return d;
}

// Each test removes its own dataset; their common folder goes when the tests end (it
// was left behind, one empty folder in /tmp per run).
struct RemoveTempRoot : ::testing::Environment {
  void TearDown() override { fs::remove_all(temp_root()); }
};
const ::testing::Environment* const kRemoveTempRoot = ::testing::AddGlobalTestEnvironment(new RemoveTempRoot);

// 3 train + 1 test (+ 2 holdout with `holdout`) frames or views of 8x8 pixels.
std::string render_small(const std::string& preset, const std::string& name, bool holdout = false) {
  DatasetJob job;
  job.preset = preset;
  job.out = temp_dir(name).string();
  job.views = holdout ? 6 : 4;
  job.views_per_scene = 1;
  job.test_fraction = holdout ? 1.0 / 6 : 0.25;
  job.width = job.height = 8;
  job.families = {"room", "floating"};
  if (holdout) {
    job.families.push_back("stairs");
    job.holdout_families = {"stairs"};
    job.holdout_fraction = 2.0 / 6;
  }
  job.settings.ao_spp = 2, job.settings.gi_spp = 2, job.settings.light_spp = 1;
  job.progress = false;
  render_dataset(job);
  return job.out;
}

std::string all_problems(const ValidationReport& r) {
  std::string s;
  for (auto& p : r.problems) s += p.str() + "\n";
  return s;
}

bool mentions(const ValidationReport& r, const std::string& text) {
  return all_problems(r).find(text) != std::string::npos;
}

std::string read_text(const fs::path& p) {
  std::stringstream ss;
  ss << std::ifstream(p).rdbuf();
  return ss.str();
}
}  // namespace

TEST(SplitCounts, RenderWritesThemAndAFinishedRenderIsClean) {
  std::string d = render_small("surround", "clean", true);
  ValidationReport r = validate_dataset(d, {});
  EXPECT_TRUE(r.clean()) << all_problems(r);
  EXPECT_EQ(r.metadata["views.train"], "3");
  EXPECT_EQ(r.metadata["views.test"], "1");
  EXPECT_EQ(r.metadata["views.holdout"], "2");
  EXPECT_EQ(r.frames["train"], 3);
  fs::remove_all(d);
}

TEST(SplitCounts, AMissingFrameIsAnErrorNamingTheSplitAndCounts) {
  std::string d = render_small("surround", "missing");
  DatasetListing l = list_dataset(d);
  ASSERT_EQ(l.train.frames.size(), 3u);
  fs::remove_all(l.train.frames[1].dir);
  ValidationReport r = validate_dataset(d, {});
  EXPECT_FALSE(r.clean());
  EXPECT_TRUE(mentions(r, "train/: 2 frames, metadata.txt says 3: 1 missing")) << all_problems(r);
  EXPECT_FALSE(mentions(r, "test/:")) << all_problems(r);
  fs::remove_all(d);
}

TEST(SplitCounts, AnExtraCopiedFrameIsAnError) {
  std::string d = render_small("surround", "extra");
  DatasetListing l = list_dataset(d);
  ASSERT_EQ(l.test.frames.size(), 1u);
  fs::copy(l.test.frames[0].dir, l.test.frames[0].dir + "-copy", fs::copy_options::recursive);
  ValidationReport r = validate_dataset(d, {});
  EXPECT_FALSE(r.clean());
  EXPECT_TRUE(mentions(r, "test/: 2 frames, metadata.txt says 1: 1 extra")) << all_problems(r);
  fs::remove_all(d);
}

TEST(SplitCounts, SingleViewsAndTheHoldoutSplitAreCountedToo) {
  std::string d = render_small("nnao", "views", true);
  DatasetListing l = list_dataset(d);
  ASSERT_EQ(l.holdout.views.size(), 2u);
  fs::remove(l.holdout.views[0]);
  ValidationReport r = validate_dataset(d, {});
  EXPECT_TRUE(mentions(r, "holdout/: 1 views, metadata.txt says 2: 1 missing")) << all_problems(r);
  fs::remove_all(d);
}

TEST(SplitCounts, OlderMetadataWithoutTheKeysIsNotAnError) {
  std::string d = render_small("surround", "older");
  const fs::path meta = fs::path(d) / kMetadataFile;
  std::string kept;
  std::istringstream in(read_text(meta));
  for (std::string line; std::getline(in, line);)
    if (line.rfind("views.", 0) != 0) kept += line + "\n";
  std::ofstream(meta) << kept;
  fs::remove_all(list_dataset(d).train.frames[0].dir);
  ValidationReport r = validate_dataset(d, {});
  EXPECT_TRUE(r.clean()) << all_problems(r);
  EXPECT_EQ(r.metadata.count("views.train"), 0u);
  fs::remove_all(d);
}

TEST(SplitCounts, AMalformedCountIsAnError) {
  std::string d = render_small("surround", "malformed");
  const fs::path meta = fs::path(d) / kMetadataFile;
  std::string text = read_text(meta);
  const size_t at = text.find("views.train: 3");
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, 14, "views.train: 3x");
  std::ofstream(meta) << text;
  ValidationReport r = validate_dataset(d, {});
  EXPECT_TRUE(mentions(r, "views.train: expected a count of views, got '3x'")) << all_problems(r);
  fs::remove_all(d);
}
