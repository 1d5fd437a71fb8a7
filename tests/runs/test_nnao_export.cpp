#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "data/exr_io.h"
#include "runs/ao/nnao_export.h"
#include "fixtures/random_nnao_blob.h"

namespace fs = std::filesystem;
using namespace nns;
namespace fixtures = nns::fixtures;

TEST(NnaoExport, FilterImagesHoldTheFoldedWeights) {
  auto m = nnao::NnaoWeights::from_blob(nns::fixtures::random_nnao_blob(9, 4, 11));
  fs::path d = fs::temp_directory_path() / ("nnao_export_" + std::to_string(::getpid()));
  runs::write_filter_images(m, d.string());
  for (int k = 0; k < 4; ++k) {
    auto v = data::read_view((d / ("filter" + std::to_string(k) + ".exr")).string());
    ASSERT_EQ(v.width, 9);
    const auto& a = v.channel("A");
    const auto& r = v.channel("R");
    // Grid point (i=2, j=5): depth weight in A, Nx weight in R.
    EXPECT_EQ(a[5 * 9 + 2], m.w0[size_t(k) * m.features() + (5 * 9 + 2) * 4 + 3]);
    EXPECT_EQ(r[5 * 9 + 2], m.w0[size_t(k) * m.features() + (5 * 9 + 2) * 4 + 0]);
    EXPECT_TRUE(fs::exists(d / ("filter" + std::to_string(k) + ".png")));
  }
  auto atlas = data::read_view((d / "nnao_filters.exr").string());
  EXPECT_EQ(atlas.width, 36);
  EXPECT_EQ(atlas.channel("G")[3 * 36 + 2 * 9 + 4], m.w0[size_t(2) * m.features() + (3 * 9 + 4) * 4 + 1]);
  fs::remove_all(d);
}

// Both passes of both model kinds; tests/gl runs them and compares with the CPU.
TEST(NnaoExport, GlslShadersCompileWithGlslangValidator) {
  if (std::system("command -v glslangValidator > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "glslangValidator not installed (Debian glslang-tools)";
  fs::path d = fs::temp_directory_path() / ("nnao_glsl_" + std::to_string(::getpid()));
  fs::create_directories(d);
  auto compiles = [&](const std::string& name, const std::string& src) {
    fs::path f = d / (name + ".frag");
    std::ofstream(f) << src;
    std::string cmd = "glslangValidator " + f.string() + " > " + (d / "log.txt").string() + " 2>&1";
    int rc = std::system(cmd.c_str());
    std::ifstream log(d / "log.txt");
    std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
    EXPECT_EQ(rc, 0) << name << ": " << text;
  };
  for (int hidden : {4, 8})
    for (int samples : {64, 256}) {
      auto m = nnao::NnaoWeights::from_blob(nns::fixtures::random_nnao_blob(31, hidden, 12));
      std::string src = runs::glsl_grid_pass(m, samples);
      EXPECT_NE(src.find("const int W = 31;"), std::string::npos);
      EXPECT_NE(src.find("uniform int uSamples = " + std::to_string(samples) + ";"), std::string::npos);
      compiles("grid_" + std::to_string(hidden) + "_" + std::to_string(samples), src);
    }
  const fixtures::HorizonShape shape{16, 8, 4};
  compiles("horizon",
           runs::glsl_horizon_pass(nnao::NnaoWeights::from_blob(fixtures::random_nnao_blob(0, 16, 3, false, shape))));
  compiles("blur", runs::glsl_blur_pass());
  // And a broken shader must fail, so the check above can fail.
  std::ofstream(d / "bad.frag") << "#version 330 core\nvoid main() { undefined_call(); }\n";
  EXPECT_NE(std::system(("glslangValidator " + (d / "bad.frag").string() + " > /dev/null 2>&1").c_str()), 0);
  fs::remove_all(d);
}

// export-nnao's folder: both passes for either kind; the filter images only for a grid.
TEST(NnaoExport, WritesBothPassesForEitherKind) {
  fs::path d = fs::temp_directory_path() / ("nnao_export_kinds_" + std::to_string(::getpid()));
  runs::write_export(nnao::NnaoWeights::from_blob(fixtures::random_nnao_blob(9, 4, 1)), (d / "grid").string(), 64);
  const fixtures::HorizonShape shape{8, 4, 2};
  runs::write_export(nnao::NnaoWeights::from_blob(fixtures::random_nnao_blob(0, 8, 2, false, shape)),
                     (d / "horizon").string(), 64);
  for (const char* f : {"nnao.frag", "nnao_blur.frag", "nnao_filters.exr", "filter3.exr"})
    EXPECT_TRUE(fs::exists(d / "grid" / f)) << f;
  for (const char* f : {"nnao.frag", "nnao_blur.frag"}) EXPECT_TRUE(fs::exists(d / "horizon" / f)) << f;
  EXPECT_FALSE(fs::exists(d / "horizon" / "nnao_filters.exr"));
  std::ifstream in(d / "horizon" / "nnao.frag");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("const int DIRS = 8, STEPS = 4, BANDS = 2, F = 20;"), std::string::npos);
  fs::remove_all(d);
}
