// Data-parallel training under mpirun on localhost (docs/distributed.md), on tiny
// synthetic data so each run takes seconds:
//  - train-nnao and train-gan with --accumulate 3 under `mpirun -np 1`, `2` and `3` end
//    with weights, checkpoint and metrics bitwise equal to one process (no mpirun) with
//    --accumulate 3: the reduction order does not depend on the rank count. The GAN has
//    BatchNorm: each image keeps its own statistics on whichever rank computes it.
//  - a run interrupted under 2 ranks and resumed under 3 ends where the one-process run does;
//  - the point files are built sharded (view i by rank i % N);
//  - a rank that dies mid-run (SIGKILL) ends the job with a non-zero exit, no hang;
//  - an unreadable view ends the job naming the file, no hang;
//  - fewer micro-batches than ranks is refused;
//  - render-dataset under `mpirun -np 3` writes the one-process dataset byte for byte.
// Every mpirun is under `timeout`, so a hang fails the test instead of the CI job.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "core/folder_lock.h"
#include "data/exr_io.h"
#include "fixtures/synthetic_gbuffer.h"
#include "tests/support/run_command.h"
#include "tests/support/synthetic_gi_dataset.h"

namespace fs = std::filesystem;

namespace {

const std::string kBin = std::string(NNSHADE_BINARY_DIR) + "/bin/";
constexpr int kTimeout = 240;  // seconds per mpirun on a loaded 2-core machine

std::string bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// mpirun as CI runs it: as root (Open MPI refuses without the two variables), more
// ranks than cores (--oversubscribe, Open MPI only), under a timeout.
std::string mpirun(int ranks, const std::string& env = "") {
  return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " + env + " timeout -k 10 " +
         std::to_string(kTimeout) + " " NNSHADE_MPIEXEC " " NNSHADE_MPIEXEC_FLAGS " -np " + std::to_string(ranks) + " ";
}

class MpiTraining : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root = fs::temp_directory_path() / ("nnshade_mpi_" + std::to_string(::getpid()));
    fs::remove_all(root);
    for (int v = 0; v < 5; ++v) {  // train-nnao's data: even views train, odd test
      auto view = nns::fixtures::synthetic_view(40, 28, v, 16);
      view.scene = "synthetic" + std::to_string(v);
      fs::path dir = root / "ao" / (v % 2 ? "test" : "train");
      fs::create_directories(dir);
      nns::data::write_view((dir / ("v" + std::to_string(v) + ".exr")).string(), view);
    }
    nns::testing::write_dataset((root / "gi").string(), 6, 1);  // 6 frames: 2 steps of 3 per epoch
  }
  static void TearDownTestSuite() { fs::remove_all(root); }

  static std::string nnao(const std::string& out, const std::string& extra = "") {
    return kBin + "train-nnao --data " + (root / "ao").string() + " --out " + (root / out).string() +
           " --preset grid --window 7 --points-per-view 96 --test-points-per-view 32 --seed 5 --epochs 2"
           " --batch 12 --accumulate 3 --dropout 0.2 --threads 1 --bucket-mb 0.0001 " +
           extra;
  }
  static std::string gan(const std::string& out, const std::string& extra = "") {
    return kBin + "train-gan --data " + (root / "gi").string() + " --out " + (root / out).string() +
           " --size 16 --ngf 4 --ndf 4 --levels 3 --d-layers 2 --epochs 2 --sample-every 0 --no-eval --seed 3"
           " --validation-fraction 0 --accumulate 3 --threads 1 --bucket-mb 0.001 --loss gan " +
           extra;
  }
  static void expect_same(const std::string& a, const std::string& b, const std::vector<std::string>& files) {
    for (auto& f : files) {
      const std::string x = bytes(root / a / f), y = bytes(root / b / f);
      ASSERT_FALSE(x.empty()) << a << "/" << f;
      EXPECT_TRUE(x == y) << b << "/" << f << " differs from " << a << "/" << f;
    }
  }
  static inline fs::path root;
};

nns::testing::CommandResult must_run(const std::string& cmd) {
  auto r = nns::testing::run_command(cmd);
  EXPECT_EQ(r.code, 0) << cmd << "\n" << r.output;
  return r;
}

TEST_F(MpiTraining, NnaoWeightsAreBitwiseEqualForOneTwoAndThreeRanks) {
  must_run(nnao("one-process"));
  for (int n : {1, 2, 3}) {
    must_run(mpirun(n) + nnao("ranks" + std::to_string(n)));
    expect_same("one-process", "ranks" + std::to_string(n), {"nnao.blob", "checkpoint.blob", "metrics.jsonl"});
  }
  // The points were built sharded: view i by rank i % N (3 train + 2 test views; rank 0
  // of 3 builds train view 0 and test view 0), and every rank ended with the same files.
  EXPECT_NE(bytes(root / "one-process" / "summary.json").find("\"point_views_read_by_rank_0\":5"), std::string::npos);
  EXPECT_NE(bytes(root / "ranks2" / "summary.json").find("\"point_views_read_by_rank_0\":3"), std::string::npos)
      << bytes(root / "ranks2" / "summary.json");
  EXPECT_NE(bytes(root / "ranks3" / "summary.json").find("\"point_views_read_by_rank_0\":2"), std::string::npos)
      << bytes(root / "ranks3" / "summary.json");
  // The accumulation is what they agree on: one batch of 12 is another computation.
  must_run(nnao("plain", "--accumulate 1"));
  EXPECT_NE(bytes(root / "plain" / "nnao.blob"), bytes(root / "one-process" / "nnao.blob"));
}

TEST_F(MpiTraining, GanWeightsAreBitwiseEqualForOneTwoAndThreeRanksAndResumeWithAnotherCount) {
  must_run(gan("gan-one-process"));
  for (int n : {2, 3}) {
    must_run(mpirun(n) + gan("gan-ranks" + std::to_string(n)));
    expect_same("gan-one-process", "gan-ranks" + std::to_string(n), {"G.blob", "D.blob", "checkpoint.blob"});
  }
  // Interrupted under 2 ranks, resumed under 3: the rank count is not part of the state.
  must_run(mpirun(2) + gan("gan-resumed", "--debug-stop-after-epochs 1"));
  must_run(mpirun(3) + gan("gan-resumed", "--resume"));
  expect_same("gan-one-process", "gan-resumed", {"G.blob", "D.blob", "checkpoint.blob"});
}

TEST_F(MpiTraining, ADeadRankEndsTheJobWithAnErrorInsteadOfAHang) {
  const auto t0 = std::chrono::steady_clock::now();
  auto r = nns::testing::run_command(mpirun(2, "NNSHADE_TEST_KILL_RANK_AT_STEP=1:5") + nnao("dead", "--epochs 50"));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_NE(r.code, 0) << r.output;
  EXPECT_NE(r.code, 124) << "timeout: the job hung after a rank died\n" << r.output;
  EXPECT_LT(seconds, kTimeout) << r.output;
  EXPECT_NE(r.output.find("killing myself at step 5"), std::string::npos) << r.output;
}

// A view that cannot be read ends the job with its file named and no hang, both when
// every rank finds it (a corrupt EXR: the dataset check before the points) and when only
// its owner does while the other rank waits for its rows in the broadcast.
TEST_F(MpiTraining, AnUnreadableViewEndsTheJobNamingTheFileInsteadOfAHang) {
  fs::copy(root / "ao", root / "ao-corrupt", fs::copy_options::recursive);
  const fs::path corrupt = root / "ao-corrupt" / "train" / "v2.exr";
  fs::resize_file(corrupt, fs::file_size(corrupt) / 2);
  std::string corrupt_run = nnao("corrupt");
  const std::string ao = "--data " + (root / "ao").string() + " ";
  corrupt_run.replace(corrupt_run.find(ao), ao.size(), "--data " + (root / "ao-corrupt").string() + " ");
  // Train view 1 (v2.exr) belongs to rank 1 of 2: rank 0 builds view 0, then waits for view 1.
  const std::string owner_fails = mpirun(2, "NNSHADE_TEST_FAIL_POINT_VIEW=v2.exr") + nnao("owner-fails");
  for (const std::string& cmd : {mpirun(2) + corrupt_run, owner_fails}) {
    const auto t0 = std::chrono::steady_clock::now();
    auto r = nns::testing::run_command(cmd);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_NE(r.code, 0) << cmd << "\n" << r.output;
    EXPECT_NE(r.code, 124) << "timeout: the job hung\n" << r.output;
    EXPECT_LT(seconds, kTimeout) << r.output;
    EXPECT_NE(r.output.find("train/v2.exr"), std::string::npos) << cmd << "\n" << r.output;
  }
}

TEST_F(MpiTraining, FewerMicroBatchesThanRanksIsRefused) {
  for (const std::string& cmd : {nnao("few", "--accumulate 2 --batch 12"), gan("few-gan", "--accumulate 2")}) {
    auto r = nns::testing::run_command(mpirun(3) + cmd);
    EXPECT_NE(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("--accumulate must be at least the number of MPI ranks (3)"), std::string::npos)
        << r.output;
  }
}

// Every file under `dir`, relative path -> bytes; the folder lock aside (it names the
// process that held it: core/folder_lock.h).
std::map<std::string, std::string> tree(const fs::path& dir) {
  std::map<std::string, std::string> t;
  for (auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename() != nns::FolderLock::kFileName)
      t[fs::relative(e.path(), dir).string()] = bytes(e.path());
  return t;
}

TEST_F(MpiTraining, RenderDatasetOverThreeRanksIsTheOneProcessDataset) {
  // nnao-v2 varies every view's size, fov and radius and writes metadata.txt.
  const std::string args = " --preset nnao-v2 --views 7 --size 24x16 --spp 2 --seed 4 --threads 1 --out ";
  must_run(kBin + "render-dataset" + args + (root / "render-one").string());
  must_run(mpirun(3) + kBin + "render-dataset" + args + (root / "render-three").string());
  const auto one = tree(root / "render-one"), three = tree(root / "render-three");
  EXPECT_GE(one.size(), 8u);  // 7 views and the metadata
  EXPECT_EQ(one.size(), three.size());
  for (auto& [name, content] : one) {
    auto it = three.find(name);
    ASSERT_NE(it, three.end()) << name << " missing from the 3-rank dataset";
    EXPECT_TRUE(it->second == content) << name << " differs";
  }
}

}  // namespace

// With no --accumulate, mpirun -np 3 takes the rank count as its default and says so: the
// run is the one-process run with --accumulate 3 (which the bitwise tests above pin).
TEST_F(MpiTraining, DefaultAccumulateIsTheRankCount) {
  auto without_accumulate = [](std::string cmd) {
    const std::string flag = "--accumulate 3 ";
    cmd.erase(cmd.find(flag), flag.size());
    return cmd;
  };
  must_run(nnao("acc-one"));
  auto r = must_run(mpirun(3) + without_accumulate(nnao("acc-default")));
  EXPECT_NE(r.output.find("3 MPI ranks, --accumulate 3"), std::string::npos) << r.output;
  expect_same("acc-one", "acc-default", {"nnao.blob", "checkpoint.blob"});
  must_run(gan("acc-gan-one"));
  r = must_run(mpirun(3) + without_accumulate(gan("acc-gan-default")));
  EXPECT_NE(r.output.find("3 MPI ranks, --accumulate 3"), std::string::npos) << r.output;
  expect_same("acc-gan-one", "acc-gan-default", {"G.blob", "checkpoint.blob"});
}
