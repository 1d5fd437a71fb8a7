// The example as a user runs it: export-nnao, then run-nnao-shader on a view EXR,
// against nnao-infer on the same view; and its errors. The pixel-exact comparison is
// test_nnao_glsl's: these commands are built with the project's flags, and GCC fuses
// multiply-adds that the shader rounds apart (docs/nnao.md), which can move a sample
// within rounding of a pixel edge to the neighbouring pixel; the blur spreads such a
// pixel over its 5 x 5 neighbours. So a few pixels may differ; any wrong binding moves
// most of them (test_nnao_glsl).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "data/exr_io.h"
#include "fixtures/random_nnao_blob.h"
#include "tests/gl/rendered_view.h"
#include "tests/support/run_command.h"

namespace fs = std::filesystem;
using namespace nns;
using nns::testing::run_app;

namespace {

class RunNnaoShader : public ::testing::Test {
 protected:
  void SetUp() override {
    setenv("LIBGL_ALWAYS_SOFTWARE", "1", 0);
    dir_ = fs::temp_directory_path() / ("run_nnao_shader_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    data::write_view(path("view.exr"), nns::testing::rendered_view());
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Pixels where the shader's and nnao-infer's images of the view differ by > 1e-4.
  int64_t shader_vs_cpu(const Blob& model, const std::string& samples_flag) {
    model.save(path("nnao.blob"));
    auto r = run_app("export-nnao", "--model " + path("nnao.blob") + " --out " + path("shaders"));
    EXPECT_EQ(r.code, 0) << r.output;
    r = run_app("run-nnao-shader", "--shaders " + path("shaders") + " --in " + path("view.exr") + " --out " +
                                       path("gl.exr") + " " + samples_flag);
    EXPECT_EQ(r.code, 0) << r.output;
    std::printf("%s", r.output.c_str());
    r = run_app("nnao-infer", "--model " + path("nnao.blob") + " --in " + path("view.exr") + " --out " +
                                  path("cpu.exr") + " " + samples_flag);
    EXPECT_EQ(r.code, 0) << r.output;
    const auto gl = data::read_view(path("gl.exr")).channel("AO"), cpu = data::read_view(path("cpu.exr")).channel("AO");
    EXPECT_EQ(gl.size(), cpu.size());
    int64_t off = 0;
    for (size_t i = 0; i < gl.size() && i < cpu.size(); ++i) off += !(std::abs(gl[i] - cpu[i]) <= 1e-4f);
    return off;
  }
  fs::path dir_;
};

TEST_F(RunNnaoShader, DrawsNnaoInfersImageForEitherKind) {
  using fixtures::random_nnao_blob, fixtures::spread_nnao_outputs;
  const int64_t grid = shader_vs_cpu(spread_nnao_outputs(random_nnao_blob(15, 4, 5), 40, 0.5f), "--samples 64");
  const int64_t horizon =
      shader_vs_cpu(spread_nnao_outputs(random_nnao_blob(0, 8, 6, false, {8, 4, 2}), 20, -0.3f), "");
  const int64_t pixels = int64_t(nns::testing::rendered_view().width) * nns::testing::rendered_view().height;
  std::printf("run-nnao-shader vs nnao-infer, pixels differing by > 1e-4: grid %lld, horizon %lld of %lld\n",
              (long long)grid, (long long)horizon, (long long)pixels);
  EXPECT_LE(grid, pixels / 100);
  EXPECT_LE(horizon, pixels / 100);
}

TEST_F(RunNnaoShader, MissingFilesAreNamed) {
  auto r =
      run_app("run-nnao-shader", "--shaders " + path("none") + " --in " + path("view.exr") + " --out " + path("o.exr"));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find(path("none") + "/nnao.frag"), std::string::npos) << r.output;
  fixtures::random_nnao_blob(9, 4, 1).save(path("nnao.blob"));
  ASSERT_EQ(run_app("export-nnao", "--model " + path("nnao.blob") + " --out " + path("shaders")).code, 0);
  fs::remove(path("shaders/nnao_filters.exr"));
  r = run_app("run-nnao-shader",
              "--shaders " + path("shaders") + " --in " + path("view.exr") + " --out " + path("o.exr"));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("nnao_filters.exr is missing"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("o.exr")));
}

}  // namespace
