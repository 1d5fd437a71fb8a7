// ꟻLIP (report/flip.h): values worked out by hand from the paper's formulas, the filters'
// normalisation, the symmetries the construction implies, and what it sees that MSE does not.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/rng.h"
#include "report/flip.h"

using namespace nns::report;

namespace {

constexpr int kW = 32, kH = 32;
constexpr size_t kN = size_t(kW) * kH;

std::vector<float> constant(float r, float g, float b) {
  std::vector<float> img(3 * kN);
  for (size_t i = 0; i < kN; ++i) img[i] = r, img[kN + i] = g, img[2 * kN + i] = b;
  return img;
}

std::vector<float> noise(uint64_t seed) {
  nns::Rng rng(seed);
  std::vector<float> img(3 * kN);
  for (float& v : img) v = float(rng.uniform());
  return img;
}

double mean(const std::vector<float>& v) {
  double s = 0;
  for (float x : v) s += x;
  return s / double(v.size());
}

double mse(const std::vector<float>& a, const std::vector<float>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
  return s / double(a.size());
}

// A grey vertical edge: `lo` left of column `at`, `hi` from it on (linear RGB).
std::vector<float> edge(float lo, float hi, int at) {
  std::vector<float> img(3 * kN);
  for (size_t c = 0; c < 3; ++c)
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) img[c * kN + size_t(y) * kW + size_t(x)] = x < at ? lo : hi;
  return img;
}

}  // namespace

TEST(Flip, DefaultObserverIs67PixelsPerDegree) {
  // p = 0.7 m * (3840 px / 0.7 m) * pi / 180 = 3840 pi / 180.
  EXPECT_NEAR(kFlipDefaultPpd, 3840 * 3.14159265358979 / 180, 1e-9);
  EXPECT_NEAR(kFlipDefaultPpd, 67.0206, 1e-4);
}

TEST(Flip, CsfKernelsSumToOneAndLeaveAConstantImageUnchanged) {
  for (const auto& k : {flip::kCsfAchromatic, flip::kCsfRedGreen, flip::kCsfBlueYellow}) {
    const auto terms = flip::csf_kernel(k, kFlipDefaultPpd);
    ASSERT_FALSE(terms.empty());
    // radius ceil(3 sqrt(0.04 / (2 pi^2)) 67.02) = ceil(9.05) = 10: 21 taps.
    EXPECT_EQ(terms[0].taps.size(), 21u);
    double sum = 0;
    for (const auto& t : terms)
      for (double tx : t.taps)
        for (double ty : t.taps) sum += t.weight * tx * ty;
    EXPECT_NEAR(sum, 1.0, 1e-12);
    std::vector<float> flat(kN, 37.5f);
    for (float v : flip::filter_csf(flat, kW, kH, terms)) ASSERT_NEAR(v, 37.5f, 1e-4f);
  }
  // Blue-yellow is the sum of two Gaussians (a2 = 13.5), the others one.
  EXPECT_EQ(flip::csf_kernel(flip::kCsfBlueYellow, kFlipDefaultPpd).size(), 2u);
  EXPECT_EQ(flip::csf_kernel(flip::kCsfAchromatic, kFlipDefaultPpd).size(), 1u);
}

TEST(Flip, FeatureKernelsAreNormalisedPerSign) {
  // sd = 0.5 * 0.082 * 67.02 = 2.748 px, radius ceil(3 sd) = 9: 19 taps.
  const auto k = flip::feature_kernels(kFlipDefaultPpd);
  ASSERT_EQ(k.gaussian.size(), 19u);
  double g = 0;
  for (double t : k.gaussian) g += t;
  EXPECT_NEAR(g, 1.0, 1e-12);
  for (const auto* taps : {&k.edge, &k.point}) {
    double pos = 0, neg = 0;
    for (double t : *taps) (t > 0 ? pos : neg) += t;
    EXPECT_NEAR(pos, 1.0, 1e-12);
    EXPECT_NEAR(neg, -1.0, 1e-12);
  }
  // A constant image has no features: each detector sums to 0.
  std::vector<float> flat(kN, 0.4f);
  for (float v : flip::filter_separable(flat, kW, kH, k.point, k.gaussian)) ASSERT_NEAR(v, 0.0f, 1e-6f);
}

TEST(Flip, IdenticalImagesScoreZero) {
  const auto a = noise(1);
  for (float v : flip_map(a.data(), a.data(), kW, kH)) ASSERT_EQ(v, 0.0f);
  EXPECT_EQ(masked_flip(a.data(), a.data(), nullptr, kW, kH), 0.0);
}

// Constant images: the CSFs leave them unchanged and they have no features (deltaE_f = 0),
// so every pixel scores the colour term alone.
TEST(Flip, MidGreyAgainstBlackIsTheColourTermWorkedByHand) {
  // sRGB 0.5 -> linear ((0.5 + 0.055) / 1.055)^2.4 = 0.214041; grey, so X/Xn = Y/Yn = Z/Zn.
  // L* = 116 * 0.214041^(1/3) - 16 = 53.3890, a* = b* = 0; black: L* = 116 * 4/29 - 16 = 0.
  // HyAB = 53.3890, ^0.7 = 16.1889.
  // cmax: Hunt-adjusted green (87.7362, -75.6099, 72.9812), blue (32.2982, 25.5781, -34.8364):
  // HyAB = 55.4380 + hypot(101.1880, 107.8176) = 203.3017, ^0.7 = 41.2761; knee pc cmax = 16.5104.
  // 16.1889 < 16.5104: deltaE_c = 0.95 * 16.1889 / 16.5104 = 0.93150.
  const auto grey = constant(0.5f, 0.5f, 0.5f), black = constant(0, 0, 0);
  for (float v : flip_map_srgb(grey.data(), black.data(), kW, kH)) ASSERT_NEAR(v, 0.93150, 2e-4);
  EXPECT_NEAR(flip::cmax(), 41.2761, 1e-3);
}

TEST(Flip, RedAgainstBlackTakesTheUpperBranchOfTheRemap) {
  // Linear red (1, 0, 0): Hunt-adjusted L*a*b* (53.2369, 42.6393, 35.7755); against black
  // HyAB = 53.2369 + hypot(42.6393, 35.7755) = 108.8965, ^0.7 = 26.6630 > knee 16.5104:
  // deltaE_c = 0.95 + (26.6630 - 16.5104) / (41.2761 - 16.5104) * 0.05 = 0.97050.
  const auto red = constant(1, 0, 0), black = constant(0, 0, 0);
  for (float v : flip_map_srgb(red.data(), black.data(), kW, kH)) ASSERT_NEAR(v, 0.97050, 2e-4);
  // Green against blue is cmax itself: the largest error, 1.
  const auto green = constant(0, 1, 0), blue = constant(0, 0, 1);
  for (float v : flip_map(green.data(), blue.data(), kW, kH)) ASSERT_NEAR(v, 1.0, 1e-5);
}

TEST(Flip, ErrorIsInTheUnitInterval) {
  for (uint64_t seed = 2; seed < 6; ++seed) {
    const auto a = noise(seed), b = noise(seed + 100);
    for (float v : flip_map(a.data(), b.data(), kW, kH)) {
      ASSERT_GE(v, 0.0f);
      ASSERT_LE(v, 1.0f);
    }
  }
  // Out-of-range input is clamped to [0, 1], not extrapolated.
  const auto hot = constant(5, -2, 3), white = constant(1, 0, 1);
  for (float v : flip_map(hot.data(), white.data(), kW, kH)) ASSERT_EQ(v, 0.0f);
}

// HyAB and |magnitude difference| are symmetric in their arguments, so swapping reference
// and test changes no bit.
TEST(Flip, SwappingReferenceAndTestChangesNothing) {
  const auto a = noise(7), b = noise(8);
  EXPECT_EQ(flip_map(a.data(), b.data(), kW, kH), flip_map(b.data(), a.data(), kW, kH));
}

// Every kernel is symmetric or antisymmetric in x and the pair (x-kernel, y-kernel) is the
// same along both axes, and only magnitudes of feature responses are used: mirroring or
// transposing both images mirrors or transposes the map (up to summation order).
TEST(Flip, MirroringOrTransposingBothImagesDoesTheSameToTheMap) {
  const auto a = noise(9), b = noise(10);
  auto mirror = [](const std::vector<float>& img, int planes) {
    std::vector<float> out(img.size());
    for (int c = 0; c < planes; ++c)
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
          out[size_t(c) * kN + size_t(y) * kW + size_t(x)] = img[size_t(c) * kN + size_t(y) * kW + size_t(kW - 1 - x)];
    return out;
  };
  auto transpose = [](const std::vector<float>& img, int planes) {  // kW == kH
    std::vector<float> out(img.size());
    for (int c = 0; c < planes; ++c)
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
          out[size_t(c) * kN + size_t(y) * kW + size_t(x)] = img[size_t(c) * kN + size_t(x) * kW + size_t(y)];
    return out;
  };
  const auto map = flip_map(a.data(), b.data(), kW, kH);
  const auto mirrored = flip_map(mirror(a, 3).data(), mirror(b, 3).data(), kW, kH);
  const auto transposed = flip_map(transpose(a, 3).data(), transpose(b, 3).data(), kW, kH);
  const auto m1 = mirror(map, 1), t1 = transpose(map, 1);
  for (size_t i = 0; i < kN; ++i) {
    ASSERT_NEAR(mirrored[i], m1[i], 1e-5f) << i;
    ASSERT_NEAR(transposed[i], t1[i], 1e-5f) << i;
  }
}

// Where MSE is blind: an edge moved by one pixel and a pixel-scale checkerboard of the same
// MSE are equal to MSE, but the checkerboard is above the CSFs' cut-off at 67 ppd (nobody
// flipping between the images would see it) while the moved edge is plain. The same for a
// lost one-pixel dark line, a contact shadow. ꟻLIP rates both structural errors at over 10x
// the checkerboard (0.057 against 0.003 for the 0.2|0.8 edge, here and in a separate NumPy
// transcription of the reference code's formulas).
TEST(Flip, AMovedEdgeScoresFarAboveInvisibleNoiseOfEqualMse) {
  const auto truth = edge(0.2f, 0.8f, kW / 2), moved = edge(0.2f, 0.8f, kW / 2 + 1);
  const double d = std::sqrt(mse(truth, moved));  // 0.6 / sqrt(32)
  std::vector<float> checker = truth;
  for (size_t c = 0; c < 3; ++c)
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) checker[c * kN + size_t(y) * kW + size_t(x)] += float((x + y) % 2 ? -d : d);
  ASSERT_NEAR(mse(truth, checker), mse(truth, moved), 1e-6);
  const double f_edge = mean(flip_map(truth.data(), moved.data(), kW, kH));
  const double f_checker = mean(flip_map(truth.data(), checker.data(), kW, kH));
  EXPECT_GT(f_edge, 10 * f_checker) << f_edge << " " << f_checker;

  std::vector<float> line = constant(0.5f, 0.5f, 0.5f), flat = line;
  for (size_t c = 0; c < 3; ++c)
    for (int y = 0; y < kH; ++y) line[c * kN + size_t(y) * kW + kW / 2] = 0.3f;
  std::vector<float> line_checker = line;
  const double dl = std::sqrt(mse(line, flat));
  for (size_t c = 0; c < 3; ++c)
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) line_checker[c * kN + size_t(y) * kW + size_t(x)] += float((x + y) % 2 ? -dl : dl);
  EXPECT_GT(mean(flip_map(line.data(), flat.data(), kW, kH)),
            10 * mean(flip_map(line.data(), line_checker.data(), kW, kH)));
}

// What ꟻLIP does *not* do, pinned so nobody reads the wrong thing into it: at equal MSE a
// uniform brightness change over the whole image scores higher than a moved edge. The
// colour term is concave in the difference (HyAB^0.7 of L*, itself a cube root), so error
// spread thin over every pixel weighs more than the same squared error on one column
// (0.229 against 0.057; the NumPy transcription gives 0.2288 and 0.0566). The gradient
// error (image_metrics.h) is the measure that ranks the moved edge above the offset.
TEST(Flip, AUniformChangeOfEqualMseScoresAboveAMovedEdge) {
  const auto truth = edge(0.2f, 0.8f, kW / 2), moved = edge(0.2f, 0.8f, kW / 2 + 1);
  const float d = float(std::sqrt(mse(truth, moved)));
  std::vector<float> brighter = truth;
  for (float& v : brighter) v += d;
  const double f_edge = mean(flip_map(truth.data(), moved.data(), kW, kH));
  const double f_uniform = mean(flip_map(truth.data(), brighter.data(), kW, kH));
  EXPECT_GT(f_uniform, f_edge);
  EXPECT_NEAR(f_edge, 0.0566, 2e-3);
  EXPECT_NEAR(f_uniform, 0.2288, 2e-3);
  // The gradient error of the offset is 0 (up to the float rounding of x + d), of the moved edge positive.
  EXPECT_NEAR(masked_gradient_error(truth.data(), brighter.data(), nullptr, kW, kH), 0.0, 1e-6);
  EXPECT_GT(masked_gradient_error(truth.data(), moved.data(), nullptr, kW, kH), 0.0);
}

TEST(Flip, MaskSelectsThePixelsAveraged) {
  const auto grey = constant(0.5f, 0.5f, 0.5f), black = constant(0, 0, 0);
  std::vector<uint8_t> mask(kN, 0);
  EXPECT_TRUE(std::isnan(masked_flip(grey.data(), black.data(), mask.data(), kW, kH)));
  mask[5] = 1;
  EXPECT_NEAR(masked_flip(grey.data(), grey.data(), mask.data(), kW, kH), 0.0, 0.0);
}
