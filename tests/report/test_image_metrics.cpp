#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/rng.h"
#include "report/image_metrics.h"

using namespace nns::report;

TEST(ImageMetrics, MseAndPsnrHandComputed) {
  std::vector<float> a = {0, 0.5f, 1, 0.25f}, b = {0, 0.25f, 1, 1};
  std::vector<uint8_t> mask = {1, 1, 1, 0};
  EXPECT_NEAR(masked_mse(a.data(), b.data(), mask.data(), 4), 0.0625 / 3, 1e-9);
  EXPECT_NEAR(masked_mse(a.data(), b.data(), nullptr, 4), (0.0625 + 0.5625) / 4, 1e-9);
  EXPECT_NEAR(psnr_from_mse(0.01), 20.0, 1e-9);
  EXPECT_TRUE(std::isinf(psnr_from_mse(0)));
  std::vector<uint8_t> none = {0, 0, 0, 0};
  EXPECT_TRUE(std::isnan(masked_mse(a.data(), b.data(), none.data(), 4)));
}

TEST(ImageMetrics, SsimIsOneForIdenticalAndDropsWithNoise) {
  const int w = 32, h = 24;
  nns::Rng rng(3);
  std::vector<float> a(w * h), b(w * h), c(w * h);
  for (int i = 0; i < w * h; ++i) {
    a[i] = float(i % w) / w;
    b[i] = a[i];
    c[i] = a[i] + 0.2f * float(rng.normal());
  }
  EXPECT_NEAR(masked_ssim(a.data(), b.data(), nullptr, w, h), 1.0, 1e-9);
  double s = masked_ssim(a.data(), c.data(), nullptr, w, h);
  EXPECT_LT(s, 0.5);
  EXPECT_GT(s, -1.0);
}

TEST(ImageMetrics, SsimOfAConstantShiftMatchesTheFormula) {
  // Constant images x = 0.5, y = 0.6: variances are zero, SSIM = (2*0.3 + C1)/(0.61 + C1).
  const int w = 16, h = 16;
  std::vector<float> a(w * h, 0.5f), b(w * h, 0.6f);
  double C1 = 1e-4;
  EXPECT_NEAR(masked_ssim(a.data(), b.data(), nullptr, w, h), (0.6 + C1) / (0.61 + C1), 1e-5);
}

TEST(ImageMetrics, GradientErrorIsBlindToOffsetsAndCountsMovedSteps) {
  // 4 x 2 image: a step 0 | 1 between columns 1 and 2; the test moves it one column right.
  const int w = 4, h = 2;
  std::vector<float> truth = {0, 0, 1, 1, 0, 0, 1, 1}, moved = {0, 0, 0, 1, 0, 0, 0, 1};
  std::vector<float> offset(truth);
  for (float& v : offset) v += 0.25f;
  EXPECT_EQ(masked_gradient_error(truth.data(), offset.data(), nullptr, w, h), 0.0);
  // 10 differences (3 per row across, 4 down); per row the across differences change by
  // (0, -1, +1): |.| sums to 2 per row, 4 in all; the vertical ones are 0 in both. 4 / 10.
  EXPECT_NEAR(masked_gradient_error(truth.data(), moved.data(), nullptr, w, h), 0.4, 1e-12);
  // A mask keeps only pairs whose two pixels are selected: the top row's three pairs.
  std::vector<uint8_t> top = {1, 1, 1, 1, 0, 0, 0, 0};
  EXPECT_NEAR(masked_gradient_error(truth.data(), moved.data(), top.data(), w, h), 2.0 / 3, 1e-12);
  std::vector<uint8_t> lonely = {1, 0, 1, 0, 0, 0, 0, 0};
  EXPECT_TRUE(std::isnan(masked_gradient_error(truth.data(), moved.data(), lonely.data(), w, h)));
  // Symmetric in its arguments.
  EXPECT_EQ(masked_gradient_error(truth.data(), moved.data(), nullptr, w, h),
            masked_gradient_error(moved.data(), truth.data(), nullptr, w, h));
}
