#include "data/image_read.h"

#include <OpenImageIO/imageio.h>

#include "data/exr_header_check.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

namespace nns::data {

int Image::channel_index(const std::string& name) const {
  for (size_t c = 0; c < channels.size(); ++c)
    if (channels[c] == name) return int(c);
  return -1;
}

std::string Image::channel_list() const {
  std::string s;
  for (auto& c : channels) s += (s.empty() ? "" : ", ") + c;
  return s.empty() ? "none" : s;
}

namespace {

// OpenImageIO's format name for the file name's extension, "" for any other.
std::string format_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".png") return "png";
  if (ext == ".tif" || ext == ".tiff") return "tiff";
  if (ext == ".hdr") return "hdr";
  if (ext == ".exr") return "openexr";
  return "";
}

// The scanlines in their stored types, at most about 64 MB of them at a time, each
// block converted to float. OpenImageIO's own conversion goes through a buffer of at
// least 256 scanlines whatever the image's height: a 237-byte TIFF of 23814x4 pixels with
// 774 channels made it ask for 4.7 GB (found by fuzz_image).
bool read_scanlines_as_float(OIIO::ImageInput& in, float* out) {
  const OIIO::ImageSpec& spec = in.spec();
  const size_t row_bytes = spec.scanline_bytes(/*native=*/true);
  const size_t pixel_bytes = spec.pixel_bytes(/*native=*/true);
  const size_t row_values = size_t(spec.width) * size_t(spec.nchannels);
  const int rows = int(std::clamp<size_t>((size_t(1) << 26) / std::max<size_t>(row_bytes, 1), 1, size_t(spec.height)));
  std::vector<unsigned char> stored(size_t(rows) * row_bytes);
  for (int y = 0; y < spec.height; y += rows) {
    const int n = std::min(rows, spec.height - y);
    if (!in.read_scanlines(0, 0, spec.y + y, spec.y + y + n, 0, 0, spec.nchannels, OIIO::TypeDesc::UNKNOWN,
                           stored.data()))
      return false;
    float* block = out + size_t(y) * row_values;
    if (spec.channelformats.empty()) {
      if (!OIIO::convert_pixel_values(spec.format, stored.data(), OIIO::TypeDesc::FLOAT, block, int(n * row_values)))
        return false;
      continue;
    }
    // Channels stored in types of their own (an EXR with half and float channels): one
    // channel at a time, at its offset inside the stored pixel.
    size_t offset = 0;
    for (int c = 0; c < spec.nchannels; ++c) {
      const OIIO::TypeDesc type = spec.channelformats[size_t(c)];
      if (!OIIO::convert_image(1, spec.width, n, 1, stored.data() + offset, type, OIIO::stride_t(pixel_bytes),
                               OIIO::stride_t(row_bytes), OIIO::AutoStride, block + c, OIIO::TypeDesc::FLOAT,
                               OIIO::stride_t(sizeof(float) * spec.nchannels),
                               OIIO::stride_t(sizeof(float) * row_values), OIIO::AutoStride))
        return false;
      offset += type.size();
    }
  }
  return true;
}

// A tiled image through OpenImageIO's own conversion, whose buffers are one row of tiles
// as stored and the same row as float: tiles far larger than any real file's are refused
// before they are made. Counting the stored row alone was not enough: a 145-byte TIFF of
// one 587268096x1 tile (587 MB stored) made the float row 2.35 GB (found by fuzz_image).
bool read_tiled_as_float(OIIO::ImageInput& in, const std::string& path, float* out) {
  const OIIO::ImageSpec& spec = in.spec();
  // In double: a header's tile sizes multiply past any integer type.
  const double tiles_across = std::ceil(double(spec.width) / double(spec.tile_width));
  const double row_pixels =
      tiles_across * double(spec.tile_width) * double(spec.tile_height) * double(std::max(spec.tile_depth, 1));
  const double row_bytes =
      row_pixels * (double(spec.pixel_bytes(/*native=*/true)) + double(spec.nchannels) * sizeof(float));
  if (spec.tile_height <= 0 || row_bytes > double(1ll << 30))
    throw std::runtime_error(path + ": tiles of " + std::to_string(spec.tile_width) + "x" +
                             std::to_string(spec.tile_height) + " pixels are larger than any image read here");
  return in.read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, out);
}

}  // namespace

Image read_image(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw std::runtime_error(path + ": no such file");
  if (!std::filesystem::is_regular_file(path, ec)) throw std::runtime_error(path + ": not a regular file");
  // Straight (unassociated) values as stored: OpenImageIO would otherwise premultiply the
  // colour channels of an RGBA PNG or TIFF by its alpha, and a normal map's alpha is not
  // coverage.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  // The reader is chosen by the file name's extension alone, and only among the formats
  // this reads: given a file name, OpenImageIO would sniff the bytes and try each of its
  // plugins (camera raw, DICOM, video, ...), putting every one of those parsers in front
  // of a user's bytes. Given a format name it makes that reader and nothing else.
  const std::string format = format_of(path);
  if (format.empty())
    throw std::runtime_error(path +
                             ": not a PNG, TIFF, Radiance HDR or OpenEXR file name (.png, .tif, .tiff, "
                             ".hdr, .exr)");
  // OpenEXR allocates each header attribute at the size the file declares before reading
  // it (a 200-byte file can ask for 1.7 GB): the project's bounded header pass goes first,
  // as it does for the dataset reader. Its side limit is raised to read_image's own.
  if (format == "openexr") {
    ExrHeaderLimits limits;
    limits.max_side = kMaxImageSide;
    check_exr_header(path, limits);
  }
  auto in = OIIO::ImageInput::create(format, /*do_open=*/false, &config);
  if (!in) throw std::runtime_error(path + ": OpenImageIO has no " + format + " reader (" + OIIO::geterror() + ")");
  OIIO::ImageSpec opened;
  if (!in->open(path, opened, config))
    throw std::runtime_error(path + ": cannot read it as " + format + " (" + in->geterror() + ")");
  const OIIO::ImageSpec& spec = in->spec();
  Image im;
  im.source = path;
  im.format = format;
  if (spec.deep) throw std::runtime_error(path + ": a deep image; only flat images are read");
  if (spec.depth > 1) throw std::runtime_error(path + ": a volume (" + std::to_string(spec.depth) + " slices)");
  const long long values = (long long)spec.width * spec.height * spec.nchannels;
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw std::runtime_error(path + ": empty image (" + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                             ", " + std::to_string(spec.nchannels) + " channels)");
  if (spec.width > kMaxImageSide || spec.height > kMaxImageSide || values > kMaxImageValues)
    throw std::runtime_error(path + ": " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + " with " +
                             std::to_string(spec.nchannels) + " channels is larger than the " +
                             std::to_string(kMaxImageValues) + " values read at most");
  im.width = spec.width;
  im.height = spec.height;
  for (int c = 0; c < spec.nchannels; ++c) {
    std::string name = c < int(spec.channelnames.size()) ? spec.channelnames[size_t(c)] : "";
    im.channels.push_back(name.empty() ? "channel" + std::to_string(c) : name);
  }
  // Integer when every channel is stored as integers (a mixed EXR is float).
  im.integer = !spec.format.is_floating_point();
  for (auto& f : spec.channelformats)
    if (f.is_floating_point()) im.integer = false;
  im.pixels.resize(size_t(values));
  // A TIFF cut short returns success with the failed strips left as they were: the
  // reader's pending error message is the only sign, so any message is a failure.
  const bool read = spec.tile_width > 0 ? read_tiled_as_float(*in, path, im.pixels.data())
                                        : read_scanlines_as_float(*in, im.pixels.data());
  const std::string error = in->geterror();
  if (!read || !error.empty())
    throw std::runtime_error(path + ": cannot decode the pixels, truncated or corrupt (" + error + ")");
  in->close();
  return im;
}

ChannelMapping parse_channel_mapping(const std::string& text) {
  auto fail = [&](const std::string& why) {
    return std::runtime_error("--channel '" + text + "': " + why + " (expected TARGET=FILE[:CHANNEL,...])");
  };
  ChannelMapping m;
  m.text = text;
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw fail("no TARGET=");
  m.target = text.substr(0, eq);
  std::string rest = text.substr(eq + 1);
  const auto colon = rest.rfind(':');
  // "C:\x" style names do not occur on Linux; a ':' followed by a '/' is part of a path.
  if (colon != std::string::npos && rest.find('/', colon) == std::string::npos) {
    const std::string list = rest.substr(colon + 1);
    rest = rest.substr(0, colon);
    size_t start = 0;
    while (true) {
      const size_t comma = list.find(',', start);
      const std::string item = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      if (item.empty()) throw fail("an empty channel name in '" + list + "'");
      m.channels.push_back(item);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  if (rest.empty()) throw fail("no FILE");
  m.file = rest;
  return m;
}

const std::vector<ChannelTarget>& channel_targets() {
  static const std::vector<ChannelTarget> t = {
      {"depth", {"Z"}, false},
      {"normal", {"N.X", "N.Y", "N.Z"}, false},
      {"albedo", {"albedo.R", "albedo.G", "albedo.B"}, true},
      {"direct", {"direct.R", "direct.G", "direct.B"}, true},
      {"emission", {"emission.R", "emission.G", "emission.B"}, true},
      {"env", {"env.R", "env.G", "env.B"}, true},
  };
  return t;
}

std::string comma_list(const std::vector<std::string>& v) {
  std::string s;
  for (auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

namespace {

float srgb_decode(float s) { return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f); }

// The target as the user wrote it, for hints to copy: "back.normal" for a face of a
// surround frame (data/frame_images.h passes the target without the face).
std::string given_target(const ChannelMapping& m) {
  const auto eq = m.text.find('=');
  return eq == std::string::npos ? m.target : m.text.substr(0, eq);
}

// The file's channels that fill `target`, by the rules of image_read.h.
std::vector<int> pick_channels(const Image& im, const ChannelMapping& m, size_t want) {
  std::vector<int> idx;
  if (!m.channels.empty()) {
    if (m.channels.size() != want)
      throw std::runtime_error("--channel '" + m.text + "': " + m.target + " takes " + std::to_string(want) +
                               (want == 1 ? " channel" : " channels") + ", " + std::to_string(m.channels.size()) +
                               " given");
    for (auto& name : m.channels) {
      const int i = im.channel_index(name);
      if (i < 0)
        throw std::runtime_error(im.source + ": no channel '" + name + "' for " + given_target(m) + " (the file has " +
                                 im.channel_list() + ")");
      idx.push_back(i);
    }
    return idx;
  }
  const size_t n = im.channels.size();
  const bool rgba = want == 3 && n == 4 && im.channels[3] == "A";
  if (n != want && !rgba)
    throw std::runtime_error(im.source + ": has " + std::to_string(n) + (n == 1 ? " channel" : " channels") + " (" +
                             im.channel_list() + ") but " + given_target(m) + " takes " + std::to_string(want) +
                             "; name them: --channel " + given_target(m) + "=" + m.file + ":" +
                             (want == 1 ? im.channels[0] : "CH1,CH2,CH3"));
  for (size_t c = 0; c < want; ++c) idx.push_back(int(c));
  return idx;
}

void fill_target(View& v, const ChannelTarget& t, const Image& im, const std::vector<int>& idx,
                 const ImageViewOptions& o) {
  const size_t n = size_t(im.width) * size_t(im.height), stride = im.channels.size();
  std::vector<std::vector<float>*> planes;
  for (auto& name : t.view_channels) planes.push_back(&v.add_channel(name));
  auto where = [&](size_t i) {
    return " at x=" + std::to_string(i % size_t(im.width)) + ", y=" + std::to_string(i / size_t(im.width));
  };
  const std::string what = im.source + ": " + t.name + " (channel" + (idx.size() == 1 ? " '" : "s '");
  auto channel_names = [&] {
    std::string s;
    for (int i : idx) s += (s.empty() ? "" : "', '") + im.channels[size_t(i)];
    return what + s + "')";
  };
  const bool depth = std::string(t.name) == "depth", normal = std::string(t.name) == "normal";
  if (depth && im.integer && !(o.depth_scale > 0))
    throw std::runtime_error(channel_names() +
                             " is stored as integers, which carry no unit: give --depth-scale "
                             "(the view-space depth of the largest code)");
  for (size_t i = 0; i < n; ++i) {
    float px[3];
    for (size_t c = 0; c < idx.size(); ++c) px[c] = im.pixels[i * stride + size_t(idx[c])];
    if (depth) {
      float z = px[0];
      if (im.integer) z = z == 0 ? INFINITY : z * o.depth_scale;
      else if (!(z > 0))
        throw std::runtime_error(channel_names() + ": depth " + (std::isnan(z) ? "NaN" : std::to_string(z)) + where(i) +
                                 "; depth must be > 0, sky is +inf or >= 1e30");
      px[0] = z;
    } else if (normal && im.integer) {
      for (auto& c : px) c = 2 * c - 1;
      const float len = std::sqrt(px[0] * px[0] + px[1] * px[1] + px[2] * px[2]);
      if (len > 0)
        for (auto& c : px) c /= len;
    } else if (t.colour && im.integer) {
      for (auto& c : px) c = srgb_decode(c);
    }
    for (size_t c = 0; c < idx.size(); ++c) {
      if (!depth && !std::isfinite(px[c]))
        throw std::runtime_error(channel_names() + ": " + (std::isnan(px[c]) ? "NaN" : "infinite") + where(i));
      (*planes[c])[i] = px[c];
    }
  }
}

}  // namespace

View view_from_images(const std::vector<ChannelMapping>& mappings, const ImageViewOptions& o) {
  const std::string cmd = o.command.empty() ? std::string("this command") : o.command;
  auto takes = [&] {
    return cmd + " takes " + comma_list(o.targets) +
           (o.optional.empty() ? "" : "; optional: " + comma_list(o.optional));
  };
  auto listed = [](const std::vector<std::string>& v, const std::string& x) {
    return std::find(v.begin(), v.end(), x) != v.end();
  };
  std::map<std::string, const ChannelMapping*> by_target;
  for (auto& m : mappings) {
    if (!listed(o.targets, m.target) && !listed(o.optional, m.target))
      throw std::runtime_error("--channel '" + m.text + "': unknown target '" + m.target + "' (" + takes() + ")");
    if (!by_target.emplace(m.target, &m).second)
      throw std::runtime_error("--channel '" + m.text + "': " + m.target + " is given twice");
  }
  for (auto& t : o.targets)
    if (!by_target.count(t)) throw std::runtime_error("no --channel " + t + "=FILE (" + takes() + ")");
  if (!(o.fov_y_deg > 0 && o.fov_y_deg < 180))
    throw std::runtime_error(
        "--fov-y is required with --channel: the camera's vertical field of view, in "
        "degrees (0, 180)");

  View v;
  std::map<std::string, Image> images;  // each file read once, however many targets use it
  const Image* first = nullptr;
  std::string first_target;
  for (auto& t : channel_targets()) {
    auto it = by_target.find(t.name);
    if (it == by_target.end()) continue;
    const ChannelMapping& m = *it->second;
    auto [at, fresh] = images.try_emplace(m.file);
    if (fresh) at->second = read_image(m.file);
    const Image& im = at->second;
    if (!first) {
      first = &im, first_target = t.name;
      v.width = im.width, v.height = im.height;
    } else if (im.width != first->width || im.height != first->height) {
      throw std::runtime_error(im.source + ": is " + std::to_string(im.width) + "x" + std::to_string(im.height) + " (" +
                               t.name + ") but " + first->source + " is " + std::to_string(first->width) + "x" +
                               std::to_string(first->height) + " (" + first_target +
                               "); every image of a view has one size");
    }
    fill_target(v, t, im, pick_channels(im, m, t.view_channels.size()), o);
  }
  v.fov_y_deg = o.fov_y_deg;
  const auto depth = by_target.find("depth");
  v.scene = depth != by_target.end() ? std::filesystem::path(depth->second->file).stem().string() : "images";
  for (auto& [file, im] : images) v.source += (v.source.empty() ? "" : " + ") + file;
  return v;
}

}  // namespace nns::data
