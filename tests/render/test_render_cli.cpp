// The render-dataset command line: a tiny render succeeds and validates; bad flags
// exit 2 naming the flag; a bad scene file exits 1 naming the file.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "data/validate.h"
#include "tests/support/run_command.h"

namespace fs = std::filesystem;

namespace {
const std::string kBin = std::string(NNSHADE_BINARY_DIR) + "/bin/render-dataset";

// Runs a shell command; returns its exit code and (stdout+stderr) in `output`.
int run(const std::string& cmd, std::string& output) {
  auto r = nns::testing::run_command(cmd);
  output = r.output;
  return r.code;
}

std::string temp_dir() {
  return (fs::temp_directory_path() / ("nnshade-render-cli-" + std::to_string(::getpid()))).string();
}
}  // namespace

TEST(RenderDatasetCli, TinyRenderValidates) {
  ASSERT_TRUE(fs::exists(kBin)) << kBin << " is not built (ninja render-dataset)";
  std::string out = temp_dir(), log;
  int rc = run(kBin + " --out " + out + " --views 3 --size 16x9 --spp 4 --families room,thin --threads 1", log);
  ASSERT_EQ(rc, 0) << log;
  EXPECT_NE(log.find("2 train + 1 test views"), std::string::npos) << log;
  nns::data::ValidationReport v = nns::data::validate_dataset(out, {nns::data::Purpose::nnao});
  EXPECT_TRUE(v.clean());
  for (auto& p : v.problems) ADD_FAILURE() << p.str();
  fs::remove_all(out);
}

TEST(RenderDatasetCli, HoldoutRenderValidates) {
  ASSERT_TRUE(fs::exists(kBin)) << kBin << " is not built (ninja render-dataset)";
  std::string out = temp_dir() + "-holdout", log;
  int rc = run(kBin + " --out " + out +
                   " --preset nnao-v2 --views 4 --size 16x9 --spp 4 --families room,cave,pipes"
                   " --holdout-families cave --threads 2",
               log);
  ASSERT_EQ(rc, 0) << log;
  EXPECT_NE(log.find("2 train + 1 test + 1 holdout views"), std::string::npos) << log;
  nns::data::ValidationReport v = nns::data::validate_dataset(out, {nns::data::Purpose::nnao});
  EXPECT_TRUE(v.clean());
  for (auto& p : v.problems) ADD_FAILURE() << p.str();
  EXPECT_EQ(v.scenes["holdout"], std::set<std::string>{"cave-200000"});
  fs::remove_all(out);
}

TEST(RenderDatasetCli, BadInputIsAnErrorThatSaysWhy) {
  ASSERT_TRUE(fs::exists(kBin)) << kBin << " is not built (ninja render-dataset)";
  std::string out = temp_dir() + "-bad", log;
  EXPECT_EQ(run(kBin + " --out " + out + " --size 16by9", log), 2);
  EXPECT_NE(log.find("--size"), std::string::npos) << log;
  EXPECT_EQ(run(kBin + " --views 3", log), 2);
  EXPECT_NE(log.find("--out is required"), std::string::npos) << log;
  EXPECT_EQ(run(kBin + " --out " + out + " --preset surround --size 16x9", log), 2);
  EXPECT_NE(log.find("square"), std::string::npos) << log;
  // A job refused after the flags parse (families, holdout, scene files) is refused before
  // its folder is made: nothing is left behind, not even the lock file.
  EXPECT_EQ(run(kBin + " --out " + out + "-family --families castle --views 2 --size 16x9", log), 1);
  EXPECT_NE(log.find("unknown scene family 'castle'"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out + "-family"));
  EXPECT_EQ(run(kBin + " --out " + out + "-held --holdout-families castle --views 4 --size 16x9", log), 1);
  EXPECT_NE(log.find("--holdout-families: unknown scene family 'castle'"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out + "-held"));
  EXPECT_EQ(
      run(kBin + " --out " + out + "-all --families room,thin --holdout-families thin,room --views 4 --size 16x9", log),
      1);
  EXPECT_NE(log.find("leaving none for train/ and test/"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out + "-all"));
  EXPECT_EQ(run(kBin + " --out " + out + " --holdout-families room --holdout-fraction 1.5 --size 16x9", log), 2);
  EXPECT_NE(log.find("--holdout-fraction: 1.5 is out of range"), std::string::npos) << log;
  EXPECT_EQ(run(kBin + " --out " + out + " --holdout-families , --size 16x9", log), 2);
  EXPECT_NE(log.find("--holdout-families: no name in"), std::string::npos) << log;
  EXPECT_EQ(run(kBin + " --out " + out + "-ao --preset nnao-v2 --no-ao --views 2 --size 16x9", log), 2);
  EXPECT_NE(log.find("--no-ao: preset nnao-v2 renders AO alone"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out + "-ao"));
  EXPECT_EQ(run(kBin + " --out " + out + "-scene --scene /no/such/file.obj --views 2 --size 16x9", log), 1);
  EXPECT_NE(log.find("/no/such/file.obj"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out + "-scene"));
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(out);
}

// A scene file that is there but is no scene is found before the folder is made: a render
// that failed on it used to leave --out with metadata.txt and the lock file, a folder
// dataset-info could not read.
TEST(RenderDatasetCli, AnUnreadableSceneFileLeavesNoFolder) {
  ASSERT_TRUE(fs::exists(kBin)) << kBin << " is not built (ninja render-dataset)";
  std::string out = temp_dir() + "-badobj", bad = temp_dir() + "-bad.obj", log;
  {
    std::FILE* f = std::fopen(bad.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("this is not an OBJ\nnor is this\n", f);
    std::fclose(f);
  }
  EXPECT_EQ(run(kBin + " --out " + out + " --scene " + bad + " --views 2 --size 16x9", log), 1);
  EXPECT_NE(log.find(bad), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out));
  // A folder that was there keeps what it held and gets no metadata.txt.
  fs::create_directories(out);
  {
    std::FILE* f = std::fopen((out + "/notes.txt").c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fclose(f);
  }
  EXPECT_EQ(run(kBin + " --out " + out + " --scene " + bad + " --views 2 --size 16x9", log), 1);
  EXPECT_TRUE(fs::exists(out + "/notes.txt"));
  EXPECT_FALSE(fs::exists(out + "/metadata.txt"));
  fs::remove_all(out);
  fs::remove(bad);
}

// A render that fails part-way (here a write: the file-size limit makes the first EXR
// fail, SIGXFSZ ignored) used to leave metadata.txt and empty split folders: a dataset
// that says it has views it has not. Now it leaves nothing of its own: no folder it made,
// and in a folder that was there, what was there.
TEST(RenderDatasetCli, AFailedWriteLeavesNoHalfDataset) {
  ASSERT_TRUE(fs::exists(kBin)) << kBin << " is not built (ninja render-dataset)";
  const std::string out = temp_dir() + "-fsz", limited = "ulimit -f 40; trap '' XFSZ; ";
  const std::string job = " --preset gi --views 2 --size 64x64 --spp 4 --gi-spp 4 --threads 2";
  std::string log;
  fs::remove_all(out);
  EXPECT_EQ(run(limited + kBin + " --out " + out + job, log), 1);
  EXPECT_NE(log.find("File too large"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out));
  fs::create_directories(out);
  { std::ofstream(out + "/notes.txt") << "mine\n"; }
  EXPECT_EQ(run(limited + kBin + " --out " + out + job, log), 1);
  EXPECT_TRUE(fs::exists(out + "/notes.txt"));
  EXPECT_FALSE(fs::exists(out + "/metadata.txt"));
  EXPECT_FALSE(fs::exists(out + "/train"));
  EXPECT_FALSE(fs::exists(out + "/test"));
  fs::remove_all(out);
}

// A file of the user's own inside train/ (or test/, holdout/) would go with the split
// folder when a render fails part-way or is replaced: a render into that folder used to
// go ahead. Now it is refused naming the file, and the file stays; --replace, which says
// it removes those folders, still does.
TEST(RenderDatasetCli, AFileOfTheUsersInASplitFolderIsRefusedNotRemoved) {
  ASSERT_TRUE(fs::exists(kBin)) << kBin << " is not built (ninja render-dataset)";
  const std::string out = temp_dir() + "-mine", job = " --views 2 --size 16x9 --spp 4 --threads 1";
  std::string log;
  fs::remove_all(out);
  fs::create_directories(out + "/train");
  { std::ofstream(out + "/train/notes.txt") << "mine\n"; }
  EXPECT_EQ(run(kBin + " --out " + out + job, log), 1);
  EXPECT_NE(log.find(out + "/train/notes.txt: not a view of a render"), std::string::npos) << log;
  EXPECT_TRUE(fs::exists(out + "/train/notes.txt"));
  EXPECT_FALSE(fs::exists(out + "/metadata.txt"));
  EXPECT_EQ(run(kBin + " --out " + out + job + " --replace", log), 0) << log;
  EXPECT_FALSE(fs::exists(out + "/train/notes.txt"));
  EXPECT_TRUE(fs::exists(out + "/metadata.txt"));
  fs::remove_all(out);
}
