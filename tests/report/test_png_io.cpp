#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "report/png_io.h"

using namespace nns::data;
namespace fs = std::filesystem;

namespace {
std::string temp(const std::string& name) {
  return (fs::temp_directory_path() / ("nns_test_png_" + std::to_string(getpid()) + "_" + name)).string();
}
}  // namespace

TEST(PngIo, GrayRoundTripWithClampAndNaNMarker) {
  const float v[6] = {0.0f, 0.5f, 1.0f, 2.0f, -1.0f, NAN};
  std::string p = temp("gray.png");
  write_png_gray(p, v, 3, 2);
  int w, h;
  auto px = read_png_rgb8(p, &w, &h);
  fs::remove(p);
  ASSERT_EQ(w, 3);
  ASSERT_EQ(h, 2);
  EXPECT_EQ(px[0], 0);
  EXPECT_EQ(px[3], 128);
  EXPECT_EQ(px[6], 255);
  EXPECT_EQ(px[9], 255);   // clamped
  EXPECT_EQ(px[12], 0);    // clamped
  EXPECT_EQ(px[15], 255);  // NaN: magenta
  EXPECT_EQ(px[16], 0);
  EXPECT_EQ(px[17], 255);
}

TEST(PngIo, ToneMapIsReinhardThenSrgb) {
  EXPECT_EQ(srgb_encode(0), 0);
  EXPECT_EQ(srgb_encode(1), 255);
  EXPECT_EQ(srgb_encode(0.2159f), 128);  // byte 128 is linear ((128/255 + 0.055) / 1.055)^2.4
  const float r[1] = {1.0f}, g[1] = {3.0f}, b[1] = {0.0f};
  std::string p = temp("rgb.png");
  write_png_rgb(p, r, g, b, 1, 1);
  int w, h;
  auto px = read_png_rgb8(p, &w, &h);
  fs::remove(p);
  EXPECT_EQ(px[0], srgb_encode(0.5f));   // 1 / (1 + 1)
  EXPECT_EQ(px[1], srgb_encode(0.75f));  // 3 / (1 + 3)
  EXPECT_EQ(px[2], 0);
}

TEST(PngIo, HeatmapRisesInLightness) {
  int last = -1;
  for (int i = 0; i <= 20; ++i) {
    uint8_t c[3];
    heatmap_colour(float(i) / 20, c);
    int lightness = 2 * c[0] + 5 * c[1] + c[2];
    EXPECT_GT(lightness, last) << i;
    last = lightness;
  }
  EXPECT_THROW(write_png_heatmap(temp("bad.png"), nullptr, 1, 1, 0), std::invalid_argument);
}

TEST(PngIo, ErrorsNameTheFile) {
  const float v[1] = {0};
  try {
    write_png_gray("/nonexistent/dir/x.png", v, 1, 1);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/dir/x.png: cannot open for writing");
  }
}
