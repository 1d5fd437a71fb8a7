// train-gan and eval-gi, run as the user runs them, on a tiny synthetic surround
// dataset: resume is bitwise equal to an uninterrupted run; a NaN stops training
// naming the step and the tensor and keeps the last good checkpoint; eval-gi refuses a
// frame with a missing face.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/blob.h"
#include "core/kernels/gemm_precision.h"
#include "core/rng.h"
#include "data/exr_io.h"
#include "tests/support/kill_and_resume.h"
#include "tests/support/synthetic_gi_dataset.h"

namespace fs = std::filesystem;
using nns::data::View;
using nns::testing::write_dataset;

namespace {

const std::string kBin = std::string(NNSHADE_BINARY_DIR) + "/bin/";

std::string read_all(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Runs a command, returns its exit code; stdout+stderr go to `log`.
int run(const std::string& cmd, const std::string& log) {
  int rc = std::system((cmd + " > " + log + " 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

class TrainGan : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("nns_train_gan_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    write_dataset((root_ / "data").string(), 3, 2);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }

  static std::string train_cmd(const std::string& out, const std::string& extra) {
    return kBin + "train-gan --data " + (root_ / "data").string() + " --out " + out +
           " --size 16 --ngf 4 --ndf 4 --levels 3 --d-layers 2 --epochs 3 --sample-every 4 --no-eval --seed 3 " +
           "--validation-fraction 0 " + extra;  // the tiny data's 3 train frames: a validation scene would take 2
  }
  static inline fs::path root_;
};

}  // namespace

TEST_F(TrainGan, ResumeIsBitwiseEqualToAnUninterruptedRun) {
  const std::string a = (root_ / "a").string(), b = (root_ / "b").string();
  // With the discriminator, whose weights, Adam state and watch the checkpoint holds too.
  ASSERT_EQ(run(train_cmd(a, "--loss gan --threads 2"), a + ".log"), 0) << read_all(a + ".log");
  // b: interrupted after the first epoch, then resumed (with the other thread count:
  // results must not depend on it either).
  ASSERT_EQ(run(train_cmd(b, "--loss gan --threads 1 --debug-stop-after-epochs 1"), b + ".log1"), 0)
      << read_all(b + ".log1");
  ASSERT_TRUE(fs::exists(b + "/checkpoint.blob"));
  ASSERT_NE(read_all(a + "/G.blob"), read_all(b + "/G.blob"));  // b really stopped early
  ASSERT_EQ(run(train_cmd(b, "--loss gan --threads 2 --resume"), b + ".log2"), 0) << read_all(b + ".log2");
  EXPECT_NE(read_all(b + ".log2").find("resuming"), std::string::npos);
  EXPECT_EQ(read_all(a + "/G.blob"), read_all(b + "/G.blob"));
  EXPECT_EQ(read_all(a + "/D.blob").substr(0, 7), "NNSBLOB");  // the GAN loss writes D.blob too
  EXPECT_EQ(read_all(a + "/D.blob"), read_all(b + "/D.blob"));
  EXPECT_EQ(read_all(a + "/checkpoint.blob"), read_all(b + "/checkpoint.blob"));
  EXPECT_EQ(read_all(a + "/metrics.jsonl"), read_all(b + "/metrics.jsonl"));
  EXPECT_TRUE(fs::exists(a + "/samples/step4_prediction.png"));
  EXPECT_TRUE(fs::exists(a + "/summary.json"));
}

TEST_F(TrainGan, NanStopsNamingStepAndTensorAndKeepsLastGoodCheckpoint) {
  const std::string good = (root_ / "good").string(), bad = (root_ / "bad").string();
  ASSERT_EQ(run(train_cmd(good, "--debug-stop-after-epochs 1"), good + ".log"), 0) << read_all(good + ".log");
  // 3 frames per epoch: step 5 is in the second epoch, after the first checkpoint.
  int rc = run(train_cmd(bad, "--debug-poison-step 5"), bad + ".log");
  std::string log = read_all(bad + ".log");
  EXPECT_EQ(rc, 3) << log;
  // The NaN enters at pixel 0 of the input. The frame-level head averages the input, so
  // its gain, and with it the whole generator output, is NaN: the forward check names it.
  // (Without the head ReLU's max(x, 0) drops it from the forward pass, and the first place
  // it shows is the gradient of the first conv's weight.)
  EXPECT_NE(log.find("at step 5 in generator output"), std::string::npos) << log;
  const std::string no_head = (root_ / "no_head").string();
  EXPECT_EQ(run(train_cmd(no_head, "--debug-poison-step 5 --level-head 0"), no_head + ".log"), 3);
  EXPECT_NE(read_all(no_head + ".log").find("at step 5 in gradient of G.model.down.weight"), std::string::npos)
      << read_all(no_head + ".log");
  EXPECT_NE(log.find("last good checkpoint"), std::string::npos) << log;
  EXPECT_EQ(read_all(bad + "/checkpoint.blob"), read_all(good + "/checkpoint.blob"));
  EXPECT_NE(read_all(bad + "/summary.json").find("\"finished\":false"), std::string::npos);
}

TEST_F(TrainGan, EvalGiWritesResultsAndRefusesAFrameWithAMissingFace) {
  const std::string run_dir = (root_ / "ev").string();
  ASSERT_EQ(run(train_cmd(run_dir, "--epochs 1"), run_dir + ".log"), 0) << read_all(run_dir + ".log");
  const std::string out = (root_ / "ev_out").string();
  ASSERT_EQ(run(kBin + "eval-gi --data " + (root_ / "data").string() + " --model " + run_dir + "/G.blob --out " + out,
                out + ".log"),
            0)
      << read_all(out + ".log");
  std::string csv = read_all(out + "/results.csv");
  EXPECT_EQ(csv.rfind("model,mode,ms_per_frame,mse,psnr,ssim", 0), 0u) << csv;
  EXPECT_NE(csv.find("direct+env,"), std::string::npos);
  EXPECT_NE(csv.find("direct+env+ambient,"), std::string::npos);
  EXPECT_NE(csv.find(",surround,"), std::string::npos);
  EXPECT_TRUE(fs::exists(out + "/frames.csv"));
  EXPECT_TRUE(fs::exists(out + "/report.md"));
  // The detail measures come last, so scripts that cut the earlier columns still read them;
  // every row's FLIP is a number in [0, 1] and its gradient error a number >= 0.
  const std::string header = csv.substr(0, csv.find('\n'));
  const std::string tail = ",path_pairs,flip,grad_error";
  EXPECT_EQ(header.substr(header.size() - tail.size()), tail);
  std::istringstream rows(csv.substr(csv.find('\n') + 1));
  int scored = 0;
  for (std::string line; std::getline(rows, line); ++scored) {
    const size_t last = line.rfind(','), before = line.rfind(',', last - 1);
    const double flip = std::stod(line.substr(before + 1, last - before - 1)), grad = std::stod(line.substr(last + 1));
    EXPECT_TRUE(flip >= 0 && flip <= 1) << line;
    EXPECT_TRUE(grad >= 0) << line;
  }
  EXPECT_EQ(scored, 3);
  EXPECT_NE(read_all(out + "/frames.csv").find("ssim_linear,flip,grad_error\n"), std::string::npos);
  const std::string bands = read_all(out + "/results_by_distance.csv");
  EXPECT_EQ(bands.rfind("model,mode,band,pixels,share,mse,flip\n", 0), 0u) << bands;
  EXPECT_NE(bands.find("direct+env,-,0-1,"), std::string::npos) << bands;
  EXPECT_NE(bands.find(",surround,16+,"), std::string::npos) << bands;
  EXPECT_TRUE(fs::exists(out + "/speed_vs_flip.svg"));

  const std::string broken = (root_ / "broken").string();
  write_dataset(broken, 1, 1, /*drop_left=*/true);
  int rc = run(
      kBin + "eval-gi --data " + broken + " --model " + run_dir + "/G.blob --out " + (root_ / "broken_out").string(),
      broken + ".log");
  std::string log = read_all(broken + ".log");
  EXPECT_NE(rc, 0);
  EXPECT_NE(log.find("frame0"), std::string::npos) << log;
  EXPECT_NE(log.find("'left'"), std::string::npos) << log;
}

// The baselines' flags reach the blob: a Deep Shading U-Net with the linear residual and
// the DSSIM loss trains, and eval-gi rebuilds it from G.blob alone (arch, residual and
// the light cap are in its config) and scores it.
TEST_F(TrainGan, DeepShadingDssimBaselineRoundTripsThroughEvalGi) {
  const std::string run_dir = (root_ / "ds").string();
  ASSERT_EQ(run(train_cmd(run_dir, "--epochs 1 --arch deepshading --residual linear --loss dssim"), run_dir + ".log"),
            0)
      << read_all(run_dir + ".log");
  std::string blob = read_all(run_dir + "/G.blob");
  EXPECT_FALSE(fs::exists(run_dir + "/D.blob"));  // no discriminator without the GAN loss
  EXPECT_NE(blob.find("deepshading"), std::string::npos);
  EXPECT_NE(blob.find("light_max"), std::string::npos);
  const std::string out = (root_ / "ds_out").string();
  ASSERT_EQ(run(kBin + "eval-gi --data " + (root_ / "data").string() + " --model " + run_dir + "/G.blob --out " + out,
                out + ".log"),
            0)
      << read_all(out + ".log");
  std::string csv = read_all(out + "/results.csv");
  EXPECT_NE(csv.find("ds/G,surround,"), std::string::npos) << csv;
  // Every metric is a number; the flicker columns after `frames` are nan here, as the
  // synthetic frames are not camera paths (nothing to reproject).
  std::istringstream lines(csv);
  for (std::string line; std::getline(lines, line);) {
    size_t cut = 0;
    for (int commas = 0; commas < 10 && cut != std::string::npos; ++commas) cut = line.find(',', cut + 1);
    EXPECT_EQ(line.substr(0, cut).find("nan"), std::string::npos) << line;
  }

  // GAN with L1 + DSSIM + gradient reconstruction: trains, and the weights are part of
  // the checkpoint.
  const std::string mixed = (root_ / "mixed").string();
  ASSERT_EQ(run(train_cmd(mixed, "--epochs 1 --dssim-weight 1 --gradient-weight 1"), mixed + ".log"), 0)
      << read_all(mixed + ".log");
  EXPECT_NE(read_all(mixed + "/checkpoint.blob").find("dssim_weight"), std::string::npos);
  EXPECT_NE(read_all(mixed + "/checkpoint.blob").find("gradient_weight"), std::string::npos);
  EXPECT_NE(read_all(mixed + "/summary.json").find("\"finished\":true"), std::string::npos);
}

// Bad flags stop before any work with a message naming the flag, and write nothing.
TEST_F(TrainGan, BadFlagsNameTheFlagAndWriteNothing) {
  const std::string out = (root_ / "badflags").string();
  const std::pair<const char*, const char*> cases[] = {
      {"--dssim-weight nan", "--dssim-weight: expected a finite number"},
      {"--lr inf", "--lr: expected a finite number"},
      {"--dssim-weight -2", "--dssim-weight must be >= 0"},
      {"--lr 0", "--lr must be > 0"},
      {"--beta1 -0.5", "--beta1 must be >= 0"},
      {"--gradient-weight -1", "--gradient-weight"},
      {"--arch foo", "--arch: expected one of"},
      {"--g-dropout 1", "--g-dropout"},
  };
  for (auto [flags, message] : cases) {
    SCOPED_TRACE(flags);
    EXPECT_NE(run(train_cmd(out, flags), out + ".log"), 0);
    EXPECT_NE(read_all(out + ".log").find(message), std::string::npos) << read_all(out + ".log");
    EXPECT_FALSE(std::filesystem::exists(out));
  }
}

// A G.blob whose config names an unknown architecture or an impossible light cap is
// refused by eval-gi with the file named, before any frame is read.
TEST_F(TrainGan, EvalGiRefusesABlobWithABadConfig) {
  const std::string run_dir = (root_ / "cfg").string();
  ASSERT_EQ(run(train_cmd(run_dir, "--epochs 1"), run_dir + ".log"), 0) << read_all(run_dir + ".log");
  const std::pair<std::pair<const char*, const char*>, const char*> cases[] = {
      {{"arch", "bogus"}, "unknown generator architecture 'bogus'"},
      {{"residual", "sideways"}, "unknown residual mode 'sideways'"},
      {{"light_max", "nan"}, "is not a positive finite number"},
      {{"validation_fraction", "1.5"}, "validation_fraction 1.500000 is not in [0, 1)"},
  };
  for (auto [kv, message] : cases) {
    SCOPED_TRACE(kv.first);
    nns::Blob b = nns::Blob::load(run_dir + "/G.blob");
    b.set_config(kv.first, kv.second);
    const std::string bad = (root_ / (std::string("bad_") + kv.first + ".blob")).string();
    b.save(bad);
    const std::string out = (root_ / "cfg_out").string();
    EXPECT_NE(
        run(kBin + "eval-gi --data " + (root_ / "data").string() + " --model " + bad + " --out " + out, out + ".log"),
        0);
    const std::string log = read_all(out + ".log");
    EXPECT_NE(log.find(bad), std::string::npos) << log;
    EXPECT_NE(log.find(message), std::string::npos) << log;
  }
}

// train[0] on an empty list used to crash both trainers.
TEST_F(TrainGan, EmptyDataIsRefusedNotACrash) {
  const fs::path empty = root_ / "empty";
  fs::create_directories(empty);
  for (const char* app : {"train-gan", "sweep-gan"}) {
    const std::string log = (root_ / (std::string(app) + "_empty.log")).string();
    int rc = run(kBin + app + " --data " + empty.string() + " --mode front --out " + (root_ / "eo").string(), log);
    EXPECT_EQ(rc, 1) << app << ": " << read_all(log);
    EXPECT_NE(read_all(log).find(empty.string()), std::string::npos) << read_all(log);
  }
}

// The default trains the generator alone on the reconstruction term (L1 + DSSIM + the
// gradient term): no D.blob, no discriminator in the progress line, and the run's
// configuration says so.
TEST_F(TrainGan, TheDefaultTrainsTheGeneratorAloneOnTheReconstructionTerm) {
  const std::string out = (root_ / "plain").string();
  ASSERT_EQ(run(train_cmd(out, ""), out + ".log"), 0) << read_all(out + ".log");
  EXPECT_TRUE(fs::exists(out + "/G.blob"));
  EXPECT_FALSE(fs::exists(out + "/D.blob"));
  const std::string log = read_all(out + ".log");
  EXPECT_NE(log.find("train-gan l1 "), std::string::npos) << log;
  EXPECT_EQ(log.find("G_adv"), std::string::npos) << log;
  const nns::Blob ck = nns::Blob::load(out + "/checkpoint.blob");
  EXPECT_EQ(ck.config_string("loss"), "l1");
  EXPECT_DOUBLE_EQ(ck.config_double("dssim_weight"), 1);
  EXPECT_DOUBLE_EQ(ck.config_double("gradient_weight"), 1);
  // Without a discriminator, Adam's ordinary regression setting, not pix2pix's.
  EXPECT_DOUBLE_EQ(ck.config_double("lr"), 5e-4);
  EXPECT_DOUBLE_EQ(ck.config_double("beta1"), 0.9);
}

// --loss gan keeps pix2pix's Adam setting unless the flags say otherwise.
TEST_F(TrainGan, TheGanKeepsPix2pixsAdamSetting) {
  const std::string out = (root_ / "ganrates").string();
  ASSERT_EQ(run(train_cmd(out, "--loss gan"), out + ".log"), 0) << read_all(out + ".log");
  const nns::Blob ck = nns::Blob::load(out + "/checkpoint.blob");
  EXPECT_DOUBLE_EQ(ck.config_double("lr"), 2e-4);
  EXPECT_DOUBLE_EQ(ck.config_double("beta1"), 0.5);
  const std::string set = (root_ / "ganrates_set").string();
  ASSERT_EQ(run(train_cmd(set, "--loss gan --lr 0.001 --beta1 0.8"), set + ".log"), 0);
  const nns::Blob ck2 = nns::Blob::load(set + "/checkpoint.blob");
  EXPECT_DOUBLE_EQ(ck2.config_double("lr"), 1e-3);
  EXPECT_DOUBLE_EQ(ck2.config_double("beta1"), 0.8);
}

// train-gan --resume with nothing to resume used to start from scratch with exit 0.
TEST_F(TrainGan, ResumeWithoutACheckpointIsRefused) {
  const std::string out = (root_ / "nock").string();
  int rc = run(train_cmd(out, "--resume"), out + ".log");
  EXPECT_EQ(rc, 1) << read_all(out + ".log");
  EXPECT_NE(read_all(out + ".log").find("no checkpoint"), std::string::npos) << read_all(out + ".log");
}

TEST_F(TrainGan, ResumeWithAnotherLambdaIsRefusedNamingIt) {
  const std::string out = (root_ / "lam").string();
  ASSERT_EQ(run(train_cmd(out, "--debug-stop-after-epochs 1"), out + ".log"), 0) << read_all(out + ".log");
  int rc = run(train_cmd(out, "--resume --lambda 50"), out + ".log2");
  EXPECT_EQ(rc, 1) << read_all(out + ".log2");
  EXPECT_NE(read_all(out + ".log2").find("lambda: was 100, now 50"), std::string::npos) << read_all(out + ".log2");
}

// Killed between writing checkpoint.blob and G.blob on the last epoch, a run used to
// resume as "all epochs done" and leave G.blob one epoch old for ever.
TEST_F(TrainGan, ResumeOfAFinishedRunRewritesAStaleGenerator) {
  const std::string full = (root_ / "fin").string(), old = (root_ / "fin_old").string();
  ASSERT_EQ(run(train_cmd(full, ""), full + ".log"), 0) << read_all(full + ".log");
  ASSERT_EQ(run(train_cmd(old, "--debug-stop-after-epochs 2"), old + ".log"), 0);
  const std::string good = read_all(full + "/G.blob");
  ASSERT_NE(good, read_all(old + "/G.blob"));
  fs::copy_file(old + "/G.blob", full + "/G.blob", fs::copy_options::overwrite_existing);
  ASSERT_EQ(run(train_cmd(full, "--resume"), full + ".log2"), 0) << read_all(full + ".log2");
  EXPECT_EQ(read_all(full + "/G.blob"), good);
}

// A bad file only in test/ used to be found after the whole training run.
TEST_F(TrainGan, ABadFileInTheTestSplitIsFoundBeforeTheFirstStep) {
  const fs::path data = root_ / "badtest";
  fs::remove_all(data);
  write_dataset(data.string(), 2, 1);
  std::ofstream(data / "test" / "frame0" / "back.exr", std::ios::trunc) << "not an EXR";
  const std::string out = (root_ / "badtest_out").string();
  int rc = std::system((kBin + "train-gan --data " + data.string() + " --out " + out +
                        " --size 16 --ngf 4 --ndf 4 --levels 3 --d-layers 2 --epochs 2 > " + out + ".log 2>&1")
                           .c_str());
  EXPECT_NE(rc, 0);
  EXPECT_NE(read_all(out + ".log").find("back.exr"), std::string::npos) << read_all(out + ".log");
  EXPECT_FALSE(fs::exists(out + "/checkpoint.blob"));
}

// SIGKILL at random moments, then --resume until done: G.blob, the checkpoint and the
// log end as in an uninterrupted run.
TEST_F(TrainGan, KilledAtRandomMomentsAndResumedEndsBitwiseEqual) {
  const std::string full = (root_ / "kfull").string(), killed = (root_ / "killed").string();
  auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(run(train_cmd(full, ""), full + ".log"), 0) << read_all(full + ".log");
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  auto st = nns::testing::kill_and_resume(train_cmd(killed, ""), killed, killed + ".log", 10, 0.4 * ms, 5);
  // Delays under 0.4x an uninterrupted run: the first two kills land whatever the load
  // (each leaves over 0.6x of the work); later, shorter resumed runs may finish first.
  EXPECT_GE(st.kills, 2);
  std::printf("%d kills in %d runs\n", st.kills, st.runs);
  ASSERT_TRUE(fs::exists(killed + "/G.blob")) << read_all(killed + ".log");
  EXPECT_EQ(read_all(full + "/G.blob"), read_all(killed + "/G.blob"));
  EXPECT_EQ(read_all(full + "/checkpoint.blob"), read_all(killed + "/checkpoint.blob"));
  EXPECT_EQ(read_all(full + "/metrics.jsonl"), read_all(killed + "/metrics.jsonl"));
}

// --lr-d sets the discriminator's own learning rate (two time-scale updates); it is
// recorded in the run's configuration in the checkpoint (only when it differs from --lr,
// so a run with one rate records what it did before) and a resume with another one is
// refused naming it.
TEST_F(TrainGan, DiscriminatorLearningRateIsRecordedAndChecked) {
  const std::string out = (root_ / "lrd").string();
  ASSERT_EQ(run(train_cmd(out, "--loss gan --lr-d 0.001 --debug-stop-after-epochs 1"), out + ".log"), 0)
      << read_all(out + ".log");
  ASSERT_EQ(run(train_cmd(out, "--loss gan --lr-d 0.001 --resume"), out + ".log1"), 0) << read_all(out + ".log1");
  EXPECT_DOUBLE_EQ(nns::Blob::load(out + "/checkpoint.blob").config_double("lr_d"), 0.001);
  int rc = run(train_cmd(out, "--loss gan --lr-d 0.002 --resume"), out + ".log2");
  EXPECT_EQ(rc, 1) << read_all(out + ".log2");
  EXPECT_NE(read_all(out + ".log2").find("lr_d: was 0.001, now 0.002"), std::string::npos) << read_all(out + ".log2");
  // One rate (--lr-d 0, pix2pix) records nothing; the default, a quarter of --lr, is recorded.
  const std::string same = (root_ / "lrd-same").string();
  ASSERT_EQ(run(train_cmd(same, "--loss gan --lr-d 0"), same + ".log"), 0) << read_all(same + ".log");
  EXPECT_FALSE(nns::Blob::load(same + "/checkpoint.blob").has_config("lr_d"));
  const std::string def = (root_ / "lrd-default").string();
  ASSERT_EQ(run(train_cmd(def, "--loss gan"), def + ".log"), 0) << read_all(def + ".log");
  EXPECT_DOUBLE_EQ(nns::Blob::load(def + "/checkpoint.blob").config_double("lr_d"), 5e-5);
}

// The validation split: train-gan carves whole train/ scenes out before fitting
// anything and records the share in G.blob; eval-gi --split validation scores exactly
// those frames, --split holdout refuses data without holdout/, and a model trained
// without a validation split is refused for --split validation.
TEST_F(TrainGan, ValidationScenesAreCarvedRecordedAndScored) {
  const std::string data = (root_ / "val_data").string();
  write_dataset(data, 8, 2);
  const std::string run_dir = (root_ / "val").string();
  const std::string cmd = kBin + "train-gan --data " + data + " --size 16 --ngf 4 --ndf 4 --levels 3 --d-layers 2 " +
                          "--epochs 1 --sample-every 0 --no-eval --out ";
  ASSERT_EQ(run(cmd + run_dir + " --validation-fraction 0.25", run_dir + ".log"), 0) << read_all(run_dir + ".log");
  // The synthetic data has two train scenes of 4 frames each: a quarter moves one of them.
  EXPECT_NE(read_all(run_dir + ".log").find("4 training frames (4 more in validation scenes)"), std::string::npos)
      << read_all(run_dir + ".log");
  EXPECT_EQ(nns::Blob::load(run_dir + "/G.blob").config_double("validation_fraction"), 0.25);

  const std::string out = (root_ / "val_out").string();
  ASSERT_EQ(run(kBin + "eval-gi --split validation --data " + data + " --model " + run_dir + "/G.blob --out " + out,
                out + ".log"),
            0)
      << read_all(out + ".log");
  EXPECT_NE(read_all(out + "/report.md").find("split validation (4 frames,"), std::string::npos)
      << read_all(out + "/report.md");
  // The scenes it trained on: the other four frames.
  ASSERT_EQ(run(kBin + "eval-gi --split train --data " + data + " --model " + run_dir + "/G.blob --out " + out + "_t",
                out + "_t.log"),
            0)
      << read_all(out + "_t.log");
  EXPECT_NE(read_all(out + "_t/report.md").find("split train (4 frames,"), std::string::npos)
      << read_all(out + "_t/report.md");
  ASSERT_EQ(
      run(kBin + "eval-gi --mirror-average --data " + data + " --model " + run_dir + "/G.blob --out " + out + "_m",
          out + "_m.log"),
      0)
      << read_all(out + "_m.log");
  EXPECT_NE(read_all(out + "_m/results.csv").find("\nval/G mirror-avg,surround,"), std::string::npos)
      << read_all(out + "_m/results.csv");
  EXPECT_TRUE(fs::exists(out + "/results_by_family.csv"));
  EXPECT_TRUE(fs::exists(out + "/speed_vs_ssim.svg"));
  EXPECT_TRUE(fs::exists(out + "/speed_vs_mse_linear.png"));

  int rc = run(kBin + "eval-gi --split holdout --data " + data + " --model " + run_dir + "/G.blob --out " + out + "_h",
               out + "_h.log");
  EXPECT_EQ(rc, 1);
  EXPECT_NE(read_all(out + "_h.log").find("no holdout/ split"), std::string::npos) << read_all(out + "_h.log");

  const std::string no_val = (root_ / "noval").string();
  ASSERT_EQ(run(cmd + no_val + " --validation-fraction 0", no_val + ".log"), 0) << read_all(no_val + ".log");
  rc = run(kBin + "eval-gi --split validation --data " + data + " --model " + no_val + "/G.blob --out " + out + "_n",
           out + "_n.log");
  EXPECT_EQ(rc, 1);
  EXPECT_NE(read_all(out + "_n.log").find("trained without a validation split"), std::string::npos)
      << read_all(out + "_n.log");
}

// Streaming training frames from disk (--stream on: item i read when the epoch's order
// reaches it, the next one prefetched on a thread) gives the same bytes as holding them
// in memory, with 1 and 2 threads.
TEST_F(TrainGan, StreamedFramesTrainBitwiseLikeFramesInMemory) {
  const std::string mem = (root_ / "mem").string(), streamed = (root_ / "streamed").string();
  ASSERT_EQ(run(train_cmd(mem, "--stream off --threads 2"), mem + ".log"), 0) << read_all(mem + ".log");
  ASSERT_EQ(run(train_cmd(streamed, "--stream on --threads 1"), streamed + ".log"), 0) << read_all(streamed + ".log");
  EXPECT_NE(read_all(mem + ".log").find("held in memory"), std::string::npos) << read_all(mem + ".log");
  // In memory, the dataset check's decoded files are the ones trained on (bitwise equal
  // to the streamed run's, read again from disk at every step).
  EXPECT_NE(read_all(mem + ".log").find("each training file decoded once"), std::string::npos)
      << read_all(mem + ".log");
  EXPECT_NE(read_all(streamed + ".log").find("streamed from disk"), std::string::npos) << read_all(streamed + ".log");
  EXPECT_EQ(read_all(mem + "/G.blob"), read_all(streamed + "/G.blob"));
  EXPECT_EQ(read_all(mem + "/checkpoint.blob"), read_all(streamed + "/checkpoint.blob"));
  // --stream auto with no memory to spare streams too.
  const std::string tight = (root_ / "tight").string();
  ASSERT_EQ(run(train_cmd(tight, "--memory-budget 0"), tight + ".log"), 0) << read_all(tight + ".log");
  EXPECT_NE(read_all(tight + ".log").find("streamed from disk"), std::string::npos);
  EXPECT_NE(read_all(tight + ".log")
                .find("decoded again after the dataset check: the decoded training views would "
                      "take more than the memory budget"),
            std::string::npos)
      << read_all(tight + ".log");
  EXPECT_EQ(read_all(mem + "/G.blob"), read_all(tight + "/G.blob"));
}

// The discriminator-collapse watch, end to end. With G all but frozen (--lr 1e-9) and
// D's rate 10x pix2pix's, D separates real from generated pairs: its loss falls to ~0
// while G's adversarial loss climbs. The trainer must say so on stderr and in
// summary.json, and go on to the end (it reports; the remedy is the user's). The same
// run at pix2pix's rates stays silent. Before autograd fixed the graph's edges when an
// op is recorded, D also received G's adversarial gradient, was held at D(fake) = 2/3
// and could never win: this test failed (D loss ~0.6).
TEST_F(TrainGan, DiscriminatorWatchFiresWhenDWinsOutright) {
  const std::string won = (root_ / "dwins").string(), calm = (root_ / "dcalm").string();
  // 3 frames x 70 epochs = 210 steps: two full 100-step windows.
  ASSERT_EQ(run(train_cmd(won, "--loss gan --lr 1e-9 --lr-d 0.002 --epochs 70"), won + ".log"), 0)
      << read_all(won + ".log");
  const std::string log = read_all(won + ".log");
  EXPECT_NE(log.find("warning: the discriminator wins outright at step 200"), std::string::npos) << log;
  EXPECT_NE(log.find("the discriminator won outright in 1 windows"), std::string::npos) << log;
  const std::string summary = read_all(won + "/summary.json");
  EXPECT_NE(summary.find("\"d_wins_windows\":1"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"first_d_wins_step\":200"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"finished\":true"), std::string::npos) << summary;
  EXPECT_TRUE(fs::exists(won + "/G.blob"));

  // --lr-d 0: D at G's rate, as pix2pix (the default is a quarter of it, calmer still).
  ASSERT_EQ(run(train_cmd(calm, "--loss gan --epochs 70 --lr-d 0"), calm + ".log"), 0) << read_all(calm + ".log");
  EXPECT_EQ(read_all(calm + ".log").find("wins outright"), std::string::npos) << read_all(calm + ".log");
  EXPECT_NE(read_all(calm + "/summary.json").find("\"d_wins_windows\":0"), std::string::npos);
}

// --precision is part of the run's configuration: resuming a bf16 run as fp32 (or the
// other way) is refused naming it (checkpoints from before the flag: test_training_run).
// Without the flag (auto) a run records the precision this CPU chose, by name.
TEST_F(TrainGan, ResumeWithAnotherPrecisionIsRefusedNamingIt) {
  const std::string out = (root_ / "prec").string();
  ASSERT_EQ(run(train_cmd(out, "--precision bf16 --debug-stop-after-epochs 1"), out + ".log"), 0)
      << read_all(out + ".log");
  EXPECT_EQ(nns::Blob::load(out + "/checkpoint.blob").config_string("precision"), "bf16");
  EXPECT_EQ(run(train_cmd(out, "--precision fp32 --resume"), out + ".log1"), 1) << read_all(out + ".log1");
  EXPECT_NE(read_all(out + ".log1").find("precision"), std::string::npos) << read_all(out + ".log1");
  ASSERT_EQ(run(train_cmd(out, "--precision bf16 --resume"), out + ".log2"), 0) << read_all(out + ".log2");
  const std::string fp = (root_ / "prec32").string();
  ASSERT_EQ(run(train_cmd(fp, "--precision fp32 --debug-stop-after-epochs 1"), fp + ".log"), 0)
      << read_all(fp + ".log");
  EXPECT_EQ(run(train_cmd(fp, "--precision bf16 --resume"), fp + ".log1"), 1) << read_all(fp + ".log1");
  const std::string chosen = (root_ / "prec-auto").string();
  ASSERT_EQ(run(train_cmd(chosen, "--debug-stop-after-epochs 1"), chosen + ".log"), 0) << read_all(chosen + ".log");
  const char* name = nns::precision_name(nns::faster_training_precision(nns::cpu_features()));
  EXPECT_EQ(nns::Blob::load(chosen + "/checkpoint.blob").config_string("precision"), name);
  EXPECT_NE(read_all(chosen + ".log").find(std::string("train-gan: ") + name + " GEMMs"), std::string::npos)
      << read_all(chosen + ".log");
}

// Augmentation (--aug-mirror, --aug-exposure, --aug-tint; runs/gi/gi_augment.h): the same
// seed trains bitwise equal with 1 and 2 threads, it changes the training (it is not a
// no-op), a run interrupted and resumed equals an unbroken one, and a resume with
// another augmentation is refused naming it.
TEST_F(TrainGan, AugmentationIsDeterministicResumableAndRecorded) {
  const std::string aug = "--aug-mirror --aug-exposure 1.4 --aug-tint 1.2 ";
  const std::string one = (root_ / "aug1").string(), two = (root_ / "aug2").string(), plain = (root_ / "aug0").string();
  ASSERT_EQ(run(train_cmd(one, aug + "--threads 1"), one + ".log"), 0) << read_all(one + ".log");
  ASSERT_EQ(run(train_cmd(two, aug + "--threads 2"), two + ".log"), 0) << read_all(two + ".log");
  EXPECT_EQ(read_all(one + "/G.blob"), read_all(two + "/G.blob"));
  EXPECT_EQ(read_all(one + "/checkpoint.blob"), read_all(two + "/checkpoint.blob"));
  ASSERT_EQ(run(train_cmd(plain, "--threads 2"), plain + ".log"), 0) << read_all(plain + ".log");
  EXPECT_NE(read_all(plain + "/G.blob"), read_all(two + "/G.blob"));
  const nns::Blob ck = nns::Blob::load(two + "/checkpoint.blob");
  EXPECT_EQ(ck.config_string("aug_mirror"), "on");
  EXPECT_EQ(ck.config_string("aug_exposure"), "1.4");
  EXPECT_EQ(ck.config_string("aug_tint"), "1.2");

  const std::string broken = (root_ / "aug_resumed").string();
  ASSERT_EQ(run(train_cmd(broken, aug + "--threads 1 --debug-stop-after-epochs 1"), broken + ".log1"), 0)
      << read_all(broken + ".log1");
  ASSERT_NE(read_all(two + "/G.blob"), read_all(broken + "/G.blob"));
  ASSERT_EQ(run(train_cmd(broken, aug + "--threads 2 --resume"), broken + ".log2"), 0) << read_all(broken + ".log2");
  EXPECT_EQ(read_all(two + "/G.blob"), read_all(broken + "/G.blob"));
  EXPECT_EQ(read_all(two + "/checkpoint.blob"), read_all(broken + "/checkpoint.blob"));
  EXPECT_EQ(read_all(two + "/metrics.jsonl"), read_all(broken + "/metrics.jsonl"));

  int rc = run(train_cmd(broken, "--aug-mirror --aug-exposure 1.2 --aug-tint 1.2 --resume"), broken + ".log3");
  EXPECT_EQ(rc, 1) << read_all(broken + ".log3");
  EXPECT_NE(read_all(broken + ".log3").find("aug_exposure: was 1.4, now 1.2"), std::string::npos)
      << read_all(broken + ".log3");
  // A checkpoint made without augmentation (or before it existed) resumes only without it.
  rc = run(train_cmd(plain, "--aug-mirror --resume"), plain + ".log2");
  EXPECT_EQ(rc, 1) << read_all(plain + ".log2");
  EXPECT_NE(read_all(plain + ".log2").find("aug_mirror: was off, now on"), std::string::npos)
      << read_all(plain + ".log2");
}

// --size 0 trains on the views as stored, as --help says; a non-square view whose sides
// the U-Net cannot halve --levels times is refused before any step, naming the levels
// that fit. 40x24 views: 8 divides both sides, 16 does not, so 3 levels fit.
TEST_F(TrainGan, SizeZeroTrainsNonSquareViewsAsStoredAndNamesTheLevelsThatFit) {
  const fs::path data = root_ / "flat";
  ASSERT_EQ(run(kBin + "render-dataset --out " + data.string() +
                    " --preset gi --views 6 --size 40x24 --spp 4 --gi-spp 4 --bounces 2 --threads 1",
                (root_ / "flat.log").string()),
            0)
      << read_all((root_ / "flat.log").string());
  const std::string base = kBin + "train-gan --data " + data.string() +
                           " --mode front --size 0 --ngf 4 --ndf 4 --d-layers 2 --epochs 1 --sample-every 0 --no-eval "
                           "--validation-fraction 0 --out ";
  const std::string refused = (root_ / "flat-l4").string();
  EXPECT_EQ(run(base + refused + " --levels 4", refused + ".log"), 1);
  EXPECT_NE(read_all(refused + ".log").find("input is 40x24"), std::string::npos) << read_all(refused + ".log");
  EXPECT_NE(read_all(refused + ".log").find("--levels 3 or fewer fits"), std::string::npos);
  EXPECT_FALSE(fs::exists(fs::path(refused) / "G.blob"));
  const std::string ok = (root_ / "flat-l3").string();
  EXPECT_EQ(run(base + ok + " --levels 3", ok + ".log"), 0) << read_all(ok + ".log");
  EXPECT_TRUE(fs::exists(fs::path(ok) / "G.blob"));
  EXPECT_NE(run(base + ok + "-bad --levels 3 --size 2", ok + "-bad.log"), 0);
  EXPECT_NE(read_all(ok + "-bad.log").find("--size must be 0"), std::string::npos) << read_all(ok + "-bad.log");
}

// The resolution study: a model trained at face 16 scored at face 32, run there fully
// convolutionally, and run at 16 with its indirect light brought up by the guided upsample.
// Both score the same face-16 frames: the references agree byte for byte, the models do not.
TEST_F(TrainGan, EvalGiScoresAModelAtAnotherSizeAndThroughTheGuidedUpsample) {
  const std::string data = (root_ / "data32").string();
  write_dataset(data, 3, 2, false, 32);
  const std::string run_dir = (root_ / "small").string();
  // With its evaluation: frames stored at 32, trained at 16, are scored at 32 through the
  // guided upsample, as `eval-gi --size 32 --upsample-from 16` scores them (below).
  ASSERT_EQ(run(kBin + "train-gan --data " + data + " --out " + run_dir +
                    " --size 16 --ngf 4 --ndf 4 --levels 3 --d-layers 2 --epochs 1 --sample-every 0"
                    " --validation-fraction 0",
                run_dir + ".log"),
            0)
      << read_all(run_dir + ".log");
  const std::string base = kBin + "eval-gi --data " + data + " --model " + run_dir + "/G.blob --size 32";
  const std::string conv = (root_ / "at16").string(), guided = (root_ / "guided16").string();
  ASSERT_EQ(run(base + " --out " + conv, conv + ".log"), 0) << read_all(conv + ".log");
  ASSERT_EQ(run(base + " --upsample-from 16 --out " + guided, guided + ".log"), 0) << read_all(guided + ".log");
  auto lines = [](const std::string& csv) {
    std::vector<std::string> out;
    std::istringstream in(csv);
    for (std::string l; std::getline(in, l);) {  // every column but ms_per_frame (the third)
      const size_t second = l.find(',', l.find(',') + 1), third = l.find(',', second + 1);
      out.push_back(l.substr(0, second) + l.substr(third));
    }
    return out;
  };
  const auto a = lines(read_all(conv + "/results.csv")), b = lines(read_all(guided + "/results.csv"));
  ASSERT_EQ(a.size(), 4u);
  ASSERT_EQ(b.size(), 5u);
  EXPECT_EQ(a[1], b[1]);  // direct+env, without the timing column
  EXPECT_EQ(a[2], b[2]);  // direct+env+ambient
  // The upsample's ceiling: the truth box-filtered to 16 and brought back up is close to
  // the truth, far closer than the light without any indirect part.
  ASSERT_EQ(b[3].rfind("truth @16 guided,", 0), 0u) << b[3];
  auto mse = [](const std::string& line) {  // the third column once ms_per_frame is cut
    const size_t second = line.find(',', line.find(',') + 1);
    return std::stod(line.substr(second + 1));
  };
  EXPECT_LT(mse(b[3]), 0.25 * mse(b[1])) << b[3] << "\n" << b[1];
  EXPECT_NE(a[3], b[4]);
  EXPECT_NE(b[4].find("small/G @16 guided"), std::string::npos) << b[4];
  EXPECT_EQ(lines(read_all(run_dir + "/eval/results.csv")), b) << "train-gan's evaluation is not eval-gi's upsample";
  EXPECT_NE(read_all(guided + "/report.md").find("scored at face 32"), std::string::npos);
  // Flags that cannot work are refused, naming the flag.
  const std::string bad = (root_ / "bad16").string();
  EXPECT_EQ(run(kBin + "eval-gi --data " + data + " --model " + run_dir + "/G.blob --upsample-from 16 --out " + bad,
                bad + ".log"),
            2);
  EXPECT_NE(read_all(bad + ".log").find("--upsample-from needs --size"), std::string::npos) << read_all(bad + ".log");
  EXPECT_EQ(run(base + " --upsample-from 6 --out " + bad, bad + ".log"), 2);
  EXPECT_NE(read_all(bad + ".log").find("proper divisor of --size"), std::string::npos) << read_all(bad + ".log");

  // --second-render: a copy of the data is a render without independent noise, so
  // "another render" scores MSE 0 and "another render @16 guided" is "truth @16 guided".
  const std::string copy = (root_ / "data32_copy").string();
  fs::copy(data, copy, fs::copy_options::recursive);
  const std::string second = (root_ / "second16").string();
  ASSERT_EQ(run(base + " --upsample-from 16 --second-render " + copy + " --out " + second, second + ".log"), 0)
      << read_all(second + ".log");
  const auto c = lines(read_all(second + "/results.csv"));
  ASSERT_EQ(c.size(), 7u);
  ASSERT_EQ(c[4].rfind("another render,", 0), 0u) << c[4];
  EXPECT_EQ(mse(c[4]), 0.0) << c[4];
  EXPECT_EQ(c[5], "another render @16 guided" + b[3].substr(b[3].find(','))) << c[5] << "\n" << b[3];
  EXPECT_EQ(c[6], b[4]);
  // A frame of another view under the same name (two frames' folders swapped) is refused, naming it.
  const std::string other = (root_ / "data32_swapped").string();
  fs::copy(data, other, fs::copy_options::recursive);
  fs::rename(other + "/test/frame0", other + "/test/tmp");
  fs::rename(other + "/test/frame1", other + "/test/frame0");
  fs::rename(other + "/test/tmp", other + "/test/frame1");
  EXPECT_EQ(run(base + " --upsample-from 16 --second-render " + other + " --out " + bad, bad + ".log"), 1);
  EXPECT_NE(read_all(bad + ".log").find("not the frame"), std::string::npos) << read_all(bad + ".log");
  // A folder that is not there is named before any frame is read.
  EXPECT_EQ(run(base + " --second-render " + copy + "_missing --out " + bad, bad + ".log"), 1);
  EXPECT_NE(read_all(bad + ".log").find(copy + "_missing: not a folder"), std::string::npos) << read_all(bad + ".log");
  EXPECT_EQ(read_all(bad + ".log").find("eval-gi small/G"), std::string::npos) << read_all(bad + ".log");
}

// --ema: G.blob holds the weights' moving average: another file than the last step's
// weights, the same with 1 or 2 threads, bitwise equal after a kill and resume (the
// average is in the checkpoint), recorded, and a resume without it is refused.
TEST_F(TrainGan, WeightAverageIsDeterministicResumableAndRecorded) {
  const std::string one = (root_ / "ema1").string(), two = (root_ / "ema2").string();
  const std::string plain = (root_ / "ema0").string(), broken = (root_ / "ema_resumed").string();
  ASSERT_EQ(run(train_cmd(one, "--ema 0.9 --threads 1"), one + ".log"), 0) << read_all(one + ".log");
  ASSERT_EQ(run(train_cmd(two, "--ema 0.9 --threads 2"), two + ".log"), 0) << read_all(two + ".log");
  EXPECT_EQ(read_all(one + "/G.blob"), read_all(two + "/G.blob"));
  ASSERT_EQ(run(train_cmd(plain, "--threads 2"), plain + ".log"), 0) << read_all(plain + ".log");
  EXPECT_NE(read_all(plain + "/G.blob"), read_all(two + "/G.blob"));
  // The same training: its losses, which the average does not touch, are the same log.
  EXPECT_EQ(read_all(plain + "/metrics.jsonl"), read_all(two + "/metrics.jsonl"));
  EXPECT_EQ(nns::Blob::load(two + "/checkpoint.blob").config_string("ema"), "0.9");

  ASSERT_EQ(run(train_cmd(broken, "--ema 0.9 --threads 1 --debug-stop-after-epochs 1"), broken + ".log1"), 0)
      << read_all(broken + ".log1");
  ASSERT_NE(read_all(two + "/G.blob"), read_all(broken + "/G.blob"));
  ASSERT_EQ(run(train_cmd(broken, "--ema 0.9 --threads 2 --resume"), broken + ".log2"), 0)
      << read_all(broken + ".log2");
  EXPECT_EQ(read_all(two + "/G.blob"), read_all(broken + "/G.blob"));
  EXPECT_EQ(read_all(two + "/checkpoint.blob"), read_all(broken + "/checkpoint.blob"));

  EXPECT_EQ(run(train_cmd(broken, "--resume"), broken + ".log3"), 1) << read_all(broken + ".log3");
  EXPECT_NE(read_all(broken + ".log3").find("ema: was 0.9, now 0"), std::string::npos) << read_all(broken + ".log3");
  EXPECT_NE(run(train_cmd(plain + "_bad", "--ema 1"), plain + "_bad.log"), 0);
  EXPECT_NE(read_all(plain + "_bad.log").find("--ema"), std::string::npos) << read_all(plain + "_bad.log");
}

// --g-dropout: the U-Net's dropout probability, recorded in G.blob (eval-gi rebuilds the
// generator from it) and in the checkpoint (a resume with another value is refused).
TEST_F(TrainGan, GeneratorDropoutIsRecordedAndChecked) {
  const std::string none = (root_ / "nodrop").string();
  ASSERT_EQ(run(train_cmd(none, "--g-dropout 0 --epochs 1"), none + ".log"), 0) << read_all(none + ".log");
  EXPECT_EQ(nns::Blob::load(none + "/G.blob").config_double("dropout"), 0.0);
  const std::string out = (root_ / "nodrop_eval").string();
  ASSERT_EQ(run(kBin + "eval-gi --data " + (root_ / "data").string() + " --model " + none + "/G.blob --out " + out,
                out + ".log"),
            0)
      << read_all(out + ".log");
  EXPECT_EQ(run(train_cmd(none, "--epochs 2 --resume"), none + ".log2"), 1) << read_all(none + ".log2");
  EXPECT_NE(read_all(none + ".log2").find("dropout: was 0, now 0.5"), std::string::npos) << read_all(none + ".log2");
}
