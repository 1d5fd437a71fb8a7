// OpenEXR I/O for one view. OpenEXR converts between pixel types while reading, so
// every channel lands in a FLOAT slice whatever it was stored as.
#include "data/exr_io.h"

#include "data/exr_header_check.h"
#include "core/atomic_file.h"

#include <unistd.h>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <Imath/half.h>
#include <OpenEXR/ImfFloatAttribute.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace nns::data {
namespace {

std::runtime_error file_error(const std::string& path, const std::string& what) {
  return std::runtime_error(path + ": " + what);
}

std::string compression_name(Imf::Compression c) {
  switch (c) {
    case Imf::NO_COMPRESSION:
      return "none";
    case Imf::RLE_COMPRESSION:
      return "rle";
    case Imf::ZIPS_COMPRESSION:
      return "zips";
    case Imf::ZIP_COMPRESSION:
      return "zip";
    case Imf::PIZ_COMPRESSION:
      return "piz";
    case Imf::PXR24_COMPRESSION:
      return "pxr24";
    case Imf::B44_COMPRESSION:
      return "b44";
    case Imf::B44A_COMPRESSION:
      return "b44a";
    case Imf::DWAA_COMPRESSION:
      return "dwaa";
    case Imf::DWAB_COMPRESSION:
      return "dwab";
    default:
      return "unknown";
  }
}

// A float attribute that some writers store as double.
std::optional<float> number_attribute(const Imf::Header& h, const char* name) {
  if (auto* f = h.findTypedAttribute<Imf::FloatAttribute>(name)) return f->value();
  if (auto* d = h.findTypedAttribute<Imf::DoubleAttribute>(name)) return float(d->value());
  return std::nullopt;
}

// The attribute holds Imath's row-vector convention (p_cam = p_world * M); the View
// holds the column-vector one (p_cam = M * p_world), so one is the other's transpose.
std::optional<std::array<float, 16>> matrix_attribute(const Imf::Header& h, const char* name) {
  std::array<float, 16> m{};
  if (auto* a = h.findTypedAttribute<Imf::M44fAttribute>(name)) {
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m[size_t(r * 4 + c)] = a->value()[c][r];
    return m;
  }
  if (auto* a = h.findTypedAttribute<Imf::M44dAttribute>(name)) {
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m[size_t(r * 4 + c)] = float(a->value()[c][r]);
    return m;
  }
  return std::nullopt;
}

}  // namespace

View read_view(const std::string& path, const ReadOptions& options, ExrInfo* info) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw file_error(path, "no such file");
  bool tiled = false, deep = false, multipart = false;
  if (!Imf::isOpenExrFile(path.c_str(), tiled, deep, multipart))
    throw file_error(path, "not an OpenEXR file (bad magic number or unreadable)");
  if (multipart) throw file_error(path, "multi-part EXR; the dataset format needs single-part files");
  if (deep) throw file_error(path, "deep EXR; the dataset format needs flat images");
  // Sizes and lengths checked against the file before OpenEXR or we allocate from them.
  check_exr_header(path);

  View v;
  v.source = path;
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& h = file.header();
    const Imath::Box2i dw = h.dataWindow();
    v.width = dw.max.x - dw.min.x + 1;
    v.height = dw.max.y - dw.min.y + 1;
    if (v.width <= 0 || v.height <= 0) throw file_error(path, "empty data window");

    ExrInfo local;
    local.tiled = tiled;
    local.compression = compression_name(h.compression());
    auto fov = number_attribute(h, "fovY");
    auto radius = number_attribute(h, "aoRadius");
    auto* scene = h.findTypedAttribute<Imf::StringAttribute>("scene");
    v.world_to_camera = matrix_attribute(h, "worldToCamera");
    local.has_fov_y = fov.has_value();
    local.has_ao_radius = radius.has_value();
    local.has_scene = scene != nullptr;
    local.has_world_to_camera = v.world_to_camera.has_value();
    for (auto it = h.begin(); it != h.end(); ++it)
      if (auto* text = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
        local.strings[it.name()] = text->value();
    if (fov) v.fov_y_deg = *fov;
    v.ao_radius = radius;
    if (scene) v.scene = scene->value();
    if (options.require_attributes) {
      if (!fov) throw file_error(path, "missing header attribute 'fovY' (float, degrees)");
      if (!scene) throw file_error(path, "missing header attribute 'scene' (string)");
    }

    if (options.header_only) {
      for (auto it = h.channels().begin(); it != h.channels().end(); ++it)
        local.channels.push_back({it.name(), it.channel().type == Imf::HALF});
      if (info) *info = std::move(local);
      return v;
    }
    Imf::FrameBuffer fb;
    const size_t w = size_t(v.width);
    for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
      std::string name = it.name();
      bool is_half = it.channel().type == Imf::HALF;
      local.channels.push_back({name, is_half});
      if (!options.only_channels.empty() &&
          std::find(options.only_channels.begin(), options.only_channels.end(), name) == options.only_channels.end())
        continue;
      if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
        throw file_error(path, "channel '" + name + "' is subsampled; the format needs full-resolution planes");
      if (name == "Z" && is_half && options.warn_half_depth)
        std::fprintf(stderr, "warning: %s: channel 'Z' is HALF; depth loses precision (store FLOAT)\n", path.c_str());
      auto& plane = v.add_channel(name);
      // The slice base is shifted so that data-window pixel (min.x, min.y) lands at index 0.
      char* base = reinterpret_cast<char*>(plane.data()) -
                   (ptrdiff_t(dw.min.x) + ptrdiff_t(dw.min.y) * ptrdiff_t(w)) * ptrdiff_t(sizeof(float));
      fb.insert(name, Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * w, 1, 1,
                                 std::numeric_limits<float>::quiet_NaN()));
    }
    if (!file.isComplete()) throw file_error(path, "truncated: some scanlines or tiles are missing");
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    if (info) *info = std::move(local);
  } catch (const std::exception& e) {
    std::string what = e.what();
    if (what.rfind(path + ":", 0) == 0) throw;
    // OpenEXR's messages name the file already only sometimes; keep ours first.
    throw file_error(path, "unreadable or truncated EXR (" + what + ")");
  }
  return v;
}

void write_view(const std::string& path, const View& v, const WriteOptions& options) {
  if (v.width <= 0 || v.height <= 0)
    throw file_error(path, "cannot write a view of size " + std::to_string(v.width) + "x" + std::to_string(v.height));
  const size_t n = size_t(v.width) * size_t(v.height);
  for (auto& [name, plane] : v.channels)
    if (plane.size() != n)
      throw file_error(path, "channel '" + name + "' has " + std::to_string(plane.size()) + " values, expected " +
                                 std::to_string(n));

  Imf::Header h(v.width, v.height);
  h.compression() = Imf::ZIP_COMPRESSION;
  h.insert("fovY", Imf::FloatAttribute(v.fov_y_deg));
  if (v.ao_radius) h.insert("aoRadius", Imf::FloatAttribute(*v.ao_radius));
  h.insert("scene", Imf::StringAttribute(v.scene));
  if (v.world_to_camera) {
    Imath::M44f m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m[c][r] = (*v.world_to_camera)[size_t(r * 4 + c)];
    h.insert("worldToCamera", Imf::M44fAttribute(m));
  }

  // HALF channels need their own converted buffers; FLOAT ones point at the View.
  std::vector<std::vector<half>> halves;
  halves.reserve(v.channels.size());
  Imf::FrameBuffer fb;
  for (auto& [name, plane] : v.channels) {
    bool store_half = options.half && name != "Z";
    h.channels().insert(name, Imf::Channel(store_half ? Imf::HALF : Imf::FLOAT));
    if (store_half) {
      halves.emplace_back(plane.begin(), plane.end());
      fb.insert(name, Imf::Slice(Imf::HALF, reinterpret_cast<char*>(halves.back().data()), sizeof(half),
                                 sizeof(half) * size_t(v.width)));
    } else {
      fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(plane.data())), sizeof(float),
                                 sizeof(float) * size_t(v.width)));
    }
  }

  // The one temporary-name convention (core/atomic_file.h), so the next run into the
  // folder removes what a killed render left.
  try {
    write_path_atomic(path, [&](const std::string& tmp) {
      Imf::OutputFile out(tmp.c_str(), h);
      out.setFrameBuffer(fb);
      out.writePixels(v.height);
    });
  } catch (const std::exception& e) {
    throw file_error(path, std::string("cannot write EXR (") + e.what() + ")");
  }
}

}  // namespace nns::data
