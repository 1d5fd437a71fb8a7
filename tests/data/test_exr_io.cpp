#include <gtest/gtest.h>
#include <unistd.h>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfChannelListAttribute.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTiledOutputFile.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "data/exr_io.h"

using namespace nns::data;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("nns_test_exr_io_" + std::to_string(getpid()));
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

View sample_view(int w, int h) {
  View v;
  v.width = w;
  v.height = h;
  v.fov_y_deg = 60;
  v.ao_radius = 0.75f;
  v.scene = "room-3";
  for (const char* c : {"Z", "N.X", "N.Y", "N.Z", "AO"}) v.add_channel(c);
  for (int i = 0; i < w * h; ++i) {
    v.channels["Z"][size_t(i)] = 1.0f + 0.001234567f * float(i);  // HALF would round this
    v.channels["N.Z"][size_t(i)] = 1.0f;
    v.channels["AO"][size_t(i)] = float(i % 7) / 7.0f;
  }
  v.channels["Z"][0] = INFINITY;  // sky
  return v;
}

}  // namespace

TEST(ExrIo, FloatRoundTripIsExactWithAttributes) {
  TempDir dir;
  View v = sample_view(7, 5);
  v.world_to_camera = std::array<float, 16>{1, 0, 0, 2, 0, 1, 0, 3, 0, 0, 1, 4, 0, 0, 0, 1};
  write_view(dir.file("a.exr"), v);
  ExrInfo info;
  View r = read_view(dir.file("a.exr"), {}, &info);
  EXPECT_EQ(r.width, 7);
  EXPECT_EQ(r.height, 5);
  EXPECT_FLOAT_EQ(r.fov_y_deg, 60);
  ASSERT_TRUE(r.ao_radius.has_value());
  EXPECT_FLOAT_EQ(*r.ao_radius, 0.75f);
  EXPECT_EQ(r.scene, "room-3");
  ASSERT_TRUE(r.world_to_camera.has_value());
  EXPECT_EQ(*r.world_to_camera, *v.world_to_camera);
  EXPECT_EQ(r.channels, v.channels);  // bit-exact, including the inf
  EXPECT_EQ(info.compression, "zip");
  EXPECT_FALSE(info.tiled);
  for (auto& c : info.channels) EXPECT_FALSE(c.half) << c.name;
  EXPECT_EQ(r.source, dir.file("a.exr"));
  // Nothing but the file itself is left behind.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()), 1);
}

TEST(ExrIo, WorldToCameraIsStoredInImathRowVectorConvention) {
  TempDir dir;
  View v = sample_view(2, 2);
  v.world_to_camera = std::array<float, 16>{1, 0, 0, 2, 0, 1, 0, 3, 0, 0, 1, 4, 0, 0, 0, 1};
  write_view(dir.file("m.exr"), v);
  Imf::InputFile f(dir.file("m.exr").c_str());
  auto* m = f.header().findTypedAttribute<Imf::M44fAttribute>("worldToCamera");
  ASSERT_NE(m, nullptr);
  // Translation sits in the last row for Imath (p * M).
  EXPECT_EQ(m->value()[3][0], 2);
  EXPECT_EQ(m->value()[3][1], 3);
  EXPECT_EQ(m->value()[3][2], 4);
}

TEST(ExrIo, HalfOptionKeepsDepthFloat) {
  TempDir dir;
  View v = sample_view(6, 4);
  write_view(dir.file("h.exr"), v, {.half = true});
  ExrInfo info;
  View r = read_view(dir.file("h.exr"), {}, &info);
  for (auto& c : info.channels) EXPECT_EQ(c.half, c.name != "Z") << c.name;
  EXPECT_EQ(r.channel("Z"), v.channel("Z"));
  bool any_rounded = false;
  for (size_t i = 0; i < v.channel("AO").size(); ++i) {
    EXPECT_NEAR(r.channel("AO")[i], v.channel("AO")[i], 1e-3);
    any_rounded |= r.channel("AO")[i] != v.channel("AO")[i];
  }
  EXPECT_TRUE(any_rounded);  // it really was stored as HALF
}

TEST(ExrIo, ReadsTiledHalfPizWithOffsetDataWindowAndWarnsOnHalfDepth) {
  TempDir dir;
  const int w = 9, h = 6;
  Imf::Header hd(Imath::Box2i({0, 0}, {w + 2, h + 2}), Imath::Box2i({3, 2}, {3 + w - 1, 2 + h - 1}));
  hd.compression() = Imf::PIZ_COMPRESSION;
  hd.setTileDescription(Imf::TileDescription(4, 4));
  hd.insert("fovY", Imf::FloatAttribute(45));
  hd.insert("scene", Imf::StringAttribute("tiled"));
  hd.insert("someoneElse", Imf::StringAttribute("ignored"));
  hd.channels().insert("Z", Imf::Channel(Imf::HALF));
  hd.channels().insert("N.X", Imf::Channel(Imf::HALF));
  std::vector<half> z(size_t(w * h)), nx(size_t(w * h));
  for (int i = 0; i < w * h; ++i) {
    z[size_t(i)] = float(i);
    nx[size_t(i)] = -0.5f;
  }
  Imf::FrameBuffer fb;
  const ptrdiff_t shift = (3 + 2 * w) * ptrdiff_t(sizeof(half));
  fb.insert("Z", Imf::Slice(Imf::HALF, reinterpret_cast<char*>(z.data()) - shift, sizeof(half), sizeof(half) * w));
  fb.insert("N.X", Imf::Slice(Imf::HALF, reinterpret_cast<char*>(nx.data()) - shift, sizeof(half), sizeof(half) * w));
  {
    Imf::TiledOutputFile out(dir.file("t.exr").c_str(), hd);
    out.setFrameBuffer(fb);
    out.writeTiles(0, out.numXTiles() - 1, 0, out.numYTiles() - 1);
  }
  testing::internal::CaptureStderr();
  ExrInfo info;
  View r = read_view(dir.file("t.exr"), {}, &info);
  std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("'Z' is HALF"), std::string::npos) << err;
  EXPECT_NE(err.find("t.exr"), std::string::npos) << err;
  EXPECT_TRUE(info.tiled);
  EXPECT_EQ(info.compression, "piz");
  ASSERT_EQ(r.width, w);
  ASSERT_EQ(r.height, h);
  EXPECT_EQ(r.at("Z", 0, 0), 0);
  EXPECT_EQ(r.at("Z", 4, 3), float(3 * w + 4));
  EXPECT_EQ(r.at("N.X", 8, 5), -0.5f);
  EXPECT_EQ(r.scene, "tiled");
}

TEST(ExrIo, OnlyChannelsReadsASubset) {
  TempDir dir;
  write_view(dir.file("a.exr"), sample_view(3, 3));
  ReadOptions subset;
  subset.only_channels = {"Z", "AO"};
  View r = read_view(dir.file("a.exr"), subset);
  EXPECT_EQ(r.channels.size(), 2u);
  EXPECT_TRUE(r.has("Z"));
  EXPECT_TRUE(r.has("AO"));
}

namespace {
std::string read_error(const std::string& path, const ReadOptions& o = {}) {
  try {
    read_view(path, o);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(ExrIo, ErrorsNameTheFileAndTheProblem) {
  TempDir dir;
  EXPECT_EQ(read_error(dir.file("none.exr")), dir.file("none.exr") + ": no such file");

  std::ofstream(dir.file("text.exr")) << "hello, not an image";
  EXPECT_NE(read_error(dir.file("text.exr")).find("text.exr: not an OpenEXR file"), std::string::npos);

  View v = sample_view(64, 64);
  write_view(dir.file("full.exr"), v);
  auto size = fs::file_size(dir.file("full.exr"));
  fs::copy_file(dir.file("full.exr"), dir.file("cut.exr"));
  fs::resize_file(dir.file("cut.exr"), size * 2 / 3);
  std::string cut = read_error(dir.file("cut.exr"));
  EXPECT_NE(cut.find("cut.exr: "), std::string::npos) << cut;
  EXPECT_NE(cut.find("truncated"), std::string::npos) << cut;

  View nofov = sample_view(2, 2);
  nofov.scene = "s";
  write_view(dir.file("nofov.exr"), nofov);
  // write_view always writes fovY; remove it by writing the header by hand.
  {
    Imf::Header hd(2, 2);
    hd.insert("scene", Imf::StringAttribute("s"));
    hd.channels().insert("Z", Imf::Channel(Imf::FLOAT));
    std::vector<float> z(4, 1.0f);
    Imf::FrameBuffer fb;
    fb.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(z.data()), 4, 8));
    Imf::OutputFile out(dir.file("nofov.exr").c_str(), hd);
    out.setFrameBuffer(fb);
    out.writePixels(2);
  }
  EXPECT_NE(read_error(dir.file("nofov.exr")).find("nofov.exr: missing header attribute 'fovY'"), std::string::npos);
  ReadOptions lenient;
  lenient.require_attributes = false;
  EXPECT_EQ(read_error(dir.file("nofov.exr"), lenient), "");
}

TEST(ExrIo, RefusesMultiPart) {
  TempDir dir;
  std::vector<Imf::Header> headers(2, Imf::Header(2, 2));
  for (int i = 0; i < 2; ++i) {
    headers[size_t(i)].setName("part" + std::to_string(i));
    headers[size_t(i)].setType(Imf::SCANLINEIMAGE);
    headers[size_t(i)].channels().insert("Z", Imf::Channel(Imf::FLOAT));
  }
  std::vector<float> z(4, 1.0f);
  {
    Imf::MultiPartOutputFile out(dir.file("multi.exr").c_str(), headers.data(), 2);
    for (int i = 0; i < 2; ++i) {
      Imf::OutputPart part(out, i);
      Imf::FrameBuffer fb;
      fb.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(z.data()), 4, 8));
      part.setFrameBuffer(fb);
      part.writePixels(2);
    }
  }
  EXPECT_NE(read_error(dir.file("multi.exr")).find("multi.exr: multi-part EXR"), std::string::npos);
}

TEST(ExrIo, WriteRejectsPlanesOfTheWrongSize) {
  TempDir dir;
  View v = sample_view(4, 4);
  v.channels["AO"].pop_back();
  try {
    write_view(dir.file("bad.exr"), v);
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("bad.exr: channel 'AO' has 15 values, expected 16"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(dir.file("bad.exr")));
}

namespace {
// Rewrites the dataWindow attribute of an EXR file in place (box2i: xmin ymin xmax ymax).
void patch_data_window(const std::string& path, int32_t xmin, int32_t ymin, int32_t xmax, int32_t ymax) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const std::string key("dataWindow\0box2i\0", 17);
  auto at = bytes.find(key);
  ASSERT_NE(at, std::string::npos);
  const int32_t box[4] = {xmin, ymin, xmax, ymax};
  f.clear();
  f.seekp(std::streamoff(at + key.size() + 4));
  f.write(reinterpret_cast<const char*>(box), sizeof box);
}

long peak_rss_kb() {
  std::ifstream s("/proc/self/status");
  std::string line;
  while (std::getline(s, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
  return 0;
}
}  // namespace

// A ~10 KB file declaring 1,048,577 x 32 pixels made the reader allocate the
// planes (hundreds of MB) before finding out the data is not there.
TEST(ExrIo, HeaderSizeIsCheckedAgainstTheFileBeforeAllocating) {
  TempDir dir;
  write_view(dir.file("huge.exr"), sample_view(1, 32));
  patch_data_window(dir.file("huge.exr"), 0, 0, 1048576, 31);
  ASSERT_LT(fs::file_size(dir.file("huge.exr")), 20000u);
  const long before = peak_rss_kb();
  std::string e = read_error(dir.file("huge.exr"));
  const long grown_mb = (peak_rss_kb() - before) / 1024;
  EXPECT_NE(e.find(dir.file("huge.exr") + ": "), std::string::npos) << e;
  EXPECT_NE(e.find("1048577x32"), std::string::npos) << e;
  EXPECT_LT(grown_mb, 64) << "the reader allocated for the declared size: " << e;
  ReadOptions header_only;
  header_only.header_only = true;
  EXPECT_NE(read_error(dir.file("huge.exr"), header_only).find("1048577x32"), std::string::npos);

  // Past any sane size, and a window whose width overflows 32 bits.
  write_view(dir.file("giant.exr"), sample_view(1, 32));
  patch_data_window(dir.file("giant.exr"), 0, 0, 1 << 30, 31);
  EXPECT_NE(read_error(dir.file("giant.exr")).find("giant.exr: "), std::string::npos);
  patch_data_window(dir.file("giant.exr"), -2147483647 - 1, 0, 2147483647, 31);
  std::string wrap = read_error(dir.file("giant.exr"));
  EXPECT_NE(wrap.find("giant.exr: "), std::string::npos) << wrap;
  EXPECT_NE(wrap.find("4294967296x32"), std::string::npos) << wrap;
}

namespace {
// Rewrites the declared size of attribute `name` in place.
void patch_attribute_size(const std::string& path, const std::string& name_and_type, int32_t size) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  auto at = bytes.find(name_and_type);
  ASSERT_NE(at, std::string::npos);
  f.clear();
  f.seekp(std::streamoff(at + name_and_type.size()));
  f.write(reinterpret_cast<const char*>(&size), 4);
}
}  // namespace

// Found by fuzz/fuzz_exr.cpp: OpenEXR reads a value of a type it knows by the type and
// carries on where the value ended, so an attribute whose declared size disagrees made
// it parse the rest of the header out of step with the size check, into an allocation
// sized by stray bytes (a timeout in a 603-byte file, fuzz/regressions/exr/).
TEST(ExrIo, AttributeSizesMustMatchTheirType) {
  TempDir dir;
  write_view(dir.file("f.exr"), sample_view(2, 2));
  patch_attribute_size(dir.file("f.exr"), std::string("fovY\0float\0", 11), 8);
  std::string e = read_error(dir.file("f.exr"));
  EXPECT_NE(e.find(dir.file("f.exr") + ": "), std::string::npos) << e;
  EXPECT_NE(e.find("attribute 'fovY' of type float declares 8 bytes"), std::string::npos) << e;

  // A channel list under another name is parsed by OpenEXR all the same.
  {
    Imf::Header hd(2, 2);
    hd.insert("scene", Imf::StringAttribute("s"));
    hd.insert("fovY", Imf::FloatAttribute(60));
    hd.channels().insert("Z", Imf::Channel(Imf::FLOAT));
    Imf::ChannelList extra;
    extra.insert("AO", Imf::Channel(Imf::FLOAT));
    hd.insert("moreChannels", Imf::ChannelListAttribute(extra));
    std::vector<float> z(4, 1.0f);
    Imf::FrameBuffer fb;
    fb.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(z.data()), 4, 8));
    Imf::OutputFile out(dir.file("extra.exr").c_str(), hd);
    out.setFrameBuffer(fb);
    out.writePixels(2);
  }
  EXPECT_EQ(read_error(dir.file("extra.exr")), "");
  patch_attribute_size(dir.file("extra.exr"), std::string("moreChannels\0chlist\0", 20), 40);
  std::string chl = read_error(dir.file("extra.exr"));
  EXPECT_NE(chl.find(dir.file("extra.exr") + ": malformed EXR header (the channel list ends before its attribute does"),
            std::string::npos)
      << chl;

  // Every input the fuzzer found is refused with the file's name.
  const fs::path regressions = fs::path(NNSHADE_SOURCE_DIR) / "fuzz" / "regressions" / "exr";
  int replayed = 0;
  for (auto& entry : fs::directory_iterator(regressions)) {
    std::string p = entry.path().string();
    std::string err = read_error(p);
    EXPECT_NE(err.find(p + ": "), std::string::npos) << p << ": " << err;
    ++replayed;
  }
  EXPECT_GE(replayed, 1);
}
