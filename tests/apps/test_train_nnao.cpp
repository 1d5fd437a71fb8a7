// train-nnao end to end on a tiny synthetic dataset: outputs exist, an interrupted and
// resumed run ends with weights bitwise equal to an uninterrupted one, and 1 vs 2
// threads give the same weights.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/blob.h"
#include "data/exr_io.h"
#include "fixtures/synthetic_gbuffer.h"
#include "tests/support/kill_and_resume.h"
#include "tests/support/run_command.h"

namespace fs = std::filesystem;

namespace {

using nns::testing::CommandResult;

CommandResult run(const std::string& args) { return nns::testing::run_app("train-nnao", args); }

std::string bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

class TrainNnao : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root = fs::temp_directory_path() / ("nnshade_train_nnao_" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root / "data" / "train");
    fs::create_directories(root / "data" / "test");
    for (int v = 0; v < 5; ++v) {  // even variants train, odd test; a scene per view
      auto view = nns::fixtures::synthetic_view(40, 28, v, 16);
      view.scene = "synthetic" + std::to_string(v);
      fs::path dir = root / "data" / (v % 2 ? "test" : "train");
      nns::data::write_view((dir / ("v" + std::to_string(v) + ".exr")).string(), view);
    }
  }
  static void TearDownTestSuite() { fs::remove_all(root); }
  static std::string common() {
    return "--data " + (root / "data").string() + " --preset grid --window 7 --points-per-view 96 --seed 5 ";
  }
  static fs::path root;
};
fs::path TrainNnao::root;

}  // namespace

TEST_F(TrainNnao, ResumeEqualsUninterruptedBitwise) {
  auto a = run(common() + "--epochs 3 --threads 2 --out " + (root / "full").string());
  ASSERT_EQ(a.code, 0) << a.output;
  EXPECT_TRUE(fs::exists(root / "full" / "nnao.blob"));
  EXPECT_TRUE(fs::exists(root / "full" / "loss.svg"));
  std::ifstream m(root / "full" / "metrics.jsonl");
  int lines = 0;
  for (std::string l; std::getline(m, l);) {
    EXPECT_NE(l.find("\"test_mse\""), std::string::npos) << l;
    ++lines;
  }
  EXPECT_EQ(lines, 3);

  auto b1 = run(common() + "--epochs 2 --threads 2 --out " + (root / "resumed").string());
  ASSERT_EQ(b1.code, 0) << b1.output;
  auto b2 = run(common() + "--epochs 3 --threads 2 --resume --out " + (root / "resumed").string());
  ASSERT_EQ(b2.code, 0) << b2.output;
  std::string full = bytes(root / "full" / "nnao.blob"), resumed = bytes(root / "resumed" / "nnao.blob");
  ASSERT_FALSE(full.empty());
  EXPECT_TRUE(full == resumed) << "resumed weights differ from the uninterrupted run";
  std::ifstream mr(root / "resumed" / "metrics.jsonl");
  int rlines = 0;
  for (std::string l; std::getline(mr, l);) ++rlines;
  EXPECT_EQ(rlines, 3);

  // A different stop point must differ (the comparison above can fail).
  EXPECT_FALSE(bytes(root / "full" / "nnao.blob") == bytes(root / "resumed" / "checkpoint.blob"));
}

TEST_F(TrainNnao, OneAndTwoThreadsGiveTheSameWeights) {
  auto a = run(common() + "--epochs 1 --threads 1 --out " + (root / "t1").string());
  auto b = run(common() + "--epochs 1 --threads 2 --out " + (root / "t2").string());
  ASSERT_EQ(a.code, 0) << a.output;
  ASSERT_EQ(b.code, 0) << b.output;
  EXPECT_TRUE(bytes(root / "t1" / "nnao.blob") == bytes(root / "t2" / "nnao.blob"));
}

TEST_F(TrainNnao, ResumeWithoutCheckpointAndBadFlagsFail) {
  auto a = run(common() + "--epochs 1 --resume --out " + (root / "nothing").string());
  EXPECT_NE(a.code, 0);
  EXPECT_NE(a.output.find("checkpoint"), std::string::npos) << a.output;
  auto b = run(common() + "--epochs x");
  EXPECT_EQ(b.code, 2);
}

TEST_F(TrainNnao, SweepTrainsTheLadderAndNamesAModel) {
  auto a = run(common() + "--sweep --sweep-epochs 1 --out " + (root / "sweep").string());
  ASSERT_EQ(a.code, 0) << a.output;
  std::ifstream csv(root / "sweep" / "sweep" / "sweep.csv");
  int rows = 0;
  for (std::string l; std::getline(csv, l);) ++rows;
  EXPECT_EQ(rows, 1 + 12);  // header + w {7,15,23,31} x hidden {4,8,16}
  std::string md = bytes(root / "sweep" / "sweep" / "sweep.md");
  EXPECT_NE(md.find("Cheapest model within 2%"), std::string::npos) << md;
  // chosen on validation scenes carved from train/, the test split only reported
  EXPECT_NE(md.find("Best validation MSE"), std::string::npos) << md;
  std::string header;
  std::getline(std::ifstream(root / "sweep" / "sweep" / "sweep.csv") >> std::ws, header);
  EXPECT_EQ(header, "w,hidden,samples,parameters,val_mse,test_mse,ms_per_frame");
  EXPECT_TRUE(fs::exists(root / "sweep" / "sweep" / "sweep.svg"));
  // The default (horizon) preset's ladder: directions {8, 16, 32} x hidden {8, 16, 32}.
  auto h = run("--data " + (root / "data").string() + " --points-per-view 32 --seed 5 --sweep --sweep-epochs 1 --out " +
               (root / "hsweep").string());
  ASSERT_EQ(h.code, 0) << h.output;
  std::ifstream hcsv(root / "hsweep" / "sweep" / "sweep.csv");
  std::string hheader;
  std::getline(hcsv, hheader);
  EXPECT_EQ(hheader, "directions,hidden,samples,parameters,val_mse,test_mse,ms_per_frame");
  int hrows = 0;
  for (std::string l; std::getline(hcsv, l);) ++hrows;
  EXPECT_EQ(hrows, 9);
  EXPECT_TRUE(fs::exists(root / "hsweep" / "sweep" / "d32_h16" / "nnao.blob"));
}

// A learning rate that diverges used to end with an all-NaN nnao.blob, "nan" in
// metrics.jsonl (invalid JSON) and exit 0: now the non-finite stop ends it, exit 3.
TEST_F(TrainNnao, DivergingLearningRateStopsWithExit3AndNoNanModel) {
  auto a = run(common() + "--epochs 3 --lr 1e6 --out " + (root / "diverge").string());
  EXPECT_EQ(a.code, 3) << a.output;
  EXPECT_NE(a.output.find("non-finite value"), std::string::npos) << a.output;
  std::ifstream m(root / "diverge" / "metrics.jsonl");
  for (std::string l; std::getline(m, l);) EXPECT_EQ(l.find("nan"), std::string::npos) << l;
  EXPECT_NE(bytes(root / "diverge" / "summary.json").find("\"finished\":false"), std::string::npos);
  if (fs::exists(root / "diverge" / "nnao.blob")) {  // only the last good epoch's model
    auto b = nns::Blob::load((root / "diverge" / "nnao.blob").string());
    for (auto& [name, t] : b.tensors()) {
      if (t.dtype != nns::DType::F32) continue;
      const float* v = reinterpret_cast<const float*>(t.bytes.data());
      for (int64_t i = 0; i < t.numel(); ++i) ASSERT_TRUE(std::isfinite(v[i])) << name;
    }
  }
}

// A NaN in a training view's AO or normals used to train an all-NaN model with exit 0.
TEST_F(TrainNnao, NanInAoOrANormalIsRefusedNamingFileAndChannel) {
  for (const char* channel : {"AO", "N.Y"}) {
    fs::path d = root / (std::string("nan_") + channel);
    fs::create_directories(d / "data" / "train");
    fs::create_directories(d / "data" / "test");
    for (int v = 0; v < 2; ++v) {
      auto view = nns::fixtures::synthetic_view(40, 28, v, 16);
      if (v == 0) view.channels[channel][300] = NAN;
      nns::data::write_view((d / "data" / (v ? "test" : "train") / ("v" + std::to_string(v) + ".exr")).string(), view);
    }
    auto a = run("--data " + (d / "data").string() + " --window 7 --points-per-view 96 --epochs 1 --out " +
                 (d / "out").string());
    EXPECT_EQ(a.code, 1) << a.output;
    EXPECT_NE(a.output.find("v0.exr"), std::string::npos) << a.output;
    EXPECT_NE(a.output.find(channel), std::string::npos) << a.output;
    EXPECT_FALSE(fs::exists(d / "out" / "nnao.blob"));
  }
}

TEST_F(TrainNnao, ResumeWithAnotherConfigurationIsRefusedNamingIt) {
  auto a = run(common() + "--epochs 1 --out " + (root / "cfg").string());
  ASSERT_EQ(a.code, 0) << a.output;
  auto b = run(common() + "--epochs 2 --lr 0.002 --resume --out " + (root / "cfg").string());
  EXPECT_EQ(b.code, 1) << b.output;
  EXPECT_NE(b.output.find("lr: was 0.001, now 0.002"), std::string::npos) << b.output;
  auto c = run(common() + "--epochs 2 --preset paper --resume --out " + (root / "cfg").string());
  EXPECT_NE(c.output.find("gamma: was 0.0001, now 0.01"), std::string::npos) << c.output;
}

// SIGKILL at random moments (steps, metrics appends, blob and checkpoint writes), then
// --resume until done: the model and the log end as in an uninterrupted run.
TEST_F(TrainNnao, KilledAtRandomMomentsAndResumedEndsBitwiseEqual) {
  const std::string full = (root / "kfull").string(), killed = (root / "killed").string();
  const std::string cmd = std::string(NNSHADE_BINARY_DIR) + "/bin/train-nnao " + common() + "--epochs 4 --out ";
  auto t0 = std::chrono::steady_clock::now();
  auto a = run(common() + "--epochs 4 --out " + full);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(a.code, 0) << a.output;
  auto st = nns::testing::kill_and_resume(cmd + killed, killed, killed + ".log", 10, 0.4 * ms, 11);
  // Delays under 0.4x an uninterrupted run: the first two kills land whatever the load
  // (each leaves over 0.6x of the work); later, shorter resumed runs may finish first.
  EXPECT_GE(st.kills, 2);
  std::printf("%d kills in %d runs\n", st.kills, st.runs);
  ASSERT_TRUE(fs::exists(killed + "/nnao.blob")) << bytes(killed + ".log");
  EXPECT_TRUE(bytes(full + "/nnao.blob") == bytes(killed + "/nnao.blob"));
  EXPECT_EQ(bytes(full + "/metrics.jsonl"), bytes(killed + "/metrics.jsonl"));
  for (auto& e : fs::directory_iterator(killed))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

// The points stream from unnamed files through the chunked shuffle (runs/ao/row_file.h).
// With chunks and buffers far smaller than the data (288 points at w 7: chunks of 16,
// buffers of 0.02 MiB = 52 rows, so 3 chunks: 6 groups per epoch) the run is the same
// for 1 and 2 threads, a resume replays it bitwise, it trains (finite test MSE that
// falls), and it differs from the global shuffle (the default buffer holds all 288
// points), so the small buffers were really used.
TEST_F(TrainNnao, SmallShuffleBuffersTrainAndAreDeterministic) {
  const std::string small = common() + "--shuffle-chunk 16 --shuffle-buffer-mb 0.02 ";
  auto a = run(small + "--epochs 3 --threads 1 --out " + (root / "s1").string());
  auto b = run(small + "--epochs 3 --threads 2 --out " + (root / "s2").string());
  auto g = run(common() + "--epochs 3 --threads 2 --out " + (root / "sglobal").string());
  ASSERT_EQ(a.code, 0) << a.output;
  ASSERT_EQ(b.code, 0) << b.output;
  ASSERT_EQ(g.code, 0) << g.output;
  EXPECT_TRUE(bytes(root / "s1" / "nnao.blob") == bytes(root / "s2" / "nnao.blob"));
  EXPECT_FALSE(bytes(root / "s2" / "nnao.blob") == bytes(root / "sglobal" / "nnao.blob"));
  EXPECT_EQ(bytes(root / "s1" / "metrics.jsonl"), bytes(root / "s2" / "metrics.jsonl"));

  auto c1 = run(small + "--epochs 1 --threads 2 --out " + (root / "sres").string());
  ASSERT_EQ(c1.code, 0) << c1.output;
  auto c2 = run(small + "--epochs 3 --threads 2 --resume --out " + (root / "sres").string());
  ASSERT_EQ(c2.code, 0) << c2.output;
  EXPECT_TRUE(bytes(root / "s2" / "nnao.blob") == bytes(root / "sres" / "nnao.blob"));
  // Another buffer size changes the order: a resume with it is refused.
  auto c3 = run(common() + "--shuffle-chunk 16 --shuffle-buffer-mb 0.04 --epochs 4 --resume --out " +
                (root / "sres").string());
  EXPECT_EQ(c3.code, 1) << c3.output;
  EXPECT_NE(c3.output.find("shuffle_buffer_rows: was 52, now 105"), std::string::npos) << c3.output;

  std::vector<double> mse;
  std::ifstream m(root / "s1" / "metrics.jsonl");
  for (std::string l; std::getline(m, l);) {
    const auto at = l.find("\"test_mse\":");
    ASSERT_NE(at, std::string::npos) << l;
    mse.push_back(std::stod(l.substr(at + 11)));
  }
  ASSERT_EQ(mse.size(), 3u);
  for (double v : mse) EXPECT_TRUE(std::isfinite(v));
  EXPECT_LT(mse.back(), mse.front());
  // No point file is left in the output folder (they never had a name there).
  for (auto& e : fs::directory_iterator(root / "s1"))
    EXPECT_EQ(e.path().filename().string().find("points"), std::string::npos) << e.path();
}

// The default preset trains a horizon-feature model (runs/ao/nnao_train_options.h): the blob
// says so, the same on 1 and 2 threads; whole families of the training split can be
// held out for validation, and a family with no view is refused by name.
TEST_F(TrainNnao, DefaultPresetIsAHorizonModelValidatedOnFamilies) {
  const std::string args = "--data " + (root / "data").string() + " --points-per-view 96 --seed 5 --epochs 2 " +
                           "--validation-families synthetic2 ";
  auto a = run(args + "--threads 1 --out " + (root / "h1").string());
  auto b = run(args + "--threads 2 --out " + (root / "h2").string());
  ASSERT_EQ(a.code, 0) << a.output;
  ASSERT_EQ(b.code, 0) << b.output;
  EXPECT_TRUE(bytes(root / "h1" / "nnao.blob") == bytes(root / "h2" / "nnao.blob"));
  auto blob = nns::Blob::load((root / "h1" / "nnao.blob").string());
  EXPECT_EQ(blob.config_string("features"), "horizon");
  EXPECT_EQ(blob.config_int("directions"), 16);
  const std::string metrics = bytes(root / "h1" / "metrics.jsonl");
  EXPECT_NE(metrics.find("\"val_mse\":"), std::string::npos) << metrics;
  auto bad = run("--data " + (root / "data").string() + " --epochs 1 --validation-families castle --out " +
                 (root / "h3").string());
  EXPECT_EQ(bad.code, 1) << bad.output;
  EXPECT_NE(bad.output.find("no training view of family 'castle'"), std::string::npos) << bad.output;
}

// --epochs 0 (points built, nothing trained) used to report "test MSE 0.00000" — a
// perfect score nothing measured; now it says so, and summary.json has null.
TEST_F(TrainNnao, ZeroEpochsReportNoTestMse) {
  auto a = run(common() + "--epochs 0 --out " + (root / "zero").string());
  ASSERT_EQ(a.code, 0) << a.output;
  EXPECT_EQ(a.output.find("test MSE 0.0"), std::string::npos) << a.output;
  EXPECT_NE(a.output.find("test MSE not measured (no epoch ran)"), std::string::npos) << a.output;
  EXPECT_NE(bytes(root / "zero" / "summary.json").find("\"test_mse\":null"), std::string::npos)
      << bytes(root / "zero" / "summary.json");
}

// --ladder trains one model per rung into OUT/<rung>/ and lists them in ladder.csv in the
// order given; a low-resolution rung's blob says so (downsample), and its points are
// taken from the downsampled frames. A rung that is not D:S:B:H:s:P is refused (exit 2).
TEST_F(TrainNnao, LadderTrainsEveryRungAndListsThem) {
  auto a = run("--data " + (root / "data").string() +
               " --points-per-view 32 --seed 5 --epochs 1 --ladder "
               "--ladder-rungs 4:4:2:4:2:1:0,8:4:2:4:1:2 --out " +
               (root / "ladder").string());
  ASSERT_EQ(a.code, 0) << a.output;
  std::ifstream csv(root / "ladder" / "ladder.csv");
  std::vector<std::string> lines;
  for (std::string l; std::getline(csv, l);) lines.push_back(l);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].rfind("rung,directions,steps,bands,hidden,downsample,blur_passes,samples_per_pixel,", 0), 0u);
  EXPECT_EQ(lines[1].rfind("d4s4h4-half-b1-n0,4,4,2,4,2,1,4,", 0), 0u) << lines[1];
  EXPECT_EQ(lines[2].rfind("d8s4h4-full-b2,8,4,2,4,1,2,32,", 0), 0u) << lines[2];
  const nns::Blob half = nns::Blob::load((root / "ladder" / "d4s4h4-half-b1-n0" / "nnao.blob").string());
  EXPECT_EQ(half.config_int("downsample"), 2);
  EXPECT_EQ(half.config_int("blur_normal_power"), 0);  // the rung's 7th field
  EXPECT_EQ(half.config_int("directions"), 4);
  const nns::Blob full = nns::Blob::load((root / "ladder" / "d8s4h4-full-b2" / "nnao.blob").string());
  EXPECT_FALSE(full.has_config("downsample"));  // full resolution: as blobs made before the key
  EXPECT_EQ(full.config_int("blur_passes"), 2);
  // Half the resolution, a quarter of the pixels: a view of 40 x 28 has 280 low pixels,
  // fewer non-sky ones than at full resolution, so fewer points per view are there to take.
  auto b = run("--data " + (root / "data").string() +
               " --points-per-view 100000 --seed 5 --epochs 0 --ladder "
               "--ladder-rungs 4:4:2:4:2:1,4:4:2:4:1:1 --out " +
               (root / "ladder2").string());
  ASSERT_EQ(b.code, 0) << b.output;
  auto summary = [&](const char* rung) { return bytes(root / "ladder2" / rung / "summary.json"); };
  auto points = [&](const std::string& s) {
    const auto at = s.find("\"train_points\":");
    return at == std::string::npos ? -1.0 : std::stod(s.substr(at + 15));
  };
  const double low = points(summary("d4s4h4-half-b1")), high = points(summary("d4s4h4-full-b1"));
  EXPECT_GT(low, 0);
  EXPECT_LE(low * 3.5, high);
  EXPECT_GE(low * 4.5, high);
  for (const char* bad : {"4:4:2:4:3:1", "4:4:2", "a:b:c:d:e:f", "4:4:2:4:2:1x", "4:4:2:4:2:1:65", "4:4:3:4:2:1",
                          "4:4:2:0:2:1", "4:4:2:4:2:17", ","}) {
    auto c = run("--data " + (root / "data").string() + " --ladder --ladder-rungs " + bad + " --out " +
                 (root / "bad").string());
    EXPECT_EQ(c.code, 2) << bad << ": " << c.output;
    EXPECT_NE(c.output.find("--ladder-rungs"), std::string::npos) << c.output;
  }
}
