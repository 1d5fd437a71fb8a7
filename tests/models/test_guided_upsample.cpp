// The guided upsample of a low-resolution GI prediction (models/gi/guided_upsample.h).
#include "models/gi/guided_upsample.h"

#include <gtest/gtest.h>

#include <cmath>

#include "runs/gi/gi_samples.h"

namespace {

using nns::Tensor;
using nns::data::View;

// A W x H view of planes facing the camera; depth(x, y) gives each pixel's depth.
template <class Depth>
View planes(int W, int H, Depth depth) {
  View v;
  v.width = W, v.height = H;
  v.fov_y_deg = 90;
  auto &z = v.add_channel("Z"), &nx = v.add_channel("N.X"), &ny = v.add_channel("N.Y"), &nz = v.add_channel("N.Z");
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y * W + x);
      z[i] = depth(x, y), nx[i] = 0, ny[i] = 0, nz[i] = 1;
    }
  return v;
}

Tensor<float> light_of(const View& low, int channels, float (*f)(float z, int x, int y)) {
  Tensor<float> t({channels, low.height, low.width});
  const int64_t n = int64_t(low.width) * low.height;
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < low.height; ++y)
      for (int x = 0; x < low.width; ++x)
        t[c * n + y * low.width + x] = f(low.channel("Z")[size_t(y * low.width + x)], x, y) * float(c + 1);
  return t;
}

}  // namespace

TEST(GuidedUpsample, AConstantStaysThatConstantSkyIncluded) {
  const View full = planes(24, 16, [](int x, int y) { return y < 4 ? INFINITY : 2.0f + 0.1f * float(x); });
  const View low = nns::runs::downsample_view(full, 4);
  const Tensor<float> up = nns::gi::guided_upsample(light_of(low, 3, [](float, int, int) { return 0.37f; }), low, full);
  ASSERT_EQ(up.size(1), 16);
  ASSERT_EQ(up.size(2), 24);
  for (int c = 0; c < 3; ++c)
    for (int64_t i = 0; i < 16 * 24; ++i) EXPECT_NEAR(up[c * 384 + i], 0.37f * float(c + 1), 1e-6f) << c << " " << i;
}

// Near plane dark, far plane lit: every full pixel keeps its own plane's light, also the
// ones whose bilinear neighbours lie across the edge, and when the edge splits a low pixel
// (whose box-filtered depth is then neither plane's). A plain bilinear upsample mixes them.
TEST(GuidedUpsample, LightDoesNotCrossADepthStep) {
  for (int edge : {8, 9, 10, 11}) {
    const View full = planes(24, 8, [edge](int x, int) { return x < edge ? 2.0f : 6.0f; });
    const View low = nns::runs::downsample_view(full, 2);
    const Tensor<float> lit = light_of(low, 1, [](float z, int, int) { return z < 3 ? 0.0f : (z > 5 ? 1.0f : 0.5f); });
    const Tensor<float> up = nns::gi::guided_upsample(lit, low, full);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 24; ++x) EXPECT_NEAR(up[y * 24 + x], x < edge ? 0.0f : 1.0f, 1e-6f) << edge << " " << x;
  }
}

// On one smooth surface the upsample is bilinear interpolation, which reproduces a linear
// ramp exactly away from the border (where the taps are clamped).
TEST(GuidedUpsample, ALinearRampOnOneSurfaceIsReproduced) {
  const int k = 4;
  const View full = planes(32, 16, [](int, int) { return 3.0f; });
  const View low = nns::runs::downsample_view(full, k);
  // The low pixel x stands at full coordinate (x + 1/2) k - 1/2.
  const Tensor<float> ramp = light_of(low, 1, [](float, int x, int y) {
    return 0.01f * ((float(x) + 0.5f) * 4 - 0.5f) + 0.02f * ((float(y) + 0.5f) * 4 - 0.5f);
  });
  const Tensor<float> up = nns::gi::guided_upsample(ramp, low, full);
  for (int y = k; y < 16 - k; ++y)
    for (int x = k; x < 32 - k; ++x)
      EXPECT_NEAR(up[y * 32 + x], 0.01f * float(x) + 0.02f * float(y), 1e-5f) << x << " " << y;
}

TEST(GuidedUpsample, SizesThatDoNotGoIntoEachOtherAreRefused) {
  const View full = planes(24, 16, [](int, int) { return 2.0f; });
  const View low = nns::runs::downsample_view(full, 2);
  Tensor<float> light({3, 8, 12});
  const View odd = planes(25, 16, [](int, int) { return 2.0f; });
  EXPECT_THROW(nns::gi::guided_upsample(light, low, odd), std::runtime_error);
}
