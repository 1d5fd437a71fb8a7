#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <OpenImageIO/imageio.h>

#include "report/image_write.h"
#include "support/image_bytes.h"

using namespace nns::report;
namespace fs = std::filesystem;

namespace {
std::string temp(const std::string& name) {
  return (fs::temp_directory_path() / ("nns_test_png_" + std::to_string(getpid()) + "_" + name)).string();
}
}  // namespace

TEST(ImageWrite, GrayRoundTripWithClampAndNaNMarker) {
  const float v[6] = {0.0f, 0.5f, 1.0f, 2.0f, -1.0f, NAN};
  std::string p = temp("gray.png");
  write_png_gray(p, v, 3, 2);
  int w, h;
  auto px = nns::testing::read_rgb8(p, &w, &h);
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

TEST(ImageWrite, ToneMapIsReinhardThenSrgb) {
  EXPECT_EQ(srgb_encode(0), 0);
  EXPECT_EQ(srgb_encode(1), 255);
  EXPECT_EQ(srgb_encode(0.2159f), 128);  // byte 128 is linear ((128/255 + 0.055) / 1.055)^2.4
  const float r[1] = {1.0f}, g[1] = {3.0f}, b[1] = {0.0f};
  std::string p = temp("rgb.png");
  write_png_rgb(p, r, g, b, 1, 1);
  int w, h;
  auto px = nns::testing::read_rgb8(p, &w, &h);
  fs::remove(p);
  EXPECT_EQ(px[0], srgb_encode(0.5f));   // 1 / (1 + 1)
  EXPECT_EQ(px[1], srgb_encode(0.75f));  // 3 / (1 + 3)
  EXPECT_EQ(px[2], 0);
}

TEST(ImageWrite, HeatmapRisesInLightness) {
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

TEST(ImageWrite, ErrorsNameTheFile) {
  const float v[1] = {0};
  try {
    write_png_gray("/nonexistent/dir/x.png", v, 1, 1);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("/nonexistent/dir/x.png: cannot open for writing", 0), 0u) << e.what();
  }
  try {
    write_png_gray(temp("x.unknownformat"), v, 1, 1);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("x.unknownformat: no image format"), std::string::npos) << e.what();
  }
}

namespace {
// Every pixel value as OpenImageIO reads it back, in the file's own integer codes.
std::vector<uint32_t> read_codes(const std::string& p, OIIO::TypeDesc* stored) {
  auto in = OIIO::ImageInput::open(p);
  if (!in) throw std::runtime_error(p + ": " + OIIO::geterror());
  const auto& s = in->spec();
  *stored = s.format;
  std::vector<uint16_t> v(size_t(s.width) * size_t(s.height) * size_t(s.nchannels));
  EXPECT_TRUE(in->read_image(0, 0, 0, s.nchannels, OIIO::TypeDesc::UINT16, v.data()));
  std::vector<uint32_t> out(v.begin(), v.end());
  if (s.format == OIIO::TypeDesc::UINT8)
    for (auto& c : out) c /= 257;  // OpenImageIO widens 8-bit code c to 257 c
  return out;
}
}  // namespace

// write_image keeps what the file type can hold: every 8-bit and 16-bit code comes back
// exactly (v = code / max written, rounded to the same code), the channel count too.
TEST(ImageWrite, PngRoundTripEightAndSixteenBits) {
  for (auto [type, max] : {std::pair{PixelType::u8, 255}, std::pair{PixelType::u16, 65535}}) {
    const int w = 7, h = 5, nc = 3;
    std::vector<float> px(size_t(w * h * nc));
    std::vector<uint32_t> want(px.size());
    for (size_t i = 0; i < px.size(); ++i) {
      want[i] = uint32_t((i * 2654435761u) % uint32_t(max + 1));  // spread over the whole range
      px[i] = float(want[i]) / float(max);
    }
    want[0] = uint32_t(max), px[0] = 1.7f;  // clamped
    want[1] = 0, px[1] = -0.2f;
    const std::string p = temp(max == 255 ? "rt8.png" : "rt16.png");
    write_image(p, w, h, {"R", "G", "B"}, px.data(), type);
    OIIO::TypeDesc stored;
    auto got = read_codes(p, &stored);
    fs::remove(p);
    EXPECT_EQ(stored, max == 255 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16);
    ASSERT_EQ(got.size(), want.size());
    for (size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i], want[i]) << "value " << i << ", " << max;
  }
}

// An image that cannot be written leaves the target as it was and no temporary behind.
TEST(ImageWrite, FailedWriteLeavesTheOldFileAndNoTemporary) {
  const std::string dir = temp("atomic_dir");
  fs::create_directories(dir);
  const std::string p = dir + "/image.png";
  std::ofstream(p) << "the old file";
  const float v[2] = {0, 1};
  // PNG holds 1 to 4 channels: five make OpenImageIO refuse after the temporary exists.
  EXPECT_THROW(write_image(p, 1, 1, {"a", "b", "c", "d", "e"}, v, PixelType::u8), std::runtime_error);
  std::ifstream in(p);
  std::string old((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(old, "the old file");
  int files = 0;
  for (auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1) << "a temporary was left in " << dir;
  write_png_gray(p, v, 2, 1);
  int w, h;
  EXPECT_EQ(nns::testing::read_rgb8(p, &w, &h)[3], 255);
  fs::remove_all(dir);
}
