// eval-gi sets aside frames with no light on their front geometry (nothing to predict;
// PSNR infinite for direct+env, a constant ambient loses there by construction).
#include <gtest/gtest.h>

#include "runs/gi/eval_gi.h"
#include "tests/support/csv_line.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::runs;

TEST(GiEvaluate, UnlitMeansNoLightOnGeometry) {
  GiSample s;
  s.target_linear = Tensor<float>({3, 2, 2});
  s.geometry = {1, 1, 0, 1};
  EXPECT_TRUE(unlit(s));
  s.target_linear[2] = 0.5f;  // channel R, pixel 2: sky, does not count
  EXPECT_TRUE(unlit(s));
  s.target_linear[2 * 4 + 3] = 1e-4f;  // channel B, pixel 3: geometry
  EXPECT_FALSE(unlit(s));
}

// The distance bands of eval-gi: a front view with a box in front of a wall (a depth
// jump) and a crease, each pixel in the band of its Chebyshev distance to the break.
TEST(GiEvaluate, DistanceBandsFollowDepthJumpsAndCreases) {
  EXPECT_EQ(DistanceBands::name(0), "0-1");
  EXPECT_EQ(DistanceBands::name(3), "8-15");
  EXPECT_EQ(DistanceBands::name(4), "16+");
  EXPECT_EQ(DistanceBands::band_of(0), 0);
  EXPECT_EQ(DistanceBands::band_of(1), 0);
  EXPECT_EQ(DistanceBands::band_of(2), 1);
  EXPECT_EQ(DistanceBands::band_of(7), 2);
  EXPECT_EQ(DistanceBands::band_of(15), 3);
  EXPECT_EQ(DistanceBands::band_of(16), 4);
  EXPECT_EQ(DistanceBands::band_of(screen_space::kNoSeed), 4);

  // 48 x 4: a wall at depth 10 (normal +z) for x < 40; x >= 40 a side wall at depth 10,
  // normal +x (a crease at x = 39|40); column 0 sky.
  const int w = 48, h = 4;
  GiSample s;
  data::View& v = s.front_geometry;
  v.width = w, v.height = h, v.fov_y_deg = 60;
  auto& z = v.add_channel("Z");
  auto& nx = v.add_channel("N.X");
  v.add_channel("N.Y");
  auto& nz = v.add_channel("N.Z");
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y * w + x);
      z[i] = x == 0 ? INFINITY : 10.0f;
      (x >= 40 ? nx : nz)[i] = 1;
    }
  const std::vector<int8_t> band = distance_bands_of(s);
  auto expected = [](int x) {
    if (x == 0) return -1;
    const int d = std::min(x - 1, x < 40 ? 39 - x : x - 40);  // to the sky edge (x = 1) or the crease
    return DistanceBands::band_of(d);
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) ASSERT_EQ(band[size_t(y * w + x)], expected(x)) << x;

  // Pooling: a prediction off by 0.1 in every channel on the band-0 pixels only.
  std::vector<float> truth(size_t(3 * w * h), 0.5f), pred = truth, flip(size_t(w * h), 0.25f);
  std::vector<uint8_t> geometry(size_t(w * h), 1);
  for (int y = 0; y < h; ++y) geometry[size_t(y * w)] = 0;
  for (size_t c = 0; c < 3; ++c)
    for (size_t i = 0; i < size_t(w * h); ++i)
      if (band[i] == 0) pred[c * size_t(w * h) + i] += 0.1f;
  DistanceBands bands;
  add_to_bands(bands, band, pred, truth, flip, geometry);
  // band 0: x = 1, 2 (sky edge) and 38..41 (crease): 6 columns of 4 rows.
  EXPECT_EQ(bands.pixels[0], 24);
  EXPECT_NEAR(bands.mse(0), 0.01, 1e-6);
  EXPECT_EQ(bands.mse(1), 0.0);
  EXPECT_NEAR(bands.mean_flip(2), 0.25, 1e-12);
  EXPECT_NEAR(bands.share(0), 24.0 / (47 * 4), 1e-12);
}

// --best-gain: a prediction whose indirect light is the truth's times a colour cast is
// brought back to the truth exactly; sky pixels do not enter the fit.
TEST(GiEvaluate, BestGainUndoesAPerChannelScaleOfTheIndirectLight) {
  GiSample s;
  s.geometry = {1, 1, 0, 1};
  s.direct_env = Tensor<float>({3, 2, 2});
  s.target_linear = Tensor<float>({3, 2, 2});
  Tensor<float> light({3, 2, 2});
  const float cast[3] = {2.0f, 0.5f, 1.0f};
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 4; ++i) {
      const int k = c * 4 + i;
      s.direct_env[k] = 0.1f * float(i + c);
      const float indirect = 0.2f + 0.05f * float(i * (c + 1));
      s.target_linear[k] = s.direct_env[k] + indirect;
      light[k] = s.direct_env[k] + cast[c] * indirect;
    }
  light[2] = 50.0f;  // sky: any value, not fitted, scaled like the rest
  Tensor<float> fitted = best_gain_light(light, s);
  for (int k : {0, 1, 3, 4, 5, 7, 8, 9, 11}) EXPECT_NEAR(fitted[k], s.target_linear[k], 1e-6f) << k;
  // no indirect light predicted: nothing to scale, the light is kept
  Tensor<float> flat = s.direct_env.clone();
  Tensor<float> kept = best_gain_light(flat, s);
  for (int64_t k = 0; k < 12; ++k) EXPECT_EQ(kept[k], flat[k]);
}

// A model label from a folder with a comma (and a quote) shifted every later column of
// its rows in results.csv, results_by_family.csv and results_by_distance.csv.
TEST(GiEvaluate, CsvFilesKeepTheirColumnsWhateverTheModelIsCalled) {
  EvalRow r;
  r.model = "runs/a,b \"new\"/G @64 guided";
  r.mode = "surround";
  r.frames = 2;
  LightMetrics m;
  m.mse = 0.01, m.ssim = 0.9;
  r.by_family["arcade,2"].add(m);
  for (const std::string& text :
       {results_csv({r}, false), results_csv({r}, true), family_csv({r}), distance_csv({r})}) {
    const auto lines = nns::testing::csv_lines(text);
    ASSERT_GE(lines.size(), 2u) << text;
    const size_t columns = nns::testing::csv_fields(lines[0]).size();
    for (size_t i = 1; i < lines.size(); ++i) {
      const auto f = nns::testing::csv_fields(lines[i]);
      EXPECT_EQ(f.size(), columns) << lines[i];
      EXPECT_EQ(f[0], r.model) << lines[i];
    }
  }
  EXPECT_EQ(nns::testing::csv_fields(nns::testing::csv_lines(family_csv({r}))[1])[1], "arcade,2");
}
