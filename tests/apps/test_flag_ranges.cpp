// Every numeric flag has a range, checked where it is read (apps/args.h): a value out of
// range, a wrapped integer or a malformed list is refused with exit 2 and a message
// naming the flag, before any work. Each case below was once accepted:
// --epochs 4294967297 ran one epoch, --test-points-per-view -1 died in vector::reserve,
// --nnao-samples abc died in stoi, render-dataset --fov 180 wrote a dataset that
// dataset-info rejects, sweep-gan --ssim-tolerance -1 crashed after its sweep.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "core/blob.h"
#include "fixtures/random_nnao_blob.h"
#include "tests/support/run_command.h"

namespace fs = std::filesystem;
using nns::testing::run_app;

namespace {

struct Case {
  const char* app;
  const char* args;
  const char* expect;  // in the message
};

class FlagRanges : public ::testing::TestWithParam<Case> {};

TEST_P(FlagRanges, RefusedNamingTheFlag) {
  const Case c = GetParam();
  auto r = run_app(c.app, std::string(c.args) + " --out /nonexistent/never-written");
  EXPECT_EQ(r.code, 2) << c.app << " " << c.args << "\n" << r.output;
  EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.app << " " << c.args << "\n" << r.output;
  EXPECT_EQ(r.output.find("Segmentation"), std::string::npos) << r.output;
}

INSTANTIATE_TEST_SUITE_P(
    OnceAccepted, FlagRanges,
    ::testing::Values(
        Case{"train-nnao", "--epochs 4294967297", "--epochs: 4294967297 is out of range"},
        Case{"train-nnao", "--gamma -1", "--gamma: -1 is out of range: expected a number in [0, 3.40282e+38]"},
        Case{"train-nnao", "--radius -1", "--radius: -1 is out of range"},
        Case{"train-nnao", "--test-points-per-view -1", "--test-points-per-view: -1 is out of range"},
        Case{"train-nnao", "--test-points-per-view 0", "--test-points-per-view: 0 is out of range"},
        Case{"train-nnao", "--hidden 65", "--hidden: 65 is out of range: expected an integer in [1, 64]"},
        Case{"eval-ao", "--nnao-samples abc", "--nnao-samples: expected a comma-separated list of integers"},
        Case{"eval-ao", "--nnao-samples 0", "--nnao-samples: 0 is out of range"},
        Case{"eval-ao", "--nnao-samples 16,-16", "--nnao-samples: -16 is out of range"},
        Case{"export-nnao", "--samples -1", "--samples: -1 is out of range"},
        Case{"train-gan", "--size -16", "--size: -16 is out of range"},
        Case{"train-gan", "--lambda -1", "--lambda: -1 is out of range"},
        Case{"train-gan", "--decay-epochs -5", "--decay-epochs: -5 is out of range"},
        Case{"train-gan", "--max-frames -1", "--max-frames: -1 is out of range"},
        Case{"render-dataset", "--fov 0", "--fov: 0 is out of range: expected a number in [1, 179]"},
        Case{"render-dataset", "--fov 180", "--fov: 180 is out of range"},
        Case{"render-dataset", "--fov -10", "--fov: -10 is out of range"},
        Case{"render-dataset", "--test-fraction 1.5", "--test-fraction: 1.5 is out of range"},
        Case{"sweep-gan", "--epochs 0", "--epochs: 0 is out of range"},
        Case{"sweep-gan", "--ssim-tolerance -1", "--ssim-tolerance: -1 is out of range"},
        Case{"sweep-gan", "--sizes 16,x", "--sizes: expected a comma-separated list of integers"}));

// A real-valued flag was checked as a double and then narrowed to an infinite
// float; tune-classical-ao's counts had no range; an empty list ran nothing and exited 0;
// render-dataset --size 65536x65536 died in std::bad_alloc naming no flag.
INSTANTIATE_TEST_SUITE_P(
    RealFlagsNarrowedToFloat, FlagRanges,
    ::testing::Values(Case{"train-nnao", "--radius 1e39", "--radius: 1e39 is out of range"},
                      Case{"nnao-infer", "--depth-scale 1e39", "--depth-scale: 1e39 is out of range"},
                      Case{"gi-infer", "--depth-scale 1e39", "--depth-scale: 1e39 is out of range"},
                      Case{"import-blender", "--ao-radius 1e39 x.exr", "--ao-radius: 1e39 is out of range"},
                      Case{"tune-classical-ao", "--threads 100000", "--threads: 100000 is out of range"},
                      Case{"tune-classical-ao", "--threads 0", "--threads: 0 is out of range"},
                      Case{"tune-classical-ao", "--rounds 0", "--rounds: 0 is out of range"},
                      Case{"tune-classical-ao", "--rounds 4294967297", "--rounds: 4294967297 is out of range"},
                      Case{"tune-classical-ao", "--max-views -5", "--max-views: -5 is out of range"},
                      Case{"tune-classical-ao", "--methods ''", "--methods: no name in ''"},
                      Case{"eval-ao", "--methods ''", "--methods: no name in ''"},
                      Case{"eval-ao", "--methods ,", "--methods: no name in ','"},
                      Case{"render-dataset", "--size 65536x65536",
                           "--size: 65536x65536 is out of range: each side at most 16384"},
                      Case{"render-dataset", "--size 320x16385", "--size: 320x16385 is out of range"}));

// "--out ''" wrote eval-ao's eleven outputs into the current folder.
TEST(FlagRanges, AnEmptyOutputPathIsRefusedNamingTheFlag) {
  for (const char* app : {"eval-ao", "tune-classical-ao", "train-nnao", "train-gan", "export-nnao", "eval-gi",
                          "render-dataset", "nnao-infer", "gi-infer", "import-blender", "sweep-gan"}) {
    auto r = run_app(app, "--out ''");
    EXPECT_EQ(r.code, 2) << app << "\n" << r.output;
    EXPECT_NE(r.output.find("--out: expected a path, got ''"), std::string::npos) << app << "\n" << r.output;
  }
}

// The grid of a window-7 model has 49 cells: 100000000 samples used to be reported as
// asked while 49 ran.
TEST(FlagRanges, SampleCountAboveTheModelsGridIsRefused) {
  fs::path d = fs::temp_directory_path() / ("nnshade_flags_" + std::to_string(::getpid()));
  fs::create_directories(d);
  const std::string blob = (d / "nnao.blob").string();
  nns::fixtures::random_nnao_blob(7, 4, 1).save(blob);
  auto r = run_app("nnao-infer", "--model " + blob + " --in " + (d / "none.exr").string() + " --out " +
                                     (d / "o.exr").string() + " --samples 100000000");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("a window-7 model takes 1 to 49 filter samples"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "o.exr"));
  r = run_app("export-nnao", "--model " + blob + " --out " + (d / "x").string() + " --samples 64");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("--samples 64: a window-7 model"), std::string::npos) << r.output;
  fs::remove_all(d);
}

}  // namespace
