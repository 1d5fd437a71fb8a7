// eval-ao end to end on small synthetic views: the CSV/report/chart appear, and bad
// input (a view without AO, a NaN depth) is explained with a non-zero exit.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/blob.h"
#include "data/exr_io.h"
#include "fixtures/random_nnao_blob.h"
#include "fixtures/synthetic_gbuffer.h"
#include "tests/support/run_command.h"

namespace fs = std::filesystem;

namespace {

using nns::testing::CommandResult;

CommandResult run(const std::string& args) { return nns::testing::run_app("eval-ao", args); }

std::string read(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// One view in each of train/, test/ and holdout/ (a "cave" family held out, as
// render-dataset --holdout-families writes it).
void write_three_splits(const fs::path& data) {
  for (const char* split : {"train", "test", "holdout"}) {
    fs::create_directories(data / split);
    auto view = nns::fixtures::synthetic_view(24, 16, split[0] == 'h' ? 3 : 1, 8);
    view.scene = std::string(split[0] == 'h' ? "cave" : "room") + "-" + std::to_string(split[1] == 'e' ? 100000 : 7);
    nns::data::write_view((data / split / "v.exr").string(), view);
  }
}

fs::path temp_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("nnshade_eval_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST(EvalAo, WritesResultsForClassicalMethods) {
  fs::path d = temp_dir("ok");
  fs::create_directories(d / "data");
  for (int v = 0; v < 3; ++v) {
    auto view = nns::fixtures::synthetic_view(48, 32, v, 16);
    view.scene = "path";  // frames of one camera path (a still camera): the temporal check runs
    view.world_to_camera = std::array<float, 16>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    nns::data::write_view((d / "data" / ("path-p00-f00" + std::to_string(v) + ".exr")).string(), view);
  }
  CommandResult r = run("--data " + (d / "data").string() + " --out " + (d / "out").string() +
                        " --methods SSAO,HBAO --threads 2 --previews 1");
  ASSERT_EQ(r.code, 0) << r.output;
  std::string csv = read(d / "out" / "results.csv");
  EXPECT_EQ(csv.rfind("method,samples,ms_per_frame,mse,ssim,psnr,setting\n", 0), 0u) << csv;
  EXPECT_NE(csv.find("\nHBAO,64,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\nSSAO,4,"), std::string::npos) << csv;
  EXPECT_EQ(csv.find("nan"), std::string::npos) << csv;
  EXPECT_TRUE(fs::exists(d / "out" / "speed_vs_accuracy.svg"));
  EXPECT_TRUE(fs::exists(d / "out" / "results_by_scene.csv"));
  EXPECT_TRUE(fs::exists(d / "out" / "previews" / "data_path-p00-f000_ground_truth.png"));
  EXPECT_TRUE(fs::exists(d / "out" / "previews" / "data_path-p00-f000_HBAO_64_error.png"));
  std::string temporal = read(d / "out" / "temporal.csv");
  EXPECT_EQ(temporal.rfind("method,samples,flicker,ground_truth_flicker,flicker_relative_to_ground_truth,temporal_"
                           "error,pairs,coverage\n",
                           0),
            0u)
      << temporal;
  EXPECT_NE(temporal.find("\nHBAO,64,"), std::string::npos) << temporal;
  EXPECT_NE(temporal.find(",2,"), std::string::npos) << temporal;  // frames 0-1 and 1-2
  EXPECT_TRUE(fs::exists(d / "out" / "timing.csv"));
  // The second chart: flicker against time, shown in report.md.
  EXPECT_TRUE(fs::exists(d / "out" / "flicker_vs_time.svg"));
  EXPECT_NE(read(d / "out" / "report.md").find("![flicker vs time](flicker_vs_time.svg)"), std::string::npos);
  const std::string fam = read(d / "out" / "results_by_family.csv");
  EXPECT_NE(fam.find("\npath,HBAO,"), std::string::npos) << fam;  // HBAO at its best setting, family "path"
  EXPECT_NE(read(d / "out" / "report.md").find("## Per family"), std::string::npos);
  EXPECT_NE(read(d / "out" / "report.md").find("| HBAO | 64 |"), std::string::npos);
  fs::remove_all(d);
}

TEST(EvalAo, ViewWithoutAoIsExplained) {
  fs::path d = temp_dir("noao");
  auto view = nns::fixtures::synthetic_view(16, 12, 0, 4);
  view.channels.erase("AO");
  view.ao_radius.reset();
  nns::data::write_view((d / "a.exr").string(), view);
  CommandResult r = run("--data " + d.string() + " --out " + (d / "out").string() + " --methods SSAO");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("a.exr"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("'AO'"), std::string::npos) << r.output;
  fs::remove_all(d);
}

TEST(EvalAo, NanDepthIsExplained) {
  fs::path d = temp_dir("nan");
  auto view = nns::fixtures::synthetic_view(16, 12, 0, 4);
  view.channels["Z"][20] = NAN;
  nns::data::write_view((d / "b.exr").string(), view);
  CommandResult r = run("--data " + d.string() + " --out " + (d / "out").string() + " --methods HBAO");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("b.exr"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("NaN"), std::string::npos) << r.output;
  fs::remove_all(d);
}

TEST(EvalAo, UnknownMethodIsAnError) {
  CommandResult r = run("--data /nonexistent --methods FOO");
  EXPECT_NE(r.code, 0);
}

// A NaN in the ground-truth AO used to give NaN scores with exit 0.
TEST(EvalAo, NanGroundTruthIsRefusedNamingTheFile) {
  fs::path d = temp_dir("nanao");
  auto view = nns::fixtures::synthetic_view(16, 12, 0, 4);
  view.channels["AO"][7] = NAN;
  nns::data::write_view((d / "c.exr").string(), view);
  CommandResult r = run("--data " + d.string() + " --out " + (d / "out").string() + " --methods SSAO");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("c.exr: channel 'AO' is NaN"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "out" / "results.csv"));
  fs::remove_all(d);
}

// A dataset with holdout/ (render-dataset --holdout-families) is scored on both splits:
// the test split into OUT, the held-out families into OUT/holdout.
TEST(EvalAo, ScoresTheHeldOutFamiliesBesideTheTestSplit) {
  fs::path d = temp_dir("holdout");
  write_three_splits(d / "data");
  CommandResult r =
      run("--data " + (d / "data").string() + " --out " + (d / "out").string() + " --methods SSAO --previews 0");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(read(d / "out" / "results_by_family.csv").find("\nroom,SSAO,"), std::string::npos);
  EXPECT_NE(read(d / "out" / "holdout" / "results_by_family.csv").find("\ncave,SSAO,"), std::string::npos);
  EXPECT_NE(read(d / "out" / "holdout" / "report.md").find("held-out families"), std::string::npos);
  fs::remove_all(d / "data" / "holdout");
  r = run("--data " + (d / "data").string() + " --out " + (d / "out2").string() + " --methods SSAO --split holdout");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("no holdout/ split"), std::string::npos) << r.output;
  fs::remove_all(d);
}

// A run that fails part-way (here a file-size limit: the tables fit under it, the charts
// and the report do not, as on a disk that fills up) left its first files in OUT: in a
// new folder a results.csv with no report, in an earlier run's folder new tables beside
// the old report. Now OUT holds all of a run's files or none of them.
TEST(EvalAo, AWriteThatFailsPartWayLeavesTheFolderAsItWas) {
  fs::path d = temp_dir("full");
  write_three_splits(d / "data");
  const std::string args = "--data " + (d / "data").string() + " --methods SSAO --previews 1 --out ";
  CommandResult r = run(args + (d / "earlier").string());
  ASSERT_EQ(r.code, 0) << r.output;
  std::ofstream(d / "earlier" / "results.csv") << "the earlier run's";
  // dash counts the limit in 512-byte blocks; SIGXFSZ ignored, a write past it fails (EFBIG).
  const std::string limited = "trap '' XFSZ; ulimit -f 8; exec " + std::string(NNSHADE_BINARY_DIR) + "/bin/eval-ao ";
  for (const char* out : {"new", "earlier"}) {
    r = nns::testing::run_command(limited + args + (d / out).string());
    EXPECT_EQ(r.code, 1) << out << ":\n" << r.output;
    EXPECT_NE(r.output.find("File too large"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(d / "new")) << "a folder the failed run made goes with it";
  EXPECT_EQ(read(d / "earlier" / "results.csv"), "the earlier run's");
  for (auto& e : fs::directory_iterator(d / "earlier"))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << "left " << e.path();
  fs::remove_all(d);
}

// --temporal-blend adds every method's accumulated form ("<method>+TA"), scored from its
// own output: on a still camera path it changes less from frame to frame than the
// method itself, and its first frame is the method's.
TEST(EvalAo, TemporalAccumulationIsOfferedToEveryMethod) {
  fs::path d = temp_dir("ta");
  fs::create_directories(d / "data");
  for (int v = 0; v < 4; ++v) {
    auto view = nns::fixtures::synthetic_view(48, 32, v % 2, 8);  // the geometry alternates
    view.scene = "path";
    view.world_to_camera = std::array<float, 16>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    nns::data::write_view((d / "data" / ("path-p00-f00" + std::to_string(v) + ".exr")).string(), view);
  }
  CommandResult r = run("--data " + (d / "data").string() + " --out " + (d / "out").string() +
                        " --methods HBAO,GTAO --threads 2 --previews 0 --temporal-blend 0.25");
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string temporal = read(d / "out" / "temporal.csv");
  for (const char* m : {"HBAO", "GTAO"}) {
    auto flicker = [&](const std::string& name) {
      const size_t at = temporal.find("\n" + name + ",64,");
      EXPECT_NE(at, std::string::npos) << temporal;
      return std::stod(temporal.substr(temporal.find(',', at + name.size() + 2) + 1));
    };
    const double raw = flicker(m), acc = flicker(std::string(m) + "+TA");
    EXPECT_GT(raw, 0) << m;
    EXPECT_LT(acc, 0.8 * raw) << m << ": " << temporal;
  }
  EXPECT_NE(read(d / "out" / "results.csv").find("\nHBAO+TA,64,"), std::string::npos);
  EXPECT_EQ(run("--data " + (d / "data").string() + " --out " + (d / "bad").string() + " --temporal-blend 1.5").code,
            2);
  fs::remove_all(d);
}

// --vary-pattern: shader-style NNAO's jitter changes with the camera-path frame, so on a
// still path of identical frames its output changes from frame to frame (and the +TA
// form averages the patterns), where the fixed pattern gives the same frame every time.
TEST(EvalAo, VaryPatternChangesShaderStyleJitterPerFrame) {
  fs::path d = temp_dir("vary");
  fs::create_directories(d / "data");
  for (int v = 0; v < 3; ++v) {
    auto view = nns::fixtures::synthetic_view(48, 32, 0, 8);
    view.scene = "still";
    view.world_to_camera = std::array<float, 16>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    nns::data::write_view((d / "data" / ("still-p00-f00" + std::to_string(v) + ".exr")).string(), view);
  }
  nns::fixtures::random_nnao_blob(7, 4, 3).save((d / "m.blob").string());
  auto flicker = [&](const std::string& extra, const std::string& out) {
    CommandResult r =
        run("--data " + (d / "data").string() + " --model " + (d / "m.blob").string() + " --out " + (d / out).string() +
            " --methods NNAO --nnao-samples 16 --previews 0 --temporal-blend 0.5 " + extra);
    EXPECT_EQ(r.code, 0) << r.output;
    const std::string t = read(d / out / "temporal.csv");
    auto at = [&](const std::string& name) {
      const size_t k = t.find("\n" + name + ",16,");
      EXPECT_NE(k, std::string::npos) << t;
      return std::stod(t.substr(k + name.size() + 5));
    };
    return std::pair(at("NNAO"), at("NNAO+TA"));
  };
  const auto fixed = flicker("", "fixed"), varied = flicker("--vary-pattern", "varied");
  EXPECT_EQ(fixed.first, 0.0);
  EXPECT_GT(varied.first, 0.0);
  EXPECT_LT(varied.second, varied.first);
  fs::remove_all(d);
}

// A ladder of NNAO models (train-nnao --ladder's folder: ladder.csv and one folder per
// rung) is evaluated as one curve: every rung a row of results.csv with its name, and
// pareto.csv saying for every classical setting which rung beats it at no more wall time
// — a claim checked here against the rows themselves. export-nnao --ladder then picks a
// rung within a budget from times it measures, or says that none fits.
TEST(EvalAo, LadderIsOneCurveAndTheFrontNamesItsWins) {
  fs::path d = temp_dir("ladder");
  fs::create_directories(d / "data");
  for (int v = 0; v < 2; ++v) {
    auto view = nns::fixtures::synthetic_view(48, 32, 3, 16);
    nns::data::write_view((d / "data" / ("v" + std::to_string(v) + ".exr")).string(), view);
  }
  std::string csv =
      "rung,directions,steps,bands,hidden,downsample,blur_passes,samples_per_pixel,test_mse,val_mse,seconds\n";
  for (int s : {4, 2, 1}) {
    nns::Blob b = nns::fixtures::random_nnao_blob(0, 4, 11 + s, false, {8, 4, 2});
    b.set_config("downsample", s);
    const std::string name = "r" + std::to_string(s);
    fs::create_directories(d / "ladder" / name);
    b.save((d / "ladder" / name / "nnao.blob").string());
    csv += name + ",8,4,2,4," + std::to_string(s) + ",1," + std::to_string(32 / (s * s)) + ",,,\n";
  }
  std::ofstream(d / "ladder" / "ladder.csv") << csv;
  CommandResult r = run("--data " + (d / "data").string() + " --ladder " + (d / "ladder").string() + " --out " +
                        (d / "out").string() + " --methods NNAO-exact,SSAO,GTAO --previews 1 --repeat 1");
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string results = read(d / "out" / "results.csv");
  for (const char* rung : {"r4", "r2", "r1"})
    EXPECT_NE(results.find(std::string(",") + rung + "\n"), std::string::npos) << results;
  std::ifstream pareto(d / "out" / "pareto.csv");
  std::string line;
  std::getline(pareto, line);
  ASSERT_EQ(line, "method,setting,wall_ms,cpu_ms,mse,ssim,flicker_x_truth,on_front,beaten_by_nnao_at_no_more_time");
  struct Row {
    std::string method, setting;
    double ms, mse, ssim;
    std::string beaten_by;
  };
  std::vector<Row> rows;
  while (std::getline(pareto, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) f.push_back(c);
    if (line.back() == ',') f.push_back("");
    ASSERT_EQ(f.size(), 9u) << line;
    rows.push_back({f[0], f[1], std::stod(f[2]), std::stod(f[4]), std::stod(f[5]), f[8]});
  }
  ASSERT_EQ(rows.size(), 3u + 4 + 5);  // the rungs, SSAO at 4 counts, GTAO at 5
  for (auto& c : rows) {
    if (c.method == "NNAO-exact") {
      EXPECT_EQ(c.beaten_by, "");
      continue;
    }
    ASSERT_FALSE(c.beaten_by.empty()) << c.method;
    if (c.beaten_by == "none") continue;
    const auto w =
        std::find_if(rows.begin(), rows.end(), [&](const Row& q) { return "NNAO-exact@" + q.setting == c.beaten_by; });
    ASSERT_NE(w, rows.end()) << c.beaten_by;
    EXPECT_LE(w->ms, c.ms);
    EXPECT_LT(w->mse, c.mse);
    EXPECT_GT(w->ssim, c.ssim);
  }
  EXPECT_NE(read(d / "out" / "report.md").find("The speed/accuracy front"), std::string::npos);

  // The budget: a generous one ships the top rung (listed last), an impossible one nothing.
  const std::string base =
      "--ladder " + (d / "ladder").string() + " --view " + (d / "data" / "v0.exr").string() + " --size 64x40";
  CommandResult e =
      nns::testing::run_app("export-nnao", base + " --budget-ms 100000 --out " + (d / "shaders").string());
  ASSERT_EQ(e.code, 0) << e.output;
  EXPECT_NE(e.output.find("r1 "), std::string::npos) << e.output;
  EXPECT_NE(e.output.find("<- picked"), std::string::npos) << e.output;
  EXPECT_FALSE(fs::exists(d / "shaders" / "nnao_downsample.frag"));  // r1 runs at full resolution
  e = nns::testing::run_app("export-nnao", base + " --budget-ms 0.001 --out " + (d / "none").string());
  EXPECT_EQ(e.code, 1) << e.output;
  EXPECT_NE(e.output.find("no rung"), std::string::npos) << e.output;
  EXPECT_FALSE(fs::exists(d / "none" / "nnao.frag"));
  e = nns::testing::run_app("export-nnao", "--ladder " + (d / "ladder").string() + " --out " + (d / "x").string());
  EXPECT_EQ(e.code, 2) << e.output;  // a ladder without a budget
  fs::remove_all(d);
}
