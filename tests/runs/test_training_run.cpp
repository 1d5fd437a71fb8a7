// The run layer on its own: one metrics format (null for NaN, strict parsing, correct
// truncation on resume), the checkpoint's configuration check, the order of the
// end-of-epoch writes, and the clean-up of a killed writer's temporaries.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <future>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/atomic_file.h"
#include "nn/linear.h"
#include "optim/adam.h"
#include "runs/metrics_log.h"
#include "runs/training_run.h"

namespace fs = std::filesystem;
using namespace nns;
using namespace nns::runs;

namespace {

fs::path temp_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("nnshade_run_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST(MetricsLine, RoundTripsAndWritesNullForNonFinite) {
  MetricsRecord r{12, 3, {{"train_loss", 0.125}, {"test_mse", std::nan("")}, {"lr", 2e-4}}};
  const std::string line = format_metrics_line(r);
  EXPECT_EQ(line, "{\"step\":12,\"epoch\":3,\"train_loss\":0.125,\"test_mse\":null,\"lr\":0.0002}");
  auto back = parse_metrics_line(line);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->step, 12);
  EXPECT_EQ(back->epoch, 3);
  EXPECT_EQ(back->get("train_loss"), 0.125);
  EXPECT_TRUE(std::isnan(back->get("test_mse")));
  EXPECT_EQ(format_metrics_line(*back), line);
}

TEST(MetricsLine, RefusesWhatItDidNotWrite) {
  for (const char* bad :
       {"", "{", "{\"step\":1,\"epoch\":1", "{\"step\":1,\"epoch\":1,\"a\":}", "{\"epoch\":1,\"step\":1}",
        "{\"step\":1.5,\"epoch\":1}", "{\"step\":1,\"epoch\":1} ", "{\"step\":1,\"epoch\":1,\"a\":nan}",
        "{\"step\":1,\"epoch\":1,\"a\":1e999}", "{\"epoch\": 1, \"train_loss\": 0.5, \"test_mse\": 0.1}"})
    EXPECT_FALSE(parse_metrics_line(bad)) << bad;
}

TEST(MetricsLog, ResumeKeepsTheLinesTheCheckpointCoversAndDropsATornOne) {
  fs::path d = temp_dir("log");
  const std::string path = (d / "metrics.jsonl").string();
  {
    MetricsLog log(path, -1);
    for (int s = 1; s <= 5; ++s) log.append({s * 10, s, {{"loss", 1.0 / s}}});
  }
  std::ofstream(path, std::ios::app) << "{\"step\":60,\"epo";  // a killed run's last write
  MetricsLog resumed(path, 30);
  ASSERT_EQ(resumed.records().size(), 3u);
  EXPECT_EQ(resumed.records().back().step, 30);
  resumed.append({40, 4, {{"loss", 0.2}}});
  auto all = read_metrics(path);
  ASSERT_EQ(all.size(), 4u);
  EXPECT_EQ(all[3].get("loss"), 0.2);
  std::ifstream in(path);
  int lines = 0;
  for (std::string l; std::getline(in, l);) {
    ++lines;
    EXPECT_TRUE(parse_metrics_line(l)) << l;
  }
  EXPECT_EQ(lines, 4);
  fs::remove_all(d);
}

TEST(TrainingRun, ResumeRefusesAnotherConfigurationNamingWhatChanged) {
  fs::path d = temp_dir("config");
  Rng rng(1);
  Linear<float> net(rng, 3, 2);
  Checkpoint<float> ck;
  ck.add_module("net", net);
  int64_t step = 0;
  RunSpec spec;
  spec.app = "test";
  spec.out = d.string();
  spec.config = {{"lr", "0.001"}, {"seed", "1"}, {"epochs", "2"}};
  {
    TrainingRun run(spec, ck, step);
    step = 7;
    run.end_epoch(1, nullptr);
  }
  spec.resume = true;
  spec.config = {{"lr", "0.002"}, {"seed", "2"}, {"epochs", "5"}};  // epochs may change
  try {
    TrainingRun run(spec, ck, step);
    FAIL() << "a resume with another lr and seed was accepted";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("lr: was 0.001, now 0.002"), std::string::npos) << m;
    EXPECT_NE(m.find("seed: was 1, now 2"), std::string::npos) << m;
    EXPECT_EQ(m.find("epochs"), std::string::npos) << m;
  }
  spec.config = {{"lr", "0.001"}, {"seed", "1"}, {"epochs", "5"}};
  step = 0;
  TrainingRun run(spec, ck, step);
  EXPECT_EQ(run.epochs_done(), 1);
  EXPECT_EQ(step, 7);
  fs::remove_all(d);
}

// A key added after checkpoints existed ("precision"): a checkpoint that lacks it resumes
// at the value it was made with (fp32), and one made with another value is refused.
TEST(TrainingRun, AKeyACheckpointPredatesMeansItsOldValue) {
  Blob old_ck("checkpoint");
  old_ck.set_config("lr", "0.001");
  RunSpec spec;
  spec.config = {{"lr", "0.001"}, {"precision", "fp32"}};
  EXPECT_EQ(config_changes(old_ck, spec), "");
  spec.config = {{"lr", "0.001"}, {"precision", "bf16"}};
  EXPECT_EQ(config_changes(old_ck, spec), "precision: was fp32, now bf16");
  Blob bf16_ck("checkpoint");
  bf16_ck.set_config("lr", "0.001");
  bf16_ck.set_config("precision", "bf16");
  spec.config = {{"lr", "0.001"}, {"precision", "fp32"}};
  EXPECT_EQ(config_changes(bf16_ck, spec), "precision: was bf16, now fp32");
  spec.config = {{"lr", "0.001"}, {"other", "1"}};  // no old value declared for it
  EXPECT_EQ(config_changes(old_ck, spec), "other: was (not recorded), now 1");
}

TEST(TrainingRun, ResumeWithoutACheckpointIsRefused) {
  fs::path d = temp_dir("nock");
  Checkpoint<float> ck;
  int64_t step = 0;
  RunSpec spec;
  spec.app = "test";
  spec.out = d.string();
  spec.resume = true;
  EXPECT_THROW({ TrainingRun run(spec, ck, step); }, std::runtime_error);
  fs::remove_all(d);
}

TEST(TrainingRun, OutputsAreWrittenBeforeTheCheckpointThatCoversThem) {
  fs::path d = temp_dir("order");
  Checkpoint<float> ck;
  int64_t step = 0;
  RunSpec spec;
  spec.app = "test";
  spec.out = d.string();
  TrainingRun run(spec, ck, step);
  bool checkpoint_existed_when_outputs_were_written = true;
  run.end_epoch(1, [&] { checkpoint_existed_when_outputs_were_written = fs::exists(d / "checkpoint.blob"); });
  EXPECT_FALSE(checkpoint_existed_when_outputs_were_written);
  EXPECT_TRUE(fs::exists(d / "checkpoint.blob"));
  fs::remove_all(d);
}

// A module with a buffer, as BatchNorm's running_var.
struct WithBuffer : Module<float> {
  explicit WithBuffer(Rng& rng) {
    fc = register_module("fc", std::make_shared<Linear<float>>(rng, 3, 2));
    running_var = &register_buffer("running_var", Tensor<float>::ones({4}));
  }
  Var<float> forward(const Var<float>& x) override { return fc->forward(x); }
  std::shared_ptr<Linear<float>> fc;
  Tensor<float>* running_var;
};

// train-gan --lr 1e9 exited 0 with +inf in BatchNorm running_var values of G.blob: the
// loss was checked, the buffers were not. Nothing is written, the first bad tensor named.
TEST(TrainingRun, ANonFiniteBufferOrWeightStopsTheRunBeforeAnythingIsWritten) {
  for (const char* bad : {"buffer", "weight", "optimizer"}) {
    fs::path d = temp_dir(std::string("nonfinite_") + bad);
    Rng rng(1);
    WithBuffer net(rng);
    Adam<float> opt(net.parameters());
    Checkpoint<float> ck;
    ck.add_module("G", net).add_optimizer("G", opt);
    int64_t step = 0;
    RunSpec spec;
    spec.app = "test";
    spec.out = d.string();
    TrainingRun run(spec, ck, step);
    run.end_epoch(1, [&] { write_file_atomic((d / "G.blob").string(), "epoch 1"); });
    std::string expected;
    if (std::string(bad) == "buffer") (*net.running_var)[2] = HUGE_VALF, expected = "module.G.running_var";
    if (std::string(bad) == "weight") net.fc->weight.value()[1] = std::nanf(""), expected = "module.G.fc.weight";
    if (std::string(bad) == "optimizer") {
      // A gradient of 1e30 squares to +inf in Adam's second moment; the step it divides
      // is 1e30 / inf = 0, so the weight itself stays finite.
      for (auto& g : net.fc->weight.grad_buffer()) g = 1e30f;
      opt.step();
      expected = "optim.G.0.v";
    }
    step = 12;
    bool written = false;
    try {
      run.end_epoch(2, [&] { written = true; });
      ADD_FAILURE() << "a non-finite " << bad << " was written";
    } catch (const NonFiniteError& e) {
      EXPECT_EQ(e.tensor, expected);
      EXPECT_EQ(e.step, 12);
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
    EXPECT_FALSE(written);
    EXPECT_EQ(read_file((d / "G.blob").string()), "epoch 1");
    EXPECT_EQ(Blob::load((d / "checkpoint.blob").string()).get_i64("counter.epochs_done"), 1);
    fs::remove_all(d);
  }
}

// `b` with the i64 tensor `name` replaced by `value`, CRC and all: what a hostile
// checkpoint looks like.
Blob with_i64(const Blob& b, const std::string& name, int64_t value) {
  Blob out(b.kind());
  for (auto& [k, v] : b.config()) out.set_config(k, v);
  for (auto& [n, t] : b.tensors()) {
    const Shape sh(t.dims.begin(), t.dims.end());
    if (n == name) out.put_i64(n, value);
    else if (t.dtype == DType::F32) out.put(n, sh, reinterpret_cast<const float*>(t.bytes.data()));
    else if (t.dtype == DType::F64) out.put(n, sh, reinterpret_cast<const double*>(t.bytes.data()));
    else if (t.dtype == DType::U64) out.put(n, sh, reinterpret_cast<const uint64_t*>(t.bytes.data()));
    else out.put(n, sh, reinterpret_cast<const int64_t*>(t.bytes.data()));
  }
  return out;
}

// A checkpoint's epochs_done of 2^62 resumed "at epoch 4611686018427387904" with exit 0,
// and -1 ran an extra epoch logged as epoch -1; a step past 2^53 cannot be logged exactly.
TEST(TrainingRun, ResumeRefusesACounterOutOfRangeNamingIt) {
  fs::path d = temp_dir("counters");
  Checkpoint<float> ck;
  int64_t step = 0;
  RunSpec spec;
  spec.app = "test";
  spec.out = d.string();
  {
    TrainingRun run(spec, ck, step);
    step = 5;
    run.end_epoch(1, nullptr);
  }
  const std::string ck_path = (d / "checkpoint.blob").string();
  const Blob good = Blob::load(ck_path);
  spec.resume = true;
  for (auto [counter, value] :
       std::initializer_list<std::pair<const char*, int64_t>>{{"counter.epochs_done", int64_t(1) << 62},
                                                              {"counter.epochs_done", -1},
                                                              {"counter.epochs_done", 100001},
                                                              {"counter.step", -1},
                                                              {"counter.step", (int64_t(1) << 53) + 1}}) {
    with_i64(good, counter, value).save(ck_path);
    try {
      TrainingRun run(spec, ck, step);
      ADD_FAILURE() << counter << " " << value << " accepted (epochs_done " << run.epochs_done() << ")";
    } catch (const std::runtime_error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(ck_path), std::string::npos) << m;
      EXPECT_NE(m.find(std::string(counter).substr(8) + "' is " + std::to_string(value) + ", out of range"),
                std::string::npos)
          << m;
    }
  }
  good.save(ck_path);
  TrainingRun run(spec, ck, step);
  EXPECT_EQ(run.epochs_done(), 1);
  fs::remove_all(d);
}

// train-nnao --resume blocked forever when OUT/metrics.jsonl was a FIFO.
TEST(TrainingRun, ResumeRefusesAMetricsLogThatIsNoRegularFile) {
  fs::path d = temp_dir("fifo");
  Checkpoint<float> ck;
  int64_t step = 0;
  RunSpec spec;
  spec.app = "test";
  spec.out = d.string();
  {
    TrainingRun run(spec, ck, step);
    run.end_epoch(1, nullptr);
  }
  const std::string log = (d / "metrics.jsonl").string();
  fs::remove(log);
  ASSERT_EQ(::mkfifo(log.c_str(), 0600), 0);
  spec.resume = true;
  auto resumed = std::async(std::launch::async, [&]() -> std::string {
    try {
      TrainingRun run(spec, ck, step);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  });
  if (resumed.wait_for(std::chrono::seconds(5)) != std::future_status::ready) {
    ADD_FAILURE() << "the resume blocks on the FIFO";
    int fd = ::open(log.c_str(), O_WRONLY);  // lets the blocked reader go on
    if (fd >= 0) ::close(fd);
  }
  const std::string m = resumed.get();
  EXPECT_NE(m.find(log), std::string::npos) << m;
  EXPECT_NE(m.find("regular file"), std::string::npos) << m;
  fs::remove_all(d);
}

// Two train-nnao runs with one --out both exited 0, interleaving one metrics.jsonl.
TEST(TrainingRun, ASecondRunIntoTheSameFolderIsRefusedNamingFolderAndHolder) {
  fs::path d = temp_dir("locked");
  Checkpoint<float> ck1, ck2;
  int64_t step1 = 0, step2 = 0;
  RunSpec spec;
  spec.app = "train-nnao";
  spec.out = d.string();
  TrainingRun first(spec, ck1, step1);
  try {
    TrainingRun second(spec, ck2, step2);
    ADD_FAILURE() << "two runs share " << d;
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(d.string()), std::string::npos) << m;
    EXPECT_NE(m.find("pid " + std::to_string(::getpid())), std::string::npos) << m;
  }
  fs::remove_all(d);
}

TEST(TrainingRun, FinishWritesValidJsonEvenForAStopMessageWithQuotes) {
  fs::path d = temp_dir("summary");
  Checkpoint<float> ck;
  int64_t step = 0;
  RunSpec spec;
  spec.app = "test";
  spec.out = d.string();
  TrainingRun run(spec, ck, step);
  EXPECT_EQ(run.finish("stopped in \"G\"\n", {{"seconds", std::nan("")}}), 3);
  EXPECT_EQ(
      read_file((d / "summary.json").string()),
      "{\"finished\":false,\"stop\":\"stopped in \\\"G\\\"\\u000a\",\"epochs_done\":0,\"steps\":0,\"seconds\":null}\n");
  fs::remove_all(d);
}

TEST(AtomicFile, StaleTemporariesOfADeadWriterAreRemovedLiveOnesKept) {
  fs::path d = temp_dir("stale");
  // A pid that cannot be running: above the kernel's pid_max (4194304 at most).
  write_file_atomic((d / "keep.blob").string(), "x");
  std::ofstream(d / "G.blob.tmp.99999999") << "torn";
  const std::string mine = "G.blob.tmp." + std::to_string(::getpid());
  std::ofstream(d / mine) << "in progress";
  std::ofstream(d / "notes.tmp.txt") << "not ours";
  EXPECT_EQ(remove_stale_temporaries(d.string()), 1);
  EXPECT_FALSE(fs::exists(d / "G.blob.tmp.99999999"));
  EXPECT_TRUE(fs::exists(d / mine));
  EXPECT_TRUE(fs::exists(d / "notes.tmp.txt"));
  EXPECT_TRUE(fs::exists(d / "keep.blob"));
  fs::remove_all(d);
}

// A set of files written together: a failure while writing any of them leaves the old
// set untouched and no temporary; success replaces all of them.
TEST(AtomicFile, FilesWrittenTogetherAreReplacedAllOrNone) {
  fs::path d = temp_dir("together");
  const std::vector<std::string> paths = {(d / "a.exr").string(), (d / "a_shaded.png").string(),
                                          (d / "a_indirect.png").string()};
  for (auto& p : paths) write_file_atomic(p, "old");
  auto write = [&](size_t fail_at) {
    write_paths_atomic(paths, [&](size_t i, const std::string& tmp) {
      if (i == fail_at) throw std::runtime_error("disk full");
      std::ofstream(tmp) << "new";
    });
  };
  for (size_t fail_at : {size_t(0), size_t(1), size_t(2)}) {
    EXPECT_THROW(write(fail_at), std::runtime_error);
    for (auto& p : paths) EXPECT_EQ(read_file(p), "old") << p << " after a failure at file " << fail_at;
    EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 3);
  }
  write(99);
  for (auto& p : paths) EXPECT_EQ(read_file(p), "new") << p;
  EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator()), 3);
  fs::remove_all(d);
}
