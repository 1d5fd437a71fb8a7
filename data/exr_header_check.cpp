#include "data/exr_header_check.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace nns::data {
namespace {

std::string mb(int64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f MB", double(bytes) / 1e6);
  return buf;
}

// Reads the header through a window that never goes past the file's end.
class HeaderReader {
 public:
  HeaderReader(const std::string& path, int64_t size) : path_(path), in_(path, std::ios::binary), left_(size) {
    if (!in_) fail("cannot open the file");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(path_ + ": malformed EXR header (" + what + ")");
  }
  int64_t left() const { return left_; }
  std::string bytes(int64_t n, const char* what) {
    if (n < 0 || n > left_)
      fail(std::string(what) + " declares " + std::to_string(n) + " bytes, more than the " + std::to_string(left_) +
           " left in the file");
    std::string s(size_t(n), '\0');
    if (n && !in_.read(s.data(), std::streamsize(n))) fail("cannot read " + std::string(what));
    left_ -= n;
    return s;
  }
  void skip(int64_t n, const std::string& what) {
    if (n < 0 || n > left_)
      fail(what + " declares " + std::to_string(n) + " bytes, more than the " + std::to_string(left_) +
           " left in the file");
    in_.seekg(std::streamoff(n), std::ios::cur);
    left_ -= n;
  }
  int32_t i32(const char* what) {
    std::string b = bytes(4, what);
    int32_t v;
    std::memcpy(&v, b.data(), 4);
    return v;
  }
  // A NUL-terminated name of at most `max` characters (OpenEXR stops reading there).
  std::string name(const char* what, size_t max = 255) {
    std::string s;
    for (;;) {
      if (left_ <= 0) fail(std::string(what) + " runs past the end of the file");
      char c;
      if (!in_.get(c)) fail("cannot read " + std::string(what));
      --left_;
      if (c == '\0') return s;
      if (s.size() == max)
        fail(std::string(what) + " is longer than " + std::to_string(max) + " characters" +
             (max < 255 ? " (the long-names flag is not set)" : ""));
      s += c;
    }
  }

 private:
  std::string path_;
  std::ifstream in_;
  int64_t left_;
};

// Bytes of the OpenEXR 3.1 attribute types whose values have a fixed size; -1 for the
// others (chlist, preview and stringvector are walked; string, floatvector and unknown
// types are read by their declared size).
int fixed_size(const std::string& type) {
  static const std::pair<const char*, int> sizes[] = {{"box2i", 16},      {"box2f", 16},   {"chromaticities", 32},
                                                      {"compression", 1}, {"double", 8},   {"envmap", 1},
                                                      {"float", 4},       {"int", 4},      {"keycode", 28},
                                                      {"lineOrder", 1},   {"m33f", 36},    {"m33d", 72},
                                                      {"m44f", 64},       {"m44d", 128},   {"rational", 8},
                                                      {"tiledesc", 9},    {"timecode", 8}, {"v2i", 8},
                                                      {"v2f", 8},         {"v2d", 16},     {"v3i", 12},
                                                      {"v3f", 12},        {"v3d", 24},     {"deepImageState", 1}};
  for (auto& [t, n] : sizes)
    if (type == t) return n;
  return -1;
}

int32_t get_i32(const std::string& v, size_t at) {
  int32_t x;
  std::memcpy(&x, v.data() + at, 4);
  return x;
}

// The entries of a channel list (OpenEXR parses every chlist by its type, whatever its
// name): NUL-terminated names, each followed by 16 bytes, the empty name last.
int64_t count_channels(const HeaderReader& r, const std::string& v) {
  size_t p = 0;
  int64_t channels = 0;
  for (;;) {
    size_t end = v.find('\0', p);
    if (end == std::string::npos) r.fail("the channel list runs past its attribute");
    if (end == p) {  // the empty name closes the list, and must end the value
      if (end + 1 != v.size()) r.fail("the channel list ends before its attribute does");
      return channels;
    }
    if (end - p > 255) r.fail("a channel name is longer than 255 characters");
    p = end + 1 + 16;  // pixel type, pLinear + 3 reserved, x and y sampling
    if (p > v.size()) r.fail("the channel list runs past its attribute");
    ++channels;
  }
}

// The value of an attribute whose type OpenEXR sizes its allocations from; the facts
// the checks after the header need go into f (box: the data window).
void check_value(const HeaderReader& r, const std::string& name, const std::string& type, const std::string& v,
                 ExrHeaderFacts& f, int32_t (&box)[4], bool& have_window) {
  const std::string what = "attribute '" + name + "'";
  if (type == "box2i") {
    if (v.size() != 16) r.fail(what + " has " + std::to_string(v.size()) + " bytes, a box2i has 16");
    if (name == "dataWindow") {
      for (int k = 0; k < 4; ++k) box[k] = get_i32(v, size_t(4 * k));
      have_window = true;
    }
  } else if (type == "chlist") {
    const int64_t channels = count_channels(r, v);
    if (name == "channels") f.channels = channels;
  } else if (type == "tiledesc") {
    if (v.size() != 9) r.fail(what + " has " + std::to_string(v.size()) + " bytes, a tiledesc has 9");
    uint32_t tx, ty;
    std::memcpy(&tx, v.data(), 4);
    std::memcpy(&ty, v.data() + 4, 4);
    if (name == "tiles") f.tile_width = int64_t(tx), f.tile_height = int64_t(ty);
  } else if (type == "preview") {
    // OpenEXR allocates width * height RGBA pixels for a preview before reading them.
    if (v.size() < 8) r.fail(what + " is shorter than a preview header");
    uint32_t pw, ph;
    std::memcpy(&pw, v.data(), 4);
    std::memcpy(&ph, v.data() + 4, 4);
    if (uint64_t(pw) * uint64_t(ph) * 4 + 8 != uint64_t(v.size()))
      r.fail(what + " declares a " + std::to_string(pw) + "x" + std::to_string(ph) + " preview that its " +
             std::to_string(v.size()) + " bytes do not hold");
  } else if (type == "stringvector") {
    // OpenEXR sizes each string from its own length field.
    size_t p = 0;
    while (p < v.size()) {
      if (v.size() - p < 4) r.fail(what + " ends inside a string length");
      int32_t len = get_i32(v, p);
      p += 4;
      if (len < 0 || size_t(len) > v.size() - p) r.fail(what + " holds a string longer than the attribute");
      p += size_t(len);
    }
  }
}

// The attributes up to the header's end: names, types and sizes that stay inside the
// file, and the values OpenEXR allocates from checked by check_value.
void walk_attributes(HeaderReader& r, size_t max_name, ExrHeaderFacts& f, int32_t (&box)[4]) {
  bool have_window = false;
  for (;;) {
    std::string name = r.name("an attribute name", max_name);
    if (name.empty()) break;
    std::string type = r.name("an attribute type", max_name);
    const int32_t size = r.i32("an attribute size");
    const std::string what = "attribute '" + name + "'";
    if (size < 0) r.fail(what + " has a negative size");
    // OpenEXR reads a value of a type it knows by the type, not by the declared size, and
    // goes on from where the value ended: a size that disagrees would let it parse bytes
    // this pass never checked. Fixed-size types must declare their size exactly.
    if (int expected = fixed_size(type); expected >= 0 && size != expected)
      r.fail(what + " of type " + type + " declares " + std::to_string(size) + " bytes, the type has " +
             std::to_string(expected));
    const bool needed =
        type == "box2i" || type == "chlist" || type == "tiledesc" || type == "preview" || type == "stringvector";
    if (type == "floatvector" && size % 4 != 0)
      r.fail(what + " of type floatvector declares " + std::to_string(size) + " bytes, not a multiple of 4");
    if (!needed) r.skip(size, what);
    else check_value(r, name, type, r.bytes(size, what.c_str()), f, box, have_window);
  }
  if (!have_window) r.fail("no 'dataWindow' attribute");
}

// The image the header declares against the limits and against the file's own size.
void check_declared_size(const std::string& path, ExrHeaderFacts& f, const int32_t (&box)[4],
                         const ExrHeaderLimits& limits) {
  f.width = int64_t(box[2]) - int64_t(box[0]) + 1;
  f.height = int64_t(box[3]) - int64_t(box[1]) + 1;
  const std::string dims = std::to_string(f.width) + "x" + std::to_string(f.height);
  if (f.width <= 0 || f.height <= 0) throw std::runtime_error(path + ": empty data window");
  if (f.width > limits.max_side || f.height > limits.max_side)
    throw std::runtime_error(path + ": header declares a " + dims + " image; the largest side accepted is " +
                             std::to_string(limits.max_side) + " (refused before allocating)");
  constexpr int64_t kCoordLimit = int64_t(1) << 30;
  for (int32_t c : box)
    if (c < -kCoordLimit || c > kCoordLimit)
      throw std::runtime_error(path + ": data window (" + std::to_string(box[0]) + ", " + std::to_string(box[1]) +
                               ") - (" + std::to_string(box[2]) + ", " + std::to_string(box[3]) +
                               ") lies outside +-2^30; refused before allocating");
  const int64_t per_pixel = 4 * std::max<int64_t>(f.channels, 1);
  const int64_t decoded = f.width * f.height * per_pixel;
  const int64_t limit =
      std::min(limits.max_decoded_bytes, std::max(limits.small_file_allowance, limits.max_expansion * f.file_bytes));
  if (decoded > limit)
    throw std::runtime_error(path + ": header declares a " + dims + " image with " + std::to_string(f.channels) +
                             " channels (" + mb(decoded) + " decoded) but the file holds " +
                             std::to_string(f.file_bytes) + " bytes; refused before allocating (limit " + mb(limit) +
                             ")");
  if (!f.tiled) return;
  if (f.tile_width < 1 || f.tile_height < 1 || f.tile_width > limits.max_side || f.tile_height > limits.max_side)
    throw std::runtime_error(path + ": tile size " + std::to_string(f.tile_width) + "x" +
                             std::to_string(f.tile_height) + " is outside 1.." + std::to_string(limits.max_side));
  if (f.tile_width * f.tile_height * per_pixel > limit)
    throw std::runtime_error(path + ": tile size " + std::to_string(f.tile_width) + "x" +
                             std::to_string(f.tile_height) +
                             " declares more than the file can hold; refused before allocating");
}

}  // namespace

ExrHeaderFacts check_exr_header(const std::string& path, const ExrHeaderLimits& limits) {
  ExrHeaderFacts f;
  {
    std::ifstream probe(path, std::ios::binary | std::ios::ate);
    if (!probe) throw std::runtime_error(path + ": cannot open the file");
    f.file_bytes = int64_t(probe.tellg());
  }
  HeaderReader r(path, f.file_bytes);
  std::string magic = r.bytes(4, "the magic number");
  if (magic != std::string("\x76\x2f\x31\x01", 4)) r.fail("bad magic number");
  const int32_t version = r.i32("the version field");
  f.tiled = (version & 0x200) != 0;
  int32_t box[4] = {0, 0, 0, 0};
  walk_attributes(r, (version & 0x400) ? 255 : 31, f, box);
  check_declared_size(path, f, box, limits);
  return f;
}

}  // namespace nns::data
