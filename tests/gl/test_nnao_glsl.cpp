// The exported GLSL, run: export-nnao's passes drawn by Mesa on the CPU (EGL
// surfaceless, llvmpipe; examples/nnao_gl binds them as an engine would) on a view the
// ground-truth renderer made, against the CPU path nnao-infer runs. Pixels agree
// within a float tolerance, except where a sample lands within rounding of a pixel
// edge (the shader and the CPU may then read neighbouring pixels): those are counted,
// and every pixel that differs must be one of them. Without a context the tests fail,
// saying why.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "core/rng.h"
#include "examples/nnao_gl/headless_gl.h"
#include "examples/nnao_gl/nnao_gl.h"
#include "fixtures/random_nnao_blob.h"
#include "models/nnao/nnao_inference.h"
#include "runs/ao/nnao_export.h"
#include "tests/gl/edge_samples.h"
#include "tests/gl/rendered_view.h"

namespace fs = std::filesystem;
using namespace nns;

namespace {

// Built without FMA contraction (tests/CMakeLists.txt), the CPU path rounds as the
// shader does but for its order of addition (the H = 4 grid path keeps per-channel
// partial sums): the largest difference measured was 1.8e-6 (these random weights,
// layer 0 scaled up) and 5.4e-7 (trained models on dataset views; llvmpipe, LLVM 15;
// docs/nnao.md).
constexpr float kTolerance = 1e-5f;

std::unique_ptr<gl::HeadlessGl> g_context;
std::string g_context_error;

class NnaoGlsl : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (g_context || !g_context_error.empty()) return;
    setenv("LIBGL_ALWAYS_SOFTWARE", "1", 0);  // Mesa on the CPU, also where a GPU exists
    try {
      g_context = std::make_unique<gl::HeadlessGl>();
      std::printf("OpenGL renderer: %s\n", g_context->renderer().c_str());
    } catch (const std::exception& e) {
      g_context_error = e.what();
    }
  }
  void SetUp() override {
    if (!g_context) FAIL() << "no headless OpenGL context, so the exported shaders cannot run: " << g_context_error;
    dir_ = fs::temp_directory_path() / ("nnao_glsl_" + std::to_string(::getpid()));
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

nnao::NnaoWeights export_model(const Blob& blob, const fs::path& dir, int samples) {
  const nnao::NnaoWeights m = nnao::NnaoWeights::from_blob(blob);
  runs::write_export(m, dir.string(), samples);
  return m;
}

// Shader against CPU, pixel by pixel; `edge` marks the pixels allowed to differ.
struct Diff {
  int64_t off = 0;           // pixels differing by more than kTolerance
  int64_t off_not_edge = 0;  // of those, pixels not marked: a failure
  int64_t edge = 0;          // pixels marked
  double max_elsewhere = 0;  // largest difference on the unmarked pixels
  int64_t unclamped = 0;     // CPU values strictly inside (0, 1): what the comparison could see
};
Diff compare(const std::vector<float>& gpu, const std::vector<float>& cpu, const std::vector<bool>& edge) {
  Diff d;
  for (size_t i = 0; i < cpu.size(); ++i) {
    const double e = std::abs(double(gpu[i]) - cpu[i]);
    const bool off = !(e <= kTolerance);  // a NaN is off
    d.off += off;
    d.edge += edge[i];
    d.unclamped += cpu[i] > 0 && cpu[i] < 1;
    if (!edge[i]) {
      d.off_not_edge += off;
      d.max_elsewhere = std::max(d.max_elsewhere, std::isnan(e) ? INFINITY : e);
    }
  }
  return d;
}
void report(const char* what, const Diff& d, size_t pixels) {
  std::printf(
      "%-52s max |GPU - CPU| %.1e off the marked pixels; %lld of %zu differ by > %.0e (%lld unmarked); "
      "%lld marked; %lld unclamped\n",
      what, d.max_elsewhere, (long long)d.off, pixels, double(kTolerance), (long long)d.off_not_edge, (long long)d.edge,
      (long long)d.unclamped);
}

// The NNAO pass, the blur alone on the CPU's pass, then both passes as an engine runs
// them; returns the pass's comparison.
Diff check_passes(const nnao::NnaoWeights& m, const fs::path& dir, const data::View& view, int samples, uint32_t frame,
                  const char* name) {
  const screen_space::GBuffer g = screen_space::gbuffer_from_view(view);
  gl::NnaoGlPasses passes(dir.string());
  passes.set_gbuffer(g);
  std::vector<float> raw(size_t(g.pixels())), cpu(size_t(g.pixels())), cpu_blur(size_t(g.pixels()));
  std::vector<bool> edge;
  if (m.input.is_horizon()) {
    nnao::infer_horizon(m, g, raw.data());
    edge = nns::testing::horizon_edge_pixels(g, m.input.horizon);
  } else {
    nnao::infer_shader_style(m, g, samples, raw.data(), /*blur=*/false, frame);
    edge = nns::testing::grid_edge_pixels(g, m.input.window, samples, frame);
  }
  // The blur as nnao-infer applies it: m.blur_passes times for a horizon model.
  const int pairs = m.input.is_horizon() ? m.blur_passes : 1;
  std::vector<float> src = raw;
  for (int p = 0; p < pairs; ++p) {
    nnao::bilateral_blur(g, src.data(), cpu.data(), m.blur_edges);
    src = cpu;
  }
  const gl::NnaoGlPasses::Frame f{samples, frame};
  const Diff pass = compare(passes.ao_pass(f), raw, edge);
  report((std::string(name) + ", NNAO pass (marked: a sample near an edge)").c_str(), pass, raw.size());
  EXPECT_EQ(pass.off_not_edge, 0) << name << ": pixels differ away from pixel edges";
  EXPECT_GT(pass.unclamped, int64_t(raw.size() * 4 / 10))
      << name << ": the outputs are mostly clamped, hiding differences";

  const Diff blur = compare(passes.blur(raw), cpu, std::vector<bool>(raw.size(), false));
  report((std::string(name) + ", blur pass on the CPU's NNAO").c_str(), blur, raw.size());
  EXPECT_EQ(blur.off, 0) << name << ": the blur differs";

  // Both passes: a pixel whose blur footprint (5 x 5 per pair) holds a differing pass pixel may differ.
  const int reach = 2 * pairs;
  const std::vector<float> gpu_pass = passes.ao_pass(f);
  std::vector<bool> near_off(raw.size(), false);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      if (!(std::abs(gpu_pass[size_t(y) * g.width + x] - raw[size_t(y) * g.width + x]) > kTolerance)) continue;
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx)
          if (x + dx >= 0 && x + dx < g.width && y + dy >= 0 && y + dy < g.height)
            near_off[size_t(y + dy) * g.width + x + dx] = true;
    }
  const Diff both = compare(passes.run(f), cpu, near_off);
  report((std::string(name) + ", both passes (marked: near a differing pixel)").c_str(), both, raw.size());
  EXPECT_EQ(both.off_not_edge, 0) << name << ": the two passes differ away from the pass's differing pixels";
  return pass;
}

// The paper's size (window 31, hidden 4: the grid and paper presets), the sample counts
// and frames as uniforms; hidden 8 takes the CPU's general (not H = 4) path.
TEST_F(NnaoGlsl, GridModelMatchesTheCpuShaderStylePath) {
  using fixtures::random_nnao_blob, fixtures::spread_nnao_outputs;
  const auto m4 = export_model(spread_nnao_outputs(random_nnao_blob(31, 4, 21), 40, 0.5f), dir_ / "h4", 64);
  check_passes(m4, dir_ / "h4", nns::testing::rendered_view(), 64, 0, "grid w31 h4, 64 samples, frame 0");
  check_passes(m4, dir_ / "h4", nns::testing::rendered_view(), 128, 7, "grid w31 h4, 128 samples, frame 7");
  const auto m8 = export_model(spread_nnao_outputs(random_nnao_blob(15, 8, 22), 40, 0.5f), dir_ / "h8", 64);
  check_passes(m8, dir_ / "h8", nns::testing::rendered_view(), 32, 3, "grid w15 h8, 32 samples, frame 3");
}

// The default model's shape: 16 directions x 8 steps in 4 bands, hidden 16.
TEST_F(NnaoGlsl, HorizonModelMatchesTheCpuExactPath) {
  const fixtures::HorizonShape shape{16, 8, 4};
  const Blob blob = fixtures::spread_nnao_outputs(fixtures::random_nnao_blob(0, 16, 23, false, shape), 20, -0.3f);
  const auto m = export_model(blob, dir_, 64);
  check_passes(m, dir_, nns::testing::rendered_view(), 0, 0, "horizon d16 s8 b4 h16");
  // The default's 4 blur passes travel in nnao_blur.frag (NNAO_BLUR_PAIRS) to the host.
  Blob four = blob;
  four.set_config("blur_passes", 4);
  const auto m4 = export_model(four, dir_ / "b4", 64);
  ASSERT_EQ(m4.blur_passes, 4);
  check_passes(m4, dir_ / "b4", nns::testing::rendered_view(), 0, 0, "horizon d16 s8 b4 h16, 4 blur passes");
  // And so do its edge terms (BLUR_DEPTH, NNAO_BLUR_NORMAL_POWER).
  four.set_config("blur_depth", 0.3);
  four.set_config("blur_normal_power", 2);
  const auto loose = export_model(four, dir_ / "loose", 64);
  ASSERT_EQ(loose.blur_edges.normal_power, 2);
  check_passes(loose, dir_ / "loose", nns::testing::rendered_view(), 0, 0,
               "horizon d16 s8 b4 h16, 4 passes, depth 0.3, power 2");
  // And the radius term's ceiling (RADIUS_TERM_MAX), low enough to hold most pixels.
  four.set_config("radius_term_max", 0.2);
  const auto capped = export_model(four, dir_ / "capped", 64);
  ASSERT_EQ(capped.input.horizon.radius_term_max, 0.2f);
  check_passes(capped, dir_ / "capped", nns::testing::rendered_view(), 0, 0,
               "horizon d16 s8 b4 h16, radius term at most 0.2");
}

// A model at 1/s resolution: the downsample, the NNAO pass and the blur on the low
// frame, the guided upsample, drawn as an engine draws them, against the CPU path. The
// NNAO pass is compared on the low frame (marked: a sample near a pixel edge there); the
// whole chain at full resolution, where a pixel may differ only if a low pixel within
// the blur's and the upsample's reach differed.
void check_low_resolution(const nnao::NnaoWeights& m, const fs::path& dir, const data::View& view, const char* name) {
  const screen_space::GBuffer g = screen_space::gbuffer_from_view(view);
  const screen_space::LowResGBuffer lr = screen_space::downsample_gbuffer(g, m.downsample);
  gl::NnaoGlPasses passes(dir.string());
  ASSERT_EQ(passes.downsample(), m.downsample) << name;
  passes.set_gbuffer(g);
  std::vector<float> raw(size_t(lr.g.pixels())), cpu(size_t(g.pixels()));
  nnao::infer_horizon(m, lr.g, raw.data());
  const std::vector<bool> edge = nns::testing::horizon_edge_pixels(lr.g, m.input.horizon);
  const Diff pass = compare(passes.ao_pass({}), raw, edge);
  report((std::string(name) + ", NNAO pass on the low frame").c_str(), pass, raw.size());
  EXPECT_EQ(pass.off_not_edge, 0) << name;
  EXPECT_GT(pass.unclamped, int64_t(raw.size() * 4 / 10)) << name;
  nnao::infer_exact(m, g, cpu.data());
  const std::vector<float> gpu_pass = passes.ao_pass({});
  const int s = m.downsample, reach = 2 * m.blur_passes + 1;
  std::vector<bool> near_off(cpu.size(), false);
  for (int y = 0; y < lr.g.height; ++y)
    for (int x = 0; x < lr.g.width; ++x) {
      const size_t i = size_t(y) * lr.g.width + x;
      if (!(std::abs(gpu_pass[i] - raw[i]) > kTolerance)) continue;
      for (int fy = (y - reach) * s; fy <= (y + reach + 1) * s; ++fy)
        for (int fx = (x - reach) * s; fx <= (x + reach + 1) * s; ++fx)
          if (fx >= 0 && fx < g.width && fy >= 0 && fy < g.height) near_off[size_t(fy) * g.width + fx] = true;
    }
  const Diff all = compare(passes.run({}), cpu, near_off);
  report((std::string(name) + ", all passes at full resolution").c_str(), all, cpu.size());
  EXPECT_EQ(all.off_not_edge, 0) << name;
  EXPECT_GT(all.unclamped, int64_t(cpu.size() * 4 / 10)) << name;
}

TEST_F(NnaoGlsl, LowResolutionModelMatchesTheCpuPath) {
  Blob blob = fixtures::spread_nnao_outputs(fixtures::random_nnao_blob(0, 8, 31, false, {8, 8, 4}), 20, -0.3f);
  blob.set_config("blur_passes", 2);
  blob.set_config("blur_depth", 0.3);
  blob.set_config("blur_normal_power", 2);
  for (int s : {2, 4}) {
    blob.set_config("downsample", s);
    const fs::path dir = dir_ / ("s" + std::to_string(s));
    const auto m = export_model(blob, dir, 64);
    ASSERT_TRUE(fs::exists(dir / "nnao_downsample.frag") && fs::exists(dir / "nnao_upsample.frag"));
    check_low_resolution(m, dir, nns::testing::rendered_view(), s == 2 ? "d8 s8 h8 at 1/2" : "d8 s8 h8 at 1/4");
  }
  // Exported again at full resolution into the same folder: the resolution passes go.
  blob.set_config("downsample", 1);
  export_model(blob, dir_ / "s2", 64);
  EXPECT_FALSE(fs::exists(dir_ / "s2" / "nnao_downsample.frag"));
}

// The pair count travels as text in nnao_blur.frag: a count outside 1..16 is refused,
// naming the file, before anything is drawn.
TEST_F(NnaoGlsl, ABadBlurPairCountIsRefusedNamingTheFile) {
  const fixtures::HorizonShape shape{8, 4, 2};
  export_model(fixtures::random_nnao_blob(0, 4, 5, false, shape), dir_, 64);
  const fs::path blur = dir_ / "nnao_blur.frag";
  std::ifstream in(blur);
  std::stringstream text;
  text << in.rdbuf();
  std::string frag = text.str();
  const std::string key = "#define NNAO_BLUR_PAIRS 1\n";
  const size_t at = frag.find(key);
  ASSERT_NE(at, std::string::npos);
  frag.replace(at, key.size(), "#define NNAO_BLUR_PAIRS 0\n");
  std::ofstream(blur) << frag;
  try {
    gl::NnaoGlPasses passes(dir_.string());
    FAIL() << "a pair count of 0 was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(blur.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("NNAO_BLUR_PAIRS"), std::string::npos) << e.what();
  }
}

// The comparison catches what an engine could get wrong: a filter atlas transposed, a
// G-buffer uploaded upside down, normals with x and y swapped, the wrong frame's pattern.
TEST_F(NnaoGlsl, AWronglyBoundInputIsCaught) {
  const auto m = export_model(fixtures::spread_nnao_outputs(fixtures::random_nnao_blob(31, 4, 21), 40, 0.5f), dir_, 64);
  const data::View& v = nns::testing::rendered_view();
  const screen_space::GBuffer g = screen_space::gbuffer_from_view(v);
  std::vector<float> cpu(size_t(g.pixels()));
  nnao::infer_shader_style(m, g, 64, cpu.data(), /*blur=*/false, /*seed=*/0);
  const std::vector<bool> none(cpu.size(), false);
  auto off = [&](const screen_space::GBuffer& bound, uint32_t frame) {
    gl::NnaoGlPasses passes(dir_.string());
    passes.set_gbuffer(bound);
    const int64_t n = compare(passes.ao_pass({64, frame}), cpu, none).off;
    std::printf("  %lld of %zu pixels off\n", (long long)n, cpu.size());
    return n;
  };
  ASSERT_EQ(off(g, 0), 0);
  const int64_t many = int64_t(cpu.size() / 10);
  EXPECT_GT(off(g, 1), many) << "the frame uniform changes nothing";

  // Upside down: the CPU planes uploaded as they are stored would be, top row first.
  std::vector<float> planes[4];
  const float* src[4] = {g.z, g.nx, g.ny, g.nz};
  for (int c = 0; c < 4; ++c)
    for (int y = g.height - 1; y >= 0; --y)
      planes[c].insert(planes[c].end(), src[c] + int64_t(y) * g.width, src[c] + int64_t(y + 1) * g.width);
  screen_space::GBuffer flipped = g;
  flipped.z = planes[0].data(), flipped.nx = planes[1].data(), flipped.ny = planes[2].data(),
  flipped.nz = planes[3].data();
  EXPECT_GT(off(flipped, 0), many) << "an upside-down G-buffer goes unnoticed";
  screen_space::GBuffer swapped = g;
  swapped.nx = g.ny, swapped.ny = g.nx;
  EXPECT_GT(off(swapped, 0), many) << "normals with x and y swapped go unnoticed";

  // Each filter of the atlas transposed (grid column i <-> row j).
  const std::string atlas = (dir_ / "nnao_filters.exr").string();
  data::View f = data::read_view(atlas), t = f;
  const int w = m.input.window;
  for (auto& [name, plane] : t.channels)
    for (int k = 0; k < m.hidden; ++k)
      for (int j = 0; j < w; ++j)
        for (int i = 0; i < w; ++i)
          plane[size_t(j) * f.width + k * w + i] = f.channel(name)[size_t(i) * f.width + k * w + j];
  data::write_view(atlas, t);
  EXPECT_GT(off(g, 0), many) << "a transposed filter atlas goes unnoticed";
}

}  // namespace
