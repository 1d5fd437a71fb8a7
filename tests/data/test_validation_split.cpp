// The validation split is carved from the training split by whole scenes: no scene is
// on both sides, nothing is lost, and fraction 0 leaves training untouched.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>

#include "data/exr_io.h"
#include "data/validation_split.h"
#include "fixtures/synthetic_gbuffer.h"

namespace fs = std::filesystem;
using namespace nns::data;

TEST(ValidationSplit, WholeScenesMoveAndNothingIsLost) {
  fs::path d = fs::temp_directory_path() / ("nnshade_val_" + std::to_string(::getpid()));
  fs::create_directories(d);
  SplitListing train{d.string(), {}, {}};
  for (int v = 0; v < 20; ++v) {  // 5 scenes of 4 views
    auto view = nns::fixtures::synthetic_view(12, 8, v, 4);
    view.scene = "scene" + std::to_string(v % 5);
    const std::string path = (d / ("v" + std::to_string(v) + ".exr")).string();
    write_view(path, view);
    train.views.push_back(path);
  }
  auto [t, val] = hold_out_validation(train, 0.2);
  EXPECT_EQ(t.views.size() + val.views.size(), 20u);
  EXPECT_EQ(val.views.size(), 4u);  // one scene of four views: 20%
  std::set<std::string> train_scenes, val_scenes;
  for (auto& p : t.views) train_scenes.insert(scene_of(p));
  for (auto& p : val.views) val_scenes.insert(scene_of(p));
  for (auto& s : val_scenes) EXPECT_EQ(train_scenes.count(s), 0u) << s;
  auto [all, none] = hold_out_validation(train, 0);
  EXPECT_EQ(all.views, train.views);
  EXPECT_EQ(none.size(), 0u);
  fs::remove_all(d);
}
