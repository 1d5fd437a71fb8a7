// NNAO at 1/s of the frame's resolution (screen_space/low_resolution.h): the G-buffer's
// downsample, the guided upsample against its scalar loop and against what it must do on
// closed-form frames (a constant stays constant, light does not cross a depth step), and
// a low-resolution horizon model's vector path against its per-pixel reference.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/thread_pool.h"
#include "fixtures/random_nnao_blob.h"
#include "fixtures/synthetic_gbuffer.h"
#include "models/nnao/nnao_inference.h"
#include "models/nnao/nnao_inference_reference.h"
#include "screen_space/low_resolution.h"

using namespace nns;

namespace {

// A frame of two fronto-parallel planes: depth 2 left of column `edge`, depth 6 right.
struct TwoPlanes {
  int w, h;
  std::vector<float> z, nx, ny, nz;
  screen_space::GBuffer g;
  TwoPlanes(int w_, int h_, int edge)
      : w(w_), h(h_), z(size_t(w_ * h_)), nx(z.size(), 0), ny(z.size(), 0), nz(z.size(), 1) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) z[size_t(y * w + x)] = x < edge ? 2.0f : 6.0f;
    g = screen_space::make_gbuffer(w, h, 60, 0.5f, z.data(), nx.data(), ny.data(), nz.data());
  }
};

}  // namespace

TEST(LowResolution, DownsampleTakesOnePixelOfEveryBlock) {
  auto v = fixtures::synthetic_view(37, 21, 0, 1);
  const screen_space::GBuffer g = screen_space::gbuffer_from_view(v);
  for (int s : {2, 4}) {
    const screen_space::LowResGBuffer lr = screen_space::downsample_gbuffer(g, s);
    EXPECT_EQ(lr.g.width, (37 + s - 1) / s);
    EXPECT_EQ(lr.g.height, (21 + s - 1) / s);
    EXPECT_EQ(lr.g.sx, g.sx);
    EXPECT_EQ(lr.g.radius, g.radius);
    for (int y = 0; y < lr.g.height; ++y)
      for (int x = 0; x < lr.g.width; ++x) {
        const int fx = std::min(36, x * s + s / 2), fy = std::min(20, y * s + s / 2);
        const size_t i = size_t(y * lr.g.width + x), j = size_t(fy * 37 + fx);
        ASSERT_EQ(lr.z[i], g.z[j]) << s << " " << x << " " << y;
        ASSERT_EQ(lr.nz[i], g.nz[j]);
      }
  }
}

TEST(LowResolution, UpsampleOfAConstantIsThatConstant) {
  auto v = fixtures::synthetic_view(40, 24, 3, 1);
  const screen_space::GBuffer g = screen_space::gbuffer_from_view(v);
  const screen_space::LowResGBuffer lr = screen_space::downsample_gbuffer(g, 2);
  std::vector<float> low(size_t(lr.g.pixels()), 0.37f), out(size_t(g.pixels()));
  screen_space::upsample(g, lr, low.data(), out.data());
  int64_t surface = 0;
  for (int64_t i = 0; i < g.pixels(); ++i) {
    if (g.sky(i)) {
      EXPECT_EQ(out[size_t(i)], 1.0f);
      continue;
    }
    ++surface;
    EXPECT_NEAR(out[size_t(i)], 0.37f, 1e-6f) << i;
  }
  EXPECT_GT(surface, g.pixels() / 2);
}

TEST(LowResolution, UpsampleDoesNotCarryLightAcrossADepthStep) {
  // Near plane dark (0), far plane lit (1) at low resolution; at full resolution every
  // pixel must keep its own plane's value, also the ones beside the edge whose bilinear
  // neighbours lie on the other plane. A plain bilinear upsample mixes them.
  for (int edge : {9, 10, 11}) {
    TwoPlanes f(24, 8, edge);
    const screen_space::LowResGBuffer lr = screen_space::downsample_gbuffer(f.g, 2);
    std::vector<float> low(size_t(lr.g.pixels())), out(size_t(f.g.pixels()));
    for (size_t i = 0; i < low.size(); ++i) low[i] = lr.z[i] < 3 ? 0.0f : 1.0f;
    screen_space::upsample(f.g, lr, low.data(), out.data());
    for (int y = 0; y < f.h; ++y)
      for (int x = 0; x < f.w; ++x)
        EXPECT_NEAR(out[size_t(y * f.w + x)], x < edge ? 0.0f : 1.0f, 1e-6f) << edge << " " << x;
  }
}

TEST(LowResolution, VectorUpsampleMatchesTheScalarLoop) {
  for (int variant : {0, 3})
    for (int s : {2, 4}) {
      auto v = fixtures::synthetic_view(53, 29, variant, 1);
      const screen_space::GBuffer g = screen_space::gbuffer_from_view(v);
      const screen_space::LowResGBuffer lr = screen_space::downsample_gbuffer(g, s);
      std::vector<float> low(size_t(lr.g.pixels()));
      for (size_t i = 0; i < low.size(); ++i) low[i] = float((i * 7919) % 101) / 100.0f;
      std::vector<float> a(size_t(g.pixels())), b(a.size()), c(a.size());
      for (int normal_power : {0, 2, 8}) {
        const screen_space::UpsampleEdges e{0.3f, normal_power};
        set_num_threads(1);
        screen_space::upsample(g, lr, low.data(), a.data(), e);
        set_num_threads(2);
        screen_space::upsample(g, lr, low.data(), c.data(), e);
        EXPECT_EQ(a, c);
        screen_space::upsample_reference(g, lr, low.data(), b.data(), e);
        double worst = 0;
        for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(double(a[i]) - b[i]));
        // exp_nonpositive against std::exp: a few float ulps in each weight.
        EXPECT_LT(worst, 2e-6) << "variant " << variant << " s " << s << " power " << normal_power;
      }
    }
}

TEST(LowResolution, LowResolutionModelMatchesItsReference) {
  Blob blob = fixtures::spread_nnao_outputs(fixtures::random_nnao_blob(0, 8, 29, false, {8, 8, 4}), 10.0f, -0.3f);
  for (int s : {2, 4}) {
    blob.set_config("downsample", s);
    blob.set_config("blur_passes", 2);
    const auto m = nnao::NnaoWeights::from_blob(blob);
    ASSERT_EQ(m.downsample, s);
    auto v = fixtures::synthetic_view(64, 36, 3, 1);
    const screen_space::GBuffer g = screen_space::gbuffer_from_view(v);
    std::vector<float> a(size_t(g.pixels())), b(a.size());
    nnao::infer_exact(m, g, a.data());
    nnao::infer_exact_reference(m, g, b.data());
    double worst = 0;
    int64_t inside = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      worst = std::max(worst, std::abs(double(a[i]) - b[i]));
      inside += a[i] > 0.02f && a[i] < 0.98f;
    }
    EXPECT_LT(worst, 1e-4) << s;
    EXPECT_GT(inside, g.pixels() / 4) << s;  // not clamped flat: the comparison means something
    // Not the full-resolution model's image: the passes ran on the low frame.
    auto full = m;
    full.downsample = 1;
    nnao::infer_exact(full, g, b.data());
    EXPECT_NE(a, b);
  }
}

TEST(LowResolution, BlobRefusesADownsampleOtherThan124) {
  Blob blob = fixtures::random_nnao_blob(0, 8, 29, false, {8, 8, 4});
  for (int s : {0, 3, 8, -2}) {
    blob.set_config("downsample", s);
    EXPECT_THROW(nnao::NnaoWeights::from_blob(blob), std::runtime_error) << s;
  }
}
