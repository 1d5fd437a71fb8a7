// nnao-infer on a user's own images (--channel, data/image_read.h) against nnao-infer on
// the dataset EXR of the same rendered view. The test writes the view's depth and
// normals in each format itself (report/image_write.h) and bounds the difference by
// what the format stores:
//   float EXR (own channel names) and float TIFF: lossless, the AO is bit-identical;
//   16-bit PNG: depth to S/65535 (S = --depth-scale), normals to 2/65535 per component.
//     The decoded depth comes back in the output EXR's Z and must lie within half a code
//     of the original; the AO must equal, to float rounding, nnao-infer on a dataset EXR
//     quantised by the documented decoding — so any other decoding fails;
//   Radiance HDR: RGBE keeps 8 mantissa bits, depth to 2^-7 relative (OpenImageIO
//     truncates); Z is checked against that bound.
// The AO's own distance from the original in the quantised formats is printed and
// bounded loosely (it depends on the network, not the reader).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "data/exr_io.h"
#include "fixtures/random_nnao_blob.h"
#include "report/image_write.h"
#include "tests/gl/rendered_view.h"
#include "tests/support/run_command.h"

namespace fs = std::filesystem;
using namespace nns;
using nns::report::PixelType;
using nns::testing::run_app;

namespace {

struct Planes {
  std::vector<float> ao, z;
};

class NnaoInferImages : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("nns_nnao_images_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    // The rendered room has no sky; a band of sky along the top (depth +inf) makes every
    // format carry it too.
    view_ = nns::testing::rendered_view();
    auto& z = view_.channels["Z"];
    for (size_t i = 0; i < size_t(view_.width) * 4; ++i) z[i] = INFINITY;
    const data::View& v = view_;
    data::write_view(path("view.exr"), v);
    fixtures::spread_nnao_outputs(fixtures::random_nnao_blob(9, 6, 5), 40, 0.5f).save(path("nnao.blob"));
    char buf[64];
    std::snprintf(buf, sizeof buf, " --radius %.9g", double(*v.ao_radius));
    radius_ = buf;
    std::snprintf(buf, sizeof buf, " --fov-y %.9g", double(v.fov_y_deg));
    camera_ = buf + radius_;  // what the images lack: the header's fovY and aoRadius
    reference_ = infer("--in " + path("view.exr"), "ref.exr");
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  static const data::View& view() { return view_; }
  static std::string path(const std::string& name) { return (root_ / name).string(); }
  static size_t pixels() { return size_t(view().width) * size_t(view().height); }

  static Planes infer(const std::string& input, const std::string& out) {
    const bool images = input.rfind("--channel", 0) == 0;
    auto r = run_app("nnao-infer", "--model " + path("nnao.blob") + " " + input + " --out " + path(out) +
                                       (images ? camera_ : radius_));
    EXPECT_EQ(r.code, 0) << r.output;
    if (r.code != 0) return {};
    data::View o = data::read_view(path(out));
    return {o.channel("AO"), o.channel("Z")};
  }
  // width x height x channels.size() floats from the view's planes, per pixel f(plane values).
  static std::string write(const std::string& name, std::vector<std::string> names, PixelType type,
                           const std::vector<std::string>& planes, float (*f)(float, size_t)) {
    const size_t n = pixels(), nc = names.size();
    std::vector<float> px(n * nc);
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < nc; ++c) px[i * nc + c] = f(view().channel(planes[c % planes.size()])[i], c);
    report::write_image(path(name), view().width, view().height, names, px.data(), type);
    return path(name);
  }
  static double max_diff(const std::vector<float>& a, const std::vector<float>& b) {
    double m = a.size() == b.size() ? 0 : INFINITY;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i) m = std::max(m, double(std::abs(a[i] - b[i])));
    return m;
  }
  static double mean_diff(const std::vector<float>& a, const std::vector<float>& b) {
    double s = 0;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i) s += std::abs(a[i] - b[i]);
    return s / double(std::max<size_t>(a.size(), 1));
  }

  // The largest depth error of `z` against the view's depth, relative to the depth or
  // absolute; every sky pixel must stay sky.
  static double worst_depth_error(const std::vector<float>& z, bool relative) {
    const auto& z0 = view().channel("Z");
    double worst = 0;
    for (size_t i = 0; i < pixels(); ++i) {
      if (data::is_sky(z0[i])) {
        EXPECT_TRUE(data::is_sky(z[i])) << i;
        continue;
      }
      worst = std::max(worst, double(std::abs(z[i] - z0[i])) / (relative ? z0[i] : 1.0));
    }
    return worst;
  }

  static inline data::View view_;
  static inline fs::path root_;
  static inline std::string camera_, radius_;
  static inline Planes reference_;
};

const std::vector<std::string> kNormals = {"N.X", "N.Y", "N.Z"};
float as_is(float x, size_t) { return x; }
// RGBE has no infinity, and truncates 1e30 to just below the sky threshold: sky as 1e32.
float sky_as_1e32(float z, size_t) { return data::is_sky(z) ? 1e32f : z; }

}  // namespace

TEST_F(NnaoInferImages, TheRenderedViewHasSkyAndGeometry) {
  size_t sky = 0;
  for (float z : view().channel("Z")) sky += data::is_sky(z);
  EXPECT_GT(sky, 0u);
  EXPECT_LT(sky, pixels() / 2);
  ASSERT_EQ(reference_.ao.size(), pixels());
  double lo = 1, hi = 0;
  for (float a : reference_.ao) lo = std::min(lo, double(a)), hi = std::max(hi, double(a));
  EXPECT_GT(hi - lo, 0.3) << "the model's AO barely varies: a wrong input could hide";
}

TEST_F(NnaoInferImages, FloatExrWithItsOwnNamesAndFloatTiffGiveTheSameAo) {
  const std::string g =
      write("gbuf.exr", {"depth.V", "nrm.x", "nrm.y", "nrm.z"}, PixelType::f32, {"Z", "N.X", "N.Y", "N.Z"}, as_is);
  Planes exr = infer("--channel depth=" + g + ":depth.V --channel normal=" + g + ":nrm.x,nrm.y,nrm.z", "exr.exr");
  EXPECT_EQ(max_diff(exr.ao, reference_.ao), 0.0);
  EXPECT_EQ(max_diff(exr.z, view().channel("Z")), 0.0);

  const std::string d = write("depth.tif", {"Y"}, PixelType::f32, {"Z"}, as_is);
  const std::string n = write("normals.tif", {"R", "G", "B"}, PixelType::f32, kNormals, as_is);
  Planes tif = infer("--channel depth=" + d + " --channel normal=" + n, "tif.exr");
  EXPECT_EQ(max_diff(tif.ao, reference_.ao), 0.0);
}

TEST_F(NnaoInferImages, SixteenBitPngWithinItsQuantisation) {
  float far = 0;
  for (float z : view().channel("Z"))
    if (!data::is_sky(z)) far = std::max(far, z);
  static float scale;
  scale = std::ceil(far);
  // Depth: code 0 is sky; normals: code/65535 = (n + 1) / 2.
  const std::string d = write("depth16.png", {"Y"}, PixelType::u16, {"Z"}, [](float z, size_t) {
    return data::is_sky(z) ? 0.0f : std::max(z / scale, 1.0f / 65535);
  });
  const std::string n =
      write("normals16.png", {"R", "G", "B"}, PixelType::u16, kNormals, [](float x, size_t) { return 0.5f * (x + 1); });
  char s[32];
  std::snprintf(s, sizeof s, "%.9g", double(scale));
  Planes png = infer("--channel depth=" + d + " --channel normal=" + n + " --depth-scale " + s, "png.exr");
  ASSERT_EQ(png.z.size(), pixels());

  // The decoded depth: within half a code of the original, plus the float rounding of
  // z / scale and code / 65535 * scale (an ulp of the depth each).
  const double worst = worst_depth_error(png.z, /*relative=*/false);
  EXPECT_LE(worst, 0.5 * scale / 65535 + 2 * scale * FLT_EPSILON) << "depth decoded off by more than half a code";

  // The same AO as the dataset path on the planes quantised and decoded as documented.
  data::View q = view();
  q.channels["Z"] = png.z;
  for (size_t i = 0; i < pixels(); ++i) {
    float n3[3], len = 0;
    for (int c = 0; c < 3; ++c) {
      const float code = std::round(0.5f * (q.channels[kNormals[size_t(c)]][i] + 1) * 65535);
      n3[c] = 2 * (code / 65535) - 1;
      len += n3[c] * n3[c];
    }
    for (int c = 0; c < 3; ++c) q.channels[kNormals[size_t(c)]][i] = n3[c] / std::sqrt(len);
  }
  data::write_view(path("quantised.exr"), q);
  Planes expect = infer("--in " + path("quantised.exr"), "quantised_ao.exr");
  EXPECT_LE(max_diff(png.ao, expect.ao), 1e-5) << "the reader's decoding is not the documented one";

  const double mean = mean_diff(png.ao, reference_.ao), max = max_diff(png.ao, reference_.ao);
  std::printf("16-bit PNG vs the dataset EXR: AO mean |diff| %.3g, max %.3g; depth max |diff| %.3g (scale %g)\n", mean,
              max, worst, double(scale));
  EXPECT_LT(mean, 1e-3);
  EXPECT_GT(max, 0.0) << "16-bit codes cannot hold the rendered floats exactly; is the PNG really 16-bit?";
}

TEST_F(NnaoInferImages, RadianceHdrDepthWithinRgbePrecision) {
  const std::string d = write("depth.hdr", {"R", "G", "B"}, PixelType::f32, {"Z"}, sky_as_1e32);
  const std::string g = write("n.exr", {"nx", "ny", "nz"}, PixelType::f32, kNormals, as_is);
  Planes hdr = infer("--channel depth=" + d + ":R --channel normal=" + g + ":nx,ny,nz", "hdr.exr");
  ASSERT_EQ(hdr.z.size(), pixels());
  const double worst = worst_depth_error(hdr.z, /*relative=*/true);
  EXPECT_LE(worst, 1.0 / 128) << "depth off by more than RGBE's 8 mantissa bits";
  EXPECT_GT(worst, 0.0) << "RGBE cannot hold the rendered floats exactly; was this really an HDR file?";
  std::printf("HDR depth vs the dataset EXR: relative depth max %.3g, AO mean |diff| %.3g, max %.3g\n", worst,
              mean_diff(hdr.ao, reference_.ao), max_diff(hdr.ao, reference_.ao));
  EXPECT_LT(mean_diff(hdr.ao, reference_.ao), 0.02);
}

// Refused naming the file and the problem, exit 1, and no output at all.
TEST_F(NnaoInferImages, RefusalsNameTheFileAndWriteNothing) {
  const std::string n = write("rn.exr", {"R", "G", "B"}, PixelType::f32, kNormals, as_is);
  const std::string d = write("rd.exr", {"Z"}, PixelType::f32, {"Z"}, as_is);
  const std::string cut =
      write("cut.png", {"R", "G", "B"}, PixelType::u16, kNormals, [](float x, size_t) { return 0.5f * (x + 1); });
  fs::resize_file(cut, fs::file_size(cut) / 2);
  const std::string small = path("small.exr");
  const float one[4] = {1, 1, 1, 1};
  report::write_image(small, 2, 2, {"Z"}, one, PixelType::f32);

  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"--channel depth=" + d + " --channel normal=" + cut, {cut, "truncated or corrupt"}},
      {"--channel depth=" + d + " --channel normal=" + n + ":R,G,W", {n, "no channel 'W'", "R, G, B"}},
      {"--channel depth=" + small + " --channel normal=" + n, {n, small, "2x2", "every image of a view has one size"}},
      {"--channel depth=" + n + " --channel normal=" + n, {n, "depth takes 1"}},
  };
  for (auto& [flags, parts] : cases) {
    const std::string out = path("refused.exr");
    auto r = run_app("nnao-infer", "--model " + path("nnao.blob") + " " + flags + camera_ + " --out " + out +
                                       " --png " + path("refused.png"));
    EXPECT_EQ(r.code, 1) << flags << "\n" << r.output;
    for (auto& p : parts) EXPECT_NE(r.output.find(p), std::string::npos) << "'" << p << "' not in: " << r.output;
    EXPECT_FALSE(fs::exists(out)) << flags;
    EXPECT_FALSE(fs::exists(path("refused.png"))) << flags;
  }
  // Flag-level mistakes: exit 2.
  auto both = run_app("nnao-infer", "--model " + path("nnao.blob") + " --in " + path("view.exr") +
                                        " --channel depth=" + d + " --out " + path("x.exr"));
  EXPECT_EQ(both.code, 2);
  EXPECT_NE(both.output.find("--in and --channel are alternatives"), std::string::npos) << both.output;
  auto help = run_app("nnao-infer", "--help");
  EXPECT_NE(help.output.find("--channel"), std::string::npos);
  EXPECT_NE(help.output.find("2*code/max - 1"), std::string::npos) << help.output;
}
