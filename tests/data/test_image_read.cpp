// data/image_read.h: a user's images (PNG 8/16-bit, TIFF, HDR, EXR with its own channel
// names) into a View, each value decoded as the header documents; and every refusal
// names the file and the problem. The images are written by the test through the one
// image writer (report/image_write.h).
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "data/image_read.h"
#include "report/image_write.h"

namespace fs = std::filesystem;
using namespace nns::data;
using namespace nns::report;

namespace {

class ImageRead : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nns_image_read_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // A w x h image whose value (pixel i, channel c) is f(i, c).
  template <class F>
  std::string image(const std::string& name, int w, int h, std::vector<std::string> channels, PixelType t, F f) {
    std::vector<float> px(size_t(w * h) * channels.size());
    for (size_t i = 0; i < size_t(w * h); ++i)
      for (size_t c = 0; c < channels.size(); ++c) px[i * channels.size() + c] = f(i, c);
    write_image(path(name), w, h, channels, px.data(), t);
    return path(name);
  }
  static ImageViewOptions options(std::vector<std::string> targets, std::vector<std::string> optional = {}) {
    ImageViewOptions o;
    o.fov_y_deg = 60;
    o.targets = std::move(targets);
    o.optional = std::move(optional);
    o.command = "test";
    return o;
  }
  // The error of view_from_images, "" when it succeeded.
  static std::string error_of(const std::vector<std::string>& flags, const ImageViewOptions& o) {
    try {
      std::vector<ChannelMapping> m;
      for (auto& f : flags) m.push_back(parse_channel_mapping(f));
      view_from_images(m, o);
      return "";
    } catch (const std::exception& e) {
      return e.what();
    }
  }
  fs::path dir_;
};

void expect_contains(const std::string& text, std::initializer_list<std::string> parts) {
  EXPECT_FALSE(text.empty()) << "no error";
  for (auto& p : parts) EXPECT_NE(text.find(p), std::string::npos) << "'" << p << "' not in: " << text;
}

}  // namespace

TEST(ChannelMapping, ParsesTargetFileAndChannels) {
  auto m = parse_channel_mapping("normal=out/n.exr:N.X,N.Y,N.Z");
  EXPECT_EQ(m.target, "normal");
  EXPECT_EQ(m.file, "out/n.exr");
  EXPECT_EQ(m.channels, (std::vector<std::string>{"N.X", "N.Y", "N.Z"}));
  m = parse_channel_mapping("depth=a=b.png");  // only the first '=' separates
  EXPECT_EQ(m.file, "a=b.png");
  EXPECT_TRUE(m.channels.empty());
  m = parse_channel_mapping("depth=odd:dir/d.png");  // a ':' before a '/' belongs to the path
  EXPECT_EQ(m.file, "odd:dir/d.png");
  EXPECT_TRUE(m.channels.empty());
  for (const char* bad : {"depth", "=d.png", "depth=", "depth=d.png:", "depth=d.png:R,,G", "depth=:R"})
    EXPECT_THROW(parse_channel_mapping(bad), std::runtime_error) << bad;
  try {
    parse_channel_mapping("normal=n.png:R,,B");
  } catch (const std::exception& e) {
    expect_contains(e.what(), {"--channel 'normal=n.png:R,,B'", "empty channel name"});
  }
}

// 16-bit depth (code 0 = sky, else code/65535 * scale), 8-bit normals (2 code/255 - 1,
// normalised), 8-bit albedo (sRGB), HDR direct light and EXR emission under their own
// names (float: as stored), float TIFF env light.
TEST_F(ImageRead, EachFormatDecodesAsDocumented) {
  const int w = 4, h = 3;
  auto code16 = [](size_t i) { return i == 5 ? 0.0f : float(1000 * i + 7); };
  const std::string depth =
      image("d.png", w, h, {"Y"}, PixelType::u16, [&](size_t i, size_t) { return code16(i) / 65535.0f; });
  const uint8_t n8[3] = {200, 30, 128};
  const std::string normal =
      image("n.png", w, h, {"R", "G", "B"}, PixelType::u8, [&](size_t, size_t c) { return n8[c] / 255.0f; });
  const std::string albedo = image("a.png", w, h, {"R", "G", "B", "A"}, PixelType::u8,
                                   [&](size_t i, size_t c) { return c == 3 ? 0.5f : float(i * 20 + c) / 255.0f; });
  const std::string direct = image("l.hdr", w, h, {"R", "G", "B"}, PixelType::f32,
                                   [&](size_t i, size_t c) { return 0.5f * float(i + c); });  // RGBE-exact values
  const std::string emis = image("e.exr", w, h, {"glow.r", "glow.g", "glow.b", "junk"}, PixelType::f32,
                                 [&](size_t i, size_t c) { return 0.01f * float(i) + float(c) - 7.0f * (c == 3); });
  const std::string env = image("env.tif", w, h, {"R", "G", "B"}, PixelType::f32,
                                [&](size_t i, size_t c) { return 1e-3f * float(i * 3 + c); });
  ImageViewOptions o = options({"depth", "normal", "albedo", "direct"}, {"emission", "env"});
  o.depth_scale = 20;
  std::vector<ChannelMapping> m;
  for (std::string f : {"depth=" + depth, "normal=" + normal, "albedo=" + albedo, "direct=" + direct,
                        "emission=" + emis + ":glow.r,glow.g,glow.b", "env=" + env})
    m.push_back(parse_channel_mapping(f));
  View v = view_from_images(m, o);
  ASSERT_EQ(v.width, w);
  ASSERT_EQ(v.height, h);
  EXPECT_EQ(v.fov_y_deg, 60.0f);
  EXPECT_EQ(v.scene, "d");
  auto srgb = [](float s) { return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f); };
  float nx = 2 * n8[0] / 255.0f - 1, ny = 2 * n8[1] / 255.0f - 1, nz = 2 * n8[2] / 255.0f - 1;
  const float len = std::sqrt(nx * nx + ny * ny + nz * nz);
  for (size_t i = 0; i < size_t(w * h); ++i) {
    if (i == 5) EXPECT_TRUE(std::isinf(v.channel("Z")[i]));
    else EXPECT_FLOAT_EQ(v.channel("Z")[i], code16(i) / 65535.0f * 20) << i;
    EXPECT_FLOAT_EQ(v.channel("N.X")[i], nx / len);
    EXPECT_FLOAT_EQ(v.channel("N.Y")[i], ny / len);
    EXPECT_FLOAT_EQ(v.channel("N.Z")[i], nz / len);
    for (size_t c = 0; c < 3; ++c) {
      const std::string ch(1, "RGB"[c]);
      EXPECT_NEAR(v.channel("albedo." + ch)[i], srgb(float(i * 20 + c) / 255.0f), 1e-6f) << i;
      EXPECT_EQ(v.channel("direct." + ch)[i], 0.5f * float(i + c)) << i;
      EXPECT_EQ(v.channel("emission." + ch)[i], 0.01f * float(i) + float(c)) << i;
      EXPECT_EQ(v.channel("env." + ch)[i], 1e-3f * float(i * 3 + c)) << i;
    }
  }
  EXPECT_NE(v.source.find(depth), std::string::npos);
  EXPECT_NE(v.source.find(env), std::string::npos);
}

// One file may fill several targets, each from its own channels, and is read once.
TEST_F(ImageRead, OneExrWithItsOwnNamesFillsDepthAndNormals) {
  const std::string g = image("g.exr", 3, 2, {"depth.V", "nrm.x", "nrm.y", "nrm.z"}, PixelType::f32,
                              [](size_t i, size_t c) { return c == 0 ? 1.5f + float(i) : (c == 3 ? 1.0f : 0.0f); });
  View v = view_from_images(
      {parse_channel_mapping("depth=" + g + ":depth.V"), parse_channel_mapping("normal=" + g + ":nrm.x,nrm.y,nrm.z")},
      options({"depth", "normal"}));
  EXPECT_EQ(v.channel("Z")[4], 5.5f);
  EXPECT_EQ(v.channel("N.Z")[4], 1.0f);
  EXPECT_EQ(v.source, g);
}

TEST_F(ImageRead, RefusalsNameTheFileAndTheProblem) {
  const auto o = options({"depth", "normal"});
  const std::string n = image("n.exr", 4, 3, {"N.X", "N.Y", "N.Z"}, PixelType::f32,
                              [](size_t, size_t c) { return c == 2 ? 1.0f : 0.0f; });
  const std::string d = image("d.exr", 4, 3, {"Z"}, PixelType::f32, [](size_t, size_t) { return 2.0f; });
  ASSERT_EQ(error_of({"depth=" + d, "normal=" + n}, o), "");

  // A channel the file does not have: named, with the ones it has.
  expect_contains(error_of({"depth=" + d, "normal=" + n + ":N.X,N.Y,N.W"}, o),
                  {n, "no channel 'N.W'", "N.X, N.Y, N.Z"});
  // Too few channels named for the target.
  expect_contains(error_of({"depth=" + d, "normal=" + n + ":N.X,N.Y"}, o), {"normal takes 3 channels, 2 given"});
  // A file with more channels than the target, and none named: which ones is ambiguous.
  expect_contains(error_of({"depth=" + n, "normal=" + n}, o),
                  {n, "has 3 channels (N.X, N.Y, N.Z) but depth takes 1", "--channel depth=" + n + ":N.X"});
  // Sizes that differ.
  const std::string small = image("small.exr", 2, 3, {"Z"}, PixelType::f32, [](size_t, size_t) { return 2.0f; });
  expect_contains(error_of({"depth=" + small, "normal=" + n}, o), {n, "is 4x3", small, "2x3"});
  // NaN, zero or negative depth: the pixel and the file.
  const std::string nan =
      image("nan.exr", 4, 3, {"Z"}, PixelType::f32, [](size_t i, size_t) { return i == 6 ? NAN : 2.0f; });
  expect_contains(error_of({"depth=" + nan, "normal=" + n}, o), {nan, "depth", "NaN", "x=2, y=1"});
  const std::string neg =
      image("neg.exr", 4, 3, {"Z"}, PixelType::f32, [](size_t i, size_t) { return i == 1 ? -1.0f : 2.0f; });
  expect_contains(error_of({"depth=" + neg, "normal=" + n}, o), {neg, "x=1, y=0", "depth must be > 0"});
  // A NaN normal.
  const std::string nann = image("nann.exr", 4, 3, {"R", "G", "B"}, PixelType::f32,
                                 [](size_t i, size_t c) { return i == 0 && c == 1 ? NAN : 0.5f; });
  expect_contains(error_of({"depth=" + d, "normal=" + nann}, o), {nann, "normal", "NaN", "x=0, y=0"});
  // Integer depth needs a unit.
  const std::string d16 = image("d16.png", 4, 3, {"Y"}, PixelType::u16, [](size_t, size_t) { return 0.5f; });
  expect_contains(error_of({"depth=" + d16, "normal=" + n}, o), {d16, "--depth-scale"});
  // Targets: unknown, twice, missing; no field of view.
  expect_contains(error_of({"depth=" + d, "normal=" + n, "albedo=" + n}, o),
                  {"unknown target 'albedo'", "test takes depth, normal"});
  expect_contains(error_of({"depth=" + d, "depth=" + d, "normal=" + n}, o), {"depth is given twice"});
  expect_contains(error_of({"depth=" + d}, o), {"no --channel normal=FILE"});
  auto no_fov = o;
  no_fov.fov_y_deg = 0;
  expect_contains(error_of({"depth=" + d, "normal=" + n}, no_fov), {"--fov-y is required"});
  // Not there, a folder, not an image.
  expect_contains(error_of({"depth=" + path("none.png"), "normal=" + n}, o), {path("none.png"), "no such file"});
  expect_contains(error_of({"depth=" + dir_.string(), "normal=" + n}, o), {dir_.string(), "not a regular file"});
  std::ofstream(path("text.png")) << "not an image at all";
  expect_contains(error_of({"depth=" + path("text.png"), "normal=" + n}, o),
                  {path("text.png"), "cannot read it as png", "Not a PNG file"});
  // Only the four formats, by the name: a JPEG (which OpenImageIO reads) is refused.
  image("j.jpg", 4, 3, {"R", "G", "B"}, PixelType::u8, [](size_t, size_t) { return 0.5f; });
  expect_contains(error_of({"depth=" + d, "normal=" + path("j.jpg")}, o), {path("j.jpg"), "not a PNG, TIFF"});
  fs::copy_file(d, path("d.dat"));
  expect_contains(error_of({"depth=" + path("d.dat"), "normal=" + n}, o), {path("d.dat"), "not a PNG, TIFF"});
}

// Each format cut off half-way: refused naming the file, never decoded as a partial view.
TEST_F(ImageRead, TruncatedFilesAreRefused) {
  const int w = 64, h = 48;
  auto noise = [](size_t i, size_t c) { return float((i * 7919 + c * 104729) % 1000) / 1000.0f + 0.01f; };
  const std::vector<std::pair<std::string, PixelType>> files = {{"t8.png", PixelType::u8},
                                                                {"t16.png", PixelType::u16},
                                                                {"t.tif", PixelType::f32},
                                                                {"t.hdr", PixelType::f32},
                                                                {"t.exr", PixelType::f32}};
  for (auto& [name, type] : files) {
    const std::string p = image(name, w, h, {"R", "G", "B"}, type, noise);
    const auto size = fs::file_size(p);
    EXPECT_NO_THROW(read_image(p)) << p;
    fs::resize_file(p, size / 2);
    try {
      read_image(p);
      ADD_FAILURE() << p << ": half of the file was read without an error";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind(p + ": ", 0), 0u) << e.what();
    }
  }
}

// OpenEXR allocates a header attribute at its declared size before reading it: a file of
// a few dozen bytes declaring a 1.7 GB attribute is refused by the bounded header pass,
// before OpenImageIO opens it (found by fuzz_image, whose 2 GB limit it overran).
TEST_F(ImageRead, AnExrAttributeLargerThanTheFileIsRefusedBeforeOpenExrAllocatesIt) {
  std::string bytes("\x76\x2f\x31\x01\x02\x00\x00\x00", 8);
  bytes += std::string("capDate\0someType\0", 17);
  const int32_t declared = 1768712291;
  bytes.append(reinterpret_cast<const char*>(&declared), 4);
  bytes += "only a few bytes follow";
  const std::string p = path("huge-attribute.exr");
  std::ofstream(p, std::ios::binary) << bytes;
  try {
    read_image(p);
    ADD_FAILURE() << "read";
  } catch (const std::runtime_error& e) {
    expect_contains(e.what(), {p + ": malformed EXR header", "declares 1768712291 bytes"});
  }
}

// OpenImageIO converts scanlines to float through a buffer of at least 256 scanlines,
// whatever the image's height: this 237-byte TIFF (23814x4 pixels of 774 channels, found
// by fuzz_image) made it ask for 4.7 GB. Read in a child whose address space is capped at
// 3 GB, it must be refused as truncated, naming the file, not die of bad_alloc. (Not
// under a sanitizer, whose shadow memory needs more address space than the cap.)
TEST_F(ImageRead, AWideShortTiffIsReadWithinBoundedMemory) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "address-space cap and sanitizer";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer)
  GTEST_SKIP() << "address-space cap and sanitizer";
#endif
#endif
  const std::string bytes(
      "\x49\x49\x2a\x00\x08\x00\x00\x00\x0e\x00\x00\x01\x03\x00\x01\x00\x00\x00\x06\x5d\x00\x00\x01\x01"
      "\x03\x00\x01\x00\x00\x00\x04\x00\x00\x00\x02\x01\x03\x00\x01\x00\x00\x00\x08\x00\x01\x00\x00\x06"
      "\x03\x00\x01\x00\x00\x00\x01\x00\x00\x00\x11\x01\x04\x00\x01\x00\x00\x00\xca\x00\x00\x00\x12\x01"
      "\x03\x00\x01\x00\x00\x00\x01\x00\x00\x00\x15\x01\x03\x00\x01\x00\x00\x00\x06\x03\x00\x01\x00\x00"
      "\x00\x01\x00\x00\x00\x11\x01\x04\x00\x01\x00\x00\x00\xca\x00\x00\x00\x12\x01\x03\x00\x01\x00\x00"
      "\x00\x01\x00\x00\x00\x15\x01\x03\x00\x01\x00\x00\x00\x01\x00\x00\x00\x16\x01\x03\x00\x01\x00\x00"
      "\x00\x20\x09\x00\x00\x00\x16\x01\x03\x00\x01\x00\x00\x00\x20\x00\x00\x00\x17\x01\x04\x00\x00\x00"
      "\x00\x00\x00\x00\x00\x01\x01\x00\x00\x00\x27\x00\x00\x00\x32\x36\x3a\x31\x32\x3a\x30\x36\x20\x30"
      "\x36\x3a\x35\x30\x3a\x34\x35\x00\x78\xb1\x86\x75\xd2\x81\xbc\x85\x20\x7f\xe3\xe1\x95\x30\xd6\x76"
      "\x66\x32\x61\x73\x27\xed\x5f\x08\xe1\x1b\x7d\x86\xb1\xf6\x2f\x04\x00\xdb\x53\x1e\x2e",
      237);
  const std::string p = path("wide-rows.tif");
  std::ofstream(p, std::ios::binary) << bytes;
  ::testing::FLAGS_gtest_death_test_style = "threadsafe";
  // The child's exit code: 0 refused as documented, 1 another message, 2 another exception.
  auto read_capped = [&p] {
    const rlimit cap{3ull << 30, 3ull << 30};
    setrlimit(RLIMIT_AS, &cap);
    int code = 0;
    try {
      read_image(p);
      code = 1;
    } catch (const std::runtime_error& e) {
      code = std::string(e.what()).rfind(p + ": cannot decode the pixels", 0) == 0 ? 0 : 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      code = 2;
    }
    std::_Exit(code);
  };
  EXPECT_EXIT(read_capped(), ::testing::ExitedWithCode(0), "");
}

// A one-pixel grey 8-bit TIFF stored as one tile of the given size.
static std::string tiff_with_tiles(uint32_t tile_width, uint32_t tile_height) {
  std::string bytes("II*\x00\x08\x00\x00\x00", 8);
  auto put16 = [&](uint16_t v) { bytes.append(reinterpret_cast<const char*>(&v), 2); };
  auto put32 = [&](uint32_t v) { bytes.append(reinterpret_cast<const char*>(&v), 4); };
  const uint16_t entries = 10;
  const uint32_t data_at = 8 + 2 + entries * 12 + 4;
  put16(entries);
  // tag, type (3 short, 4 long), count 1, value: width, height, 8 bits, no compression,
  // grey, one sample, tile width and length, tile offset and byte count.
  const uint32_t tags[entries][3] = {{256, 4, 1},       {257, 4, 1}, {258, 3, 8},          {259, 3, 1},
                                     {262, 3, 1},       {277, 3, 1}, {322, 4, tile_width}, {323, 4, tile_height},
                                     {324, 4, data_at}, {325, 4, 64}};
  for (auto& t : tags) {
    put16(uint16_t(t[0]));
    put16(uint16_t(t[1]));
    put32(1);
    if (t[1] == 3) {
      put16(uint16_t(t[2]));
      put16(0);
    } else {
      put32(t[2]);
    }
  }
  put32(0);
  return bytes + std::string(64, '\0');
}

// A tiled image is converted through a row of its tiles, as stored and as float: a 1x1
// TIFF declaring tiles of 65536x65536 (a 4 GB row, in 134 bytes) is refused before that
// buffer is made, and so is one tile of 587268096x1, whose stored row (587 MB) is within
// bounds but whose float row is 2.35 GB (found by fuzz_image), and one whose row's size
// overflows a 64-bit integer.
TEST_F(ImageRead, TilesLargerThanAnyImageAreRefused) {
  for (const auto& [w, h] : {std::pair<uint32_t, uint32_t>{65536, 65536}, {587268096, 1}, {2147483647, 2147483647}}) {
    const std::string name = std::to_string(w) + "x" + std::to_string(h);
    const std::string p = path("huge-tiles-" + name + ".tif");
    std::ofstream(p, std::ios::binary) << tiff_with_tiles(w, h);
    try {
      read_image(p);
      ADD_FAILURE() << name << ": read";
    } catch (const std::runtime_error& e) {
      expect_contains(e.what(), {p + ": tiles of " + name + " pixels"});
    }
  }
}
