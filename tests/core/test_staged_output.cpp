// A command's outputs appear together or not at all (core/staged_output.h): commit()
// moves every staged file into OUT, replacing an earlier run's file of that name and
// keeping its others; a run that throws first leaves OUT as it was; a killed run's stage
// is removed when the next run takes the folder.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/folder_lock.h"
#include "core/staged_output.h"

using namespace nns;
namespace fs = std::filesystem;

namespace {

class StagedOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nns_staged_output_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

std::string read(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Every regular file under `dir` but the lock file, relative, sorted.
std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> v;
  for (auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename() != FolderLock::kFileName)
      v.push_back(fs::relative(e.path(), dir).string());
  std::sort(v.begin(), v.end());
  return v;
}

// An earlier run's outputs, as an evaluation leaves them.
void earlier_run(const fs::path& out) {
  fs::create_directories(out / "previews");
  std::ofstream(out / "results.csv") << "old results";
  std::ofstream(out / "report.html") << "old report";
  std::ofstream(out / "previews" / "v0.png") << "old v0";
  std::ofstream(out / "previews" / "v9.png") << "old v9";
}

TEST_F(StagedOutputTest, CommitMovesEveryFileIntoPlaceAndKeepsTheOthers) {
  earlier_run(dir_);
  FolderLock lock = prepare_output_folder(dir_.string(), "eval-gi");
  StagedOutput stage(dir_.string());
  ASSERT_EQ(fs::path(stage.dir()).parent_path(), dir_);
  fs::create_directories(fs::path(stage.dir()) / "previews");
  fs::create_directories(fs::path(stage.dir()) / "holdout");
  std::ofstream(fs::path(stage.dir()) / "results.csv") << "new results";
  std::ofstream(fs::path(stage.dir()) / "previews" / "v0.png") << "new v0";
  std::ofstream(fs::path(stage.dir()) / "holdout" / "results.csv") << "new holdout";
  EXPECT_EQ(read(dir_ / "results.csv"), "old results") << "nothing appears before the commit";
  stage.commit();
  EXPECT_EQ(read(dir_ / "results.csv"), "new results");
  EXPECT_EQ(read(dir_ / "previews" / "v0.png"), "new v0");
  EXPECT_EQ(read(dir_ / "holdout" / "results.csv"), "new holdout");
  EXPECT_EQ(read(dir_ / "report.html"), "old report");  // a file this run did not write
  EXPECT_EQ(read(dir_ / "previews" / "v9.png"), "old v9");
  EXPECT_FALSE(fs::exists(stage.dir()));
  const std::vector<std::string> expected = {"holdout/results.csv", "previews/v0.png", "previews/v9.png", "report.html",
                                             "results.csv"};
  EXPECT_EQ(files_in(dir_), expected);
}

// An evaluation that failed after its first files (a full disk) left them beside an
// earlier run's, or alone in a new folder.
TEST_F(StagedOutputTest, ARunThatFailsBeforeTheCommitLeavesTheFolderAsItWas) {
  earlier_run(dir_ / "was-there");
  const fs::path made = dir_ / "made";
  for (const fs::path& out : {dir_ / "was-there", made}) {
    try {
      FolderLock lock = prepare_output_folder(out.string(), "eval-ao");
      StagedOutput stage(out.string());
      std::ofstream(fs::path(stage.dir()) / "results.csv") << "new results";
      throw std::runtime_error("No space left on device");
    } catch (const std::runtime_error&) {
    }
  }
  const std::vector<std::string> expected = {"previews/v0.png", "previews/v9.png", "report.html", "results.csv"};
  EXPECT_EQ(files_in(dir_ / "was-there"), expected);
  EXPECT_EQ(read(dir_ / "was-there" / "results.csv"), "old results");
  EXPECT_FALSE(fs::exists(made)) << "a folder the failed run made goes with it";
}

// SIGKILL runs no destructor: the next run that takes the folder removes the stage.
TEST_F(StagedOutputTest, AKilledRunsStageIsRemovedByTheNextRun) {
  const fs::path stage = dir_ / ".stage.tmp.999999999";  // a pid never handed out
  fs::create_directories(stage / "previews");
  std::ofstream(stage / "results.csv") << "torn";
  std::ofstream(stage / "previews" / "v0.png") << "torn";
  std::ofstream(dir_ / "results.csv") << "kept";
  FolderLock lock = prepare_output_folder(dir_.string(), "eval-gi");
  EXPECT_FALSE(fs::exists(stage));
  EXPECT_EQ(files_in(dir_), std::vector<std::string>{"results.csv"});
}

}  // namespace
