// render-dataset --views 6 and then --views 2 --seed 9 into one folder kept four stale
// views beside the new ones, and dataset-info called the mix clean: a folder holding
// another render's views is refused unless the user asks to replace them.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "render/dataset_writer.h"

using namespace nns::render;
namespace fs = std::filesystem;

TEST(RenderFolder, AFolderHoldingAnotherRendersViewsIsRefusedUnlessReplaced) {
  const fs::path d = fs::temp_directory_path() / ("nns_render_folder_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  EXPECT_NO_THROW(prepare_render_folder(d.string(), false)) << "an empty folder";
  std::ofstream(d / "notes.txt") << "the user's";
  EXPECT_NO_THROW(prepare_render_folder(d.string(), false)) << "no view in it";
  fs::create_directories(d / "train" / "room-p00-f000");  // a surround frame
  std::ofstream(d / "train" / "a-v000.exr") << "x";
  fs::create_directories(d / "test");
  std::ofstream(d / "test" / "b-v000.exr") << "x";
  std::ofstream(d / "metadata.txt") << "format: nnshade-dataset-metadata 1\n";
  EXPECT_EQ(rendered_views_in(d.string()), 3);
  try {
    prepare_render_folder(d.string(), false);
    ADD_FAILURE() << "a folder with views accepted";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(d.string()), std::string::npos) << m;
    EXPECT_NE(m.find("holds 3 views of another render"), std::string::npos) << m;
    EXPECT_NE(m.find("--replace"), std::string::npos) << m;
  }
  EXPECT_EQ(rendered_views_in(d.string()), 3) << "nothing removed";
  prepare_render_folder(d.string(), true);
  EXPECT_EQ(rendered_views_in(d.string()), 0);
  EXPECT_FALSE(fs::exists(d / "metadata.txt"));
  EXPECT_TRUE(fs::exists(d / "notes.txt")) << "not a view: kept";
  fs::remove_all(d);
}

// A metadata.txt of the user's own in an otherwise empty folder was overwritten by the
// render's: it is refused like a stranger in a split folder. One left by a render that
// stopped before its first view is the render's own and is written over.
TEST(RenderFolder, AMetadataFileNoRenderWroteIsRefusedUnlessReplaced) {
  const fs::path d = fs::temp_directory_path() / ("nns_render_meta_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  std::ofstream(d / "metadata.txt") << "my notes on this shoot\n";
  try {
    prepare_render_folder(d.string(), false);
    ADD_FAILURE() << "a user's metadata.txt accepted";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find((d / "metadata.txt").string()), std::string::npos) << m;
    EXPECT_NE(m.find("not a render's metadata"), std::string::npos) << m;
    EXPECT_NE(m.find("--replace"), std::string::npos) << m;
  }
  EXPECT_NO_THROW(prepare_render_folder(d.string(), true)) << "--replace: the render writes its own";
  std::ofstream(d / "metadata.txt") << "# nnshade dataset metadata\nformat: nnshade-dataset-metadata 1\n";
  EXPECT_NO_THROW(prepare_render_folder(d.string(), false)) << "a render's own, without views";
  fs::remove_all(d);
  fs::create_directories(d / "metadata.txt");  // not a file at all
  EXPECT_THROW(prepare_render_folder(d.string(), false), std::runtime_error);
  fs::remove_all(d);
}
