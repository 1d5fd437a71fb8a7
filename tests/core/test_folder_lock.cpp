// One folder, one run (core/folder_lock.h): a second writer is refused naming the folder
// and the holder; a killed holder leaves no stale lock; a killed writer's temporaries are
// removed anywhere in the folder when the next run takes it.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/atomic_file.h"
#include "core/folder_lock.h"

using namespace nns;
namespace fs = std::filesystem;

namespace {

class FolderLockTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nns_folder_lock_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

std::string error_of(const std::string& dir) {
  try {
    FolderLock again = prepare_output_folder(dir, "train-nnao");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// Two train-nnao runs with one --out both exited 0 and interleaved one metrics.jsonl.
TEST_F(FolderLockTest, ASecondRunIsRefusedNamingTheFolderAndTheHolder) {
  {
    FolderLock lock = prepare_output_folder(dir_.string(), "train-nnao");
    ASSERT_TRUE(lock.held());
    const std::string e = error_of(dir_.string());
    EXPECT_NE(e.find("'" + dir_.string() + "'"), std::string::npos) << e;
    EXPECT_NE(e.find("pid " + std::to_string(::getpid())), std::string::npos) << e;
  }
  EXPECT_EQ(error_of(dir_.string()), "") << "released with its holder";
}

// The kernel drops the lock of a process killed with SIGKILL.
TEST_F(FolderLockTest, AKilledHolderLeavesNoStaleLock) {
  fs::create_directories(dir_);
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    FolderLock lock(dir_.string(), "child");
    (void)!::write(ready[1], "x", 1);
    ::pause();
    ::_exit(0);
  }
  char c;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  const std::string held = error_of(dir_.string());
  EXPECT_NE(held.find("pid " + std::to_string(child)), std::string::npos) << held;
  ::kill(child, SIGKILL);
  ::waitpid(child, nullptr, 0);
  EXPECT_EQ(error_of(dir_.string()), "");
  ::close(ready[0]);
  ::close(ready[1]);
}

// A killed eval-ao or render left "*.tmp.<pid>" files (previews/, a split) that no
// later run removed.
TEST_F(FolderLockTest, TakingTheFolderRemovesDeadWritersTemporariesAtAnyDepth) {
  // A pid that is surely not running: the highest, never handed out on this machine.
  const std::string dead = "999999999";
  fs::create_directories(dir_ / "previews");
  fs::create_directories(dir_ / "train" / "room-v000");
  for (const fs::path& p : {dir_ / ("results.csv.tmp." + dead), dir_ / "previews" / ("a.png.tmp." + dead),
                            dir_ / "train" / "room-v000" / ("front.exr.tmp." + dead)})
    std::ofstream(p) << "torn";
  const fs::path live = dir_ / ("b.png.tmp." + std::to_string(::getpid()));
  std::ofstream(live) << "being written";
  std::ofstream(dir_ / "keep.csv") << "a result";
  FolderLock lock = prepare_output_folder(dir_.string(), "eval-ao");
  std::vector<std::string> left;
  for (auto& e : fs::recursive_directory_iterator(dir_))
    if (e.is_regular_file()) left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  const std::vector<std::string> expected = {FolderLock::kFileName, live.filename().string(), "keep.csv"};
  EXPECT_EQ(left, expected);
}

// A command writing one file removes only that file's temporaries.
TEST_F(FolderLockTest, ASingleFilesTemporariesAreRemovedAndNothingElse) {
  fs::create_directories(dir_);
  for (const char* name : {"ao.exr.tmp.999999999", "other.exr.tmp.999999999", "ao.exr.tmp.x"})
    std::ofstream(dir_ / name) << "torn";
  EXPECT_EQ(remove_stale_temporaries_of((dir_ / "ao.exr").string()), 1);
  EXPECT_FALSE(fs::exists(dir_ / "ao.exr.tmp.999999999"));
  EXPECT_TRUE(fs::exists(dir_ / "other.exr.tmp.999999999"));
  EXPECT_TRUE(fs::exists(dir_ / "ao.exr.tmp.x"));
}

// A run that fails before it writes anything (eval-gi and eval-ao given a blob that is no
// blob) used to leave the folder it made, holding the lock file and empty subfolders.
TEST_F(FolderLockTest, AFailedRunRemovesTheEmptyFolderItMade) {
  const fs::path out = dir_ / "out";
  try {
    FolderLock lock = prepare_output_folder(out.string(), "eval-gi");
    fs::create_directories(out / "previews");
    throw std::runtime_error("bad model");
  } catch (const std::runtime_error&) {
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(fs::exists(dir_));  // only what the run made
}

TEST_F(FolderLockTest, AFailedRunKeepsWhatItWroteAndAFolderThatWasThere) {
  const fs::path wrote = dir_ / "wrote", was_there = dir_ / "was-there";
  fs::create_directories(was_there);
  for (const fs::path& out : {wrote, was_there}) {
    try {
      FolderLock lock = prepare_output_folder(out.string(), "train-gan");
      if (out == wrote) std::ofstream(out / "metrics.jsonl") << "{}\n";
      throw std::runtime_error("diverged");
    } catch (const std::runtime_error&) {
    }
  }
  EXPECT_TRUE(fs::exists(wrote / "metrics.jsonl"));
  EXPECT_TRUE(fs::is_directory(was_there));
}

TEST_F(FolderLockTest, ASuccessfulRunKeepsItsFolderEvenEmpty) {
  const fs::path out = dir_ / "out";
  { FolderLock lock = prepare_output_folder(out.string(), "eval-ao"); }
  EXPECT_TRUE(fs::is_directory(out));
}

}  // namespace
