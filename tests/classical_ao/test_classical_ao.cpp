#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/thread_pool.h"
#include "report/image_metrics.h"
#include "classical_ao/methods.h"
#include "fixtures/synthetic_gbuffer.h"

using namespace nns;

namespace {

// An open floor filling the lower half of the screen (sky above): nothing occludes it.
data::View open_plane(int w, int h) {
  data::View v;
  v.width = w, v.height = h, v.fov_y_deg = 60, v.ao_radius = 1.0f, v.scene = "plane";
  auto& Z = v.add_channel("Z");
  auto& NY = v.add_channel("N.Y");
  v.add_channel("N.X");
  v.add_channel("N.Z");
  float ty = std::tan(30 * 3.14159265f / 180);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float dy = (1 - 2 * (y + 0.5f) / h) * ty;
      size_t i = size_t(y) * w + x;
      Z[i] = dy < -1e-3f ? 1.0f / -dy : INFINITY;  // floor at y = -1
      NY[i] = 1;
    }
  return v;
}

}  // namespace

TEST(ClassicalAo, OpenPlaneIsUnoccluded) {
  auto v = open_plane(64, 48);
  auto g = screen_space::gbuffer_from_view(v);
  std::vector<uint8_t> mask(size_t(g.pixels()));
  for (int64_t i = 0; i < g.pixels(); ++i) mask[size_t(i)] = !g.sky(i) && (i / 64) < 40;
  for (auto& m : classical_ao::classical_methods())
    for (int n : m.sample_counts) {
      std::vector<float> out(size_t(g.pixels()));
      m.run(g, n, out.data());
      double mean = report::masked_mean(out.data(), mask.data(), g.pixels());
      // 4 samples quantise a pixel's AO to quarters; the 4x4 blur averages 16 pixels.
      EXPECT_GT(mean, n >= 8 ? 0.85 : 0.75) << m.name << " " << n;
    }
}

TEST(ClassicalAo, CorrelatesWithRayTracedAo) {
  // Every method must follow the ray-traced AO of the synthetic scene: a clearly
  // positive correlation over the non-sky pixels at its largest sample count. (Mean
  // squared error is what eval-ao reports; crude SSAO need not beat a constant there.)
  auto v = nns::fixtures::synthetic_view(96, 64, 1, 128);
  auto g = screen_space::gbuffer_from_view(v);
  const auto& gt = v.channel("AO");
  for (auto& m : classical_ao::classical_methods()) {
    std::vector<float> out(size_t(g.pixels()));
    m.run(g, m.sample_counts.back(), out.data());
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0, n = 0;
    for (int64_t i = 0; i < g.pixels(); ++i) {
      if (g.sky(i)) continue;
      double a = out[size_t(i)], b = gt[size_t(i)];
      sa += a, sb += b, saa += a * a, sbb += b * b, sab += a * b, n += 1;
    }
    double cov = sab / n - sa / n * sb / n;
    double corr = cov / std::sqrt((saa / n - sa * sa / n / n) * (sbb / n - sb * sb / n / n));
    std::printf("[classical] %s@%d correlation with ground truth %.3f\n", m.name.c_str(), m.sample_counts.back(), corr);
    // Crytek's SSAO has no normal: at this scene's grazing view of the floor the samples
    // under the floor fail the range check, so it misses the crease (a known artifact).
    if (m.name != "SSAO") EXPECT_GT(corr, 0.3) << m.name;
  }
}

TEST(ClassicalAo, SameResultWithOneAndTwoThreads) {
  auto v = nns::fixtures::synthetic_view(64, 40, 2, 8);
  auto g = screen_space::gbuffer_from_view(v);
  for (auto& m : classical_ao::classical_methods()) {
    std::vector<float> a(size_t(g.pixels())), b(size_t(g.pixels()));
    set_num_threads(1);
    m.run(g, 16, a.data());
    set_num_threads(2);
    m.run(g, 16, b.data());
    EXPECT_EQ(a, b) << m.name;
  }
}

TEST(ClassicalAo, GBufferRejectsNanDepthAndMissingRadius) {
  auto v = open_plane(8, 8);
  v.source = "bad.exr";
  v.channels["Z"][10] = NAN;
  try {
    screen_space::gbuffer_from_view(v);
    FAIL() << "NaN depth accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.exr"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("NaN"), std::string::npos);
  }
  auto w = open_plane(8, 8);
  w.ao_radius.reset();
  EXPECT_THROW(screen_space::gbuffer_from_view(w), std::runtime_error);
}

TEST(ClassicalAo, ProjectionInvertsPosition) {
  auto v = open_plane(40, 30);
  auto g = screen_space::gbuffer_from_view(v);
  Vec3 p = g.position(7.0f, 25.0f, 3.5f);
  float px, py;
  g.project(p, px, py);
  EXPECT_NEAR(px, 7.0f, 1e-4);
  EXPECT_NEAR(py, 25.0f, 1e-4);
}

namespace {

// How far a vectorised method may stray from its scalar reference: the arithmetic is
// the same expression for expression, but the vector code multiplies by reciprocals
// where the reference divides, and the compiler fuses multiply-adds differently; a
// sample on an exact half-pixel boundary may then round to the neighbouring pixel. So:
// almost every pixel equal to float precision, and the few others still close.
void expect_matches_reference(const std::vector<float>& fast, const std::vector<float>& ref, const std::string& what) {
  ASSERT_EQ(fast.size(), ref.size());
  size_t off = 0;
  double max_diff = 0, sum_diff = 0;
  for (size_t i = 0; i < ref.size(); ++i) {
    double d = std::abs(double(fast[i]) - ref[i]);
    ASSERT_FALSE(std::isnan(fast[i])) << what << " pixel " << i;
    off += d > 1e-5;
    max_diff = std::max(max_diff, d);
    sum_diff += d;
  }
  std::printf("[vector vs scalar] %s: %zu of %zu pixels differ by > 1e-5, max %.3g, mean %.3g\n", what.c_str(), off,
              ref.size(), max_diff, sum_diff / double(ref.size()));
  EXPECT_LE(double(off), 0.005 * double(ref.size())) << what;
  EXPECT_LT(sum_diff / double(ref.size()), 1e-4) << what;
  EXPECT_LT(max_diff, 0.1) << what;
}

}  // namespace

TEST(ClassicalAo, VectorisedMethodsMatchScalarReferences) {
  // 100 wide: six full 16-pixel blocks and a 4-pixel tail per row.
  for (int seed : {1, 2}) {
    auto v = nns::fixtures::synthetic_view(100, 60, seed, 8);
    auto g = screen_space::gbuffer_from_view(v);
    struct Pair {
      const char* name;
      void (*fast)(const screen_space::GBuffer&, int, float*);
      void (*ref)(const screen_space::GBuffer&, int, float*);
    };
    const Pair pairs[] = {{"SSAO", classical_ao::ssao, classical_ao::ssao_reference},
                          {"SSAO+", classical_ao::ssao_plus, classical_ao::ssao_plus_reference},
                          {"HBAO", classical_ao::hbao, classical_ao::hbao_reference},
                          {"Alchemy", classical_ao::alchemy_ao, classical_ao::alchemy_ao_reference},
                          {"GTAO", classical_ao::gtao, classical_ao::gtao_reference}};
    for (auto& p : pairs)
      for (int n : {4, 16, 64}) {
        std::vector<float> a(size_t(g.pixels())), b(size_t(g.pixels()));
        p.fast(g, n, a.data());
        p.ref(g, n, b.data());
        expect_matches_reference(a, b, std::string(p.name) + "@" + std::to_string(n) + " seed " + std::to_string(seed));
      }
  }
}

TEST(ClassicalAo, VectorisedBoxBlurIsBitwiseTheReference) {
  auto v = nns::fixtures::synthetic_view(37, 21, 3, 8);  // a 5-pixel tail, sky and edges
  auto g = screen_space::gbuffer_from_view(v);
  std::vector<float> in(size_t(g.pixels())), a(in.size()), b(in.size());
  for (size_t i = 0; i < in.size(); ++i) in[i] = float((i * 7919) % 101) / 100.0f;
  screen_space::box_blur_4x4(g, in.data(), a.data());
  screen_space::box_blur_4x4_reference(g, in.data(), b.data());
  EXPECT_EQ(a, b);
}
