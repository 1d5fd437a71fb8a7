// data/frame_images.h: a surround frame from a user's images, six faces by FACE.TARGET.
// Float images give read_frame's faces bit for bit; 16-bit PNGs stay within their
// quantisation; the faces' sources name the face, so later messages do.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "data/dataset.h"
#include "data/exr_io.h"
#include "data/frame_images.h"
#include "report/image_write.h"
#include "tests/support/synthetic_gi_dataset.h"

namespace fs = std::filesystem;
using namespace nns::data;
using namespace nns::report;

namespace {

class FrameImages : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("nns_frame_images_" + std::to_string(::getpid()));
    fs::create_directories(dir_ / "frame");
    for (size_t f = 0; f < 6; ++f) {
      entry_.faces[f] = (dir_ / "frame" / (std::string(kFaceNames[f]) + ".exr")).string();
      write_view(entry_.faces[f], nns::testing::make_face(16, 1, int(f), false, 4));
    }
    entry_.dir = (dir_ / "frame").string();
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Planes of `v` as one image, channels named `names`; `encode` maps each value first.
  template <class Encode>
  std::string image(const View& v, const std::string& name, std::vector<std::string> names,
                    std::vector<std::string> planes, PixelType t, Encode encode) {
    const size_t n = size_t(v.width) * size_t(v.height), nc = names.size();
    std::vector<float> px(n * nc);
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < nc; ++c) px[i * nc + c] = encode(v.channel(planes[c])[i]);
    write_image((dir_ / name).string(), v.width, v.height, names, px.data(), t);
    return (dir_ / name).string();
  }

  // Every face's mappings: depth and normals from one EXR with its own names, the
  // colours from float TIFFs; with `png16` normals and albedo as 16-bit PNGs.
  std::vector<ChannelMapping> mappings(bool png16) {
    auto same = [](float x) { return x; };
    std::vector<std::string> flags;
    for (size_t f = 0; f < 6; ++f) {
      const View v = read_view(entry_.faces[f]);
      const std::string face = kFaceNames[f];
      const std::string g =
          image(v, face + "_g.exr", {"d", "nx", "ny", "nz"}, {"Z", "N.X", "N.Y", "N.Z"}, PixelType::f32, same);
      flags.push_back(face + ".depth=" + g + ":d");
      if (png16) {
        flags.push_back(face + ".normal=" +
                        image(v, face + "_n.png", {"R", "G", "B"}, {"N.X", "N.Y", "N.Z"}, PixelType::u16,
                              [](float x) { return (x + 1) / 2; }));
        flags.push_back(
            face + ".albedo=" +
            image(v, face + "_a.png", {"R", "G", "B"}, {"albedo.R", "albedo.G", "albedo.B"}, PixelType::u16,
                  [](float x) { return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1 / 2.4f) - 0.055f; }));
      } else {
        flags.push_back(face + ".normal=" + g + ":nx,ny,nz");
        flags.push_back(
            face + ".albedo=" +
            image(v, face + "_a.tif", {"R", "G", "B"}, {"albedo.R", "albedo.G", "albedo.B"}, PixelType::f32, same));
      }
      for (const char* t : {"direct", "env"}) {
        const std::string T(t);
        flags.push_back(
            face + "." + T + "=" +
            image(v, face + "_" + T + ".tif", {"R", "G", "B"}, {T + ".R", T + ".G", T + ".B"}, PixelType::f32, same));
      }
    }
    std::vector<ChannelMapping> m;
    for (auto& f : flags) m.push_back(parse_channel_mapping(f));
    return m;
  }
  static ImageViewOptions options() {
    ImageViewOptions o;
    o.targets = {"depth", "normal", "albedo", "direct"};
    o.optional = {"emission", "env"};
    o.command = "test";
    return o;
  }
  fs::path dir_;
  FrameEntry entry_;
};

}  // namespace

TEST_F(FrameImages, FloatImagesGiveReadFramesFacesBitForBit) {
  const auto want = read_frame(entry_);
  const auto got = frame_from_images(mappings(false), options());
  for (size_t f = 0; f < 6; ++f) {
    EXPECT_EQ(got[f].width, 16);
    EXPECT_EQ(got[f].fov_y_deg, 90.0f);
    EXPECT_EQ(got[f].source.rfind(std::string(kFaceNames[f]) + " face (", 0), 0u) << got[f].source;
    ASSERT_EQ(got[f].channels.size(), want[f].channels.size()) << kFaceNames[f];
    for (auto& [name, plane] : want[f].channels) EXPECT_EQ(got[f].channel(name), plane) << kFaceNames[f] << " " << name;
  }
}

// 16-bit codes: a normal component within 1/65535 before renormalising (2/65535 after,
// at most), an albedo within 0.5/65535 times the sRGB decode's largest slope, 2.28
// (1.8e-5). Measured: normals 1.5e-5, albedo 1.5e-5.
TEST_F(FrameImages, SixteenBitPngsStayWithinTheirQuantisation) {
  const auto want = read_frame(entry_);
  const auto got = frame_from_images(mappings(true), options());
  double normal = 0, albedo = 0;
  for (size_t f = 0; f < 6; ++f)
    for (auto& [name, plane] : want[f].channels) {
      double& worst = name.rfind("N.", 0) == 0 ? normal : name.rfind("albedo.", 0) == 0 ? albedo : normal;
      const bool exact = name.rfind("N.", 0) != 0 && name.rfind("albedo.", 0) != 0;
      for (size_t i = 0; i < plane.size(); ++i) {
        if (exact) ASSERT_EQ(got[f].channel(name)[i], plane[i]) << name;
        else worst = std::max(worst, double(std::abs(got[f].channel(name)[i] - plane[i])));
      }
    }
  std::printf("16-bit PNG: max normal error %.3g, max albedo error %.3g\n", normal, albedo);
  EXPECT_LE(normal, 2.0 / 65535);
  EXPECT_LE(albedo, 0.5 / 65535 * 2.28);
  EXPECT_GT(albedo, 0);  // quantised indeed: the PNGs were read, not the floats
}

TEST_F(FrameImages, RefusesNamingTheFaceAndWhatIsMissing) {
  auto error_of = [&](std::vector<ChannelMapping> m, ImageViewOptions o) -> std::string {
    try {
      frame_from_images(m, o);
      return "";
    } catch (const std::exception& e) {
      return e.what();
    }
  };
  auto all = mappings(false);
  std::vector<ChannelMapping> some;
  for (auto& m : all)
    if (m.target != "back.depth" && m.target != "up.normal" && m.target.rfind("down.", 0) != 0) some.push_back(m);
  EXPECT_NE(error_of(some, options())
                .find("missing: back.depth, up.normal, down (all of depth, normal, albedo, "
                      "direct)"),
            std::string::npos)
      << error_of(some, options());
  ImageViewOptions o = options();
  o.fov_y_deg = 60;
  EXPECT_NE(error_of(all, o).find("--fov-y 60: the faces of a surround frame are square 90-degree views"),
            std::string::npos);
  // A face of another size: its source names the face and its files.
  auto sized = all;
  const View small = nns::testing::make_face(8, 1, 2, false, 4);
  const std::string f = image(small, "left_small.exr", {"d"}, {"Z"}, PixelType::f32, [](float x) { return x; });
  std::vector<ChannelMapping> left;
  for (auto& m : sized)
    if (m.target != "left.depth") left.push_back(m);
  left.push_back(parse_channel_mapping("left.depth=" + f + ":d"));
  const std::string e = error_of(left, options());
  EXPECT_NE(e.find(f), std::string::npos) << e;  // inside the face: view_from_images names both files
  EXPECT_NE(e.find("every image of a view has one size"), std::string::npos) << e;
  EXPECT_TRUE(face_prefixed(parse_channel_mapping("up.env=x.exr")));
  EXPECT_FALSE(face_prefixed(parse_channel_mapping("env=x.exr")));
}
