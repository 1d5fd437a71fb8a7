#pragma once
// A user's own images as a G-buffer view: depth, normals, albedo, ... from PNG (8/16
// bit), TIFF, Radiance HDR or EXR with any channel names (OpenImageIO, the format by the
// file name's extension: .png, .tif/.tiff, .hdr, .exr; no other reader sees the bytes),
// assembled into the View that nnao-infer and gi-infer take from a dataset EXR. The
// dataset itself is read by data/exr_io.h; this is for images made by other tools.
//
//   auto m = parse_channel_mapping("normal=normals.png:R,G,B");   // the --channel flag
//   View v = view_from_images({d, m}, {.fov_y_deg = 60, .targets = {"depth", "normal"}});
//
// The mapping, one --channel per target: TARGET=FILE[:CH[,CH,...]], CH being channel
// names as the file has them (case-sensitive: a PNG has R, G, B, A or Y; an EXR whatever
// its writer chose). Without CH, a file with exactly the target's channel count is taken
// whole (an RGBA file gives R, G, B for a 3-channel target, the alpha ignored); anything
// else is an error listing the file's channels. Values (docs/your-own-images.md):
//   depth   -> Z       planar view-space depth (distance along -z, the AO radius's units).
//                      Float files as stored: > 0, sky +inf or >= 1e30; NaN, 0, negative
//                      are errors. Integer files: code 0 = sky, else code/max * depth_scale
//                      (depth_scale required).
//   normal  -> N.X/Y/Z camera-space unit normals (x right, y up, +z toward the viewer).
//                      Float files as stored; integer files n = 2 code/max - 1, normalised.
//   albedo, direct, emission, env -> <target>.R/G/B   linear; integer files are taken as
//                      sRGB-encoded and decoded with the IEC 61966-2-1 curve.
// Every error names the file and the problem ("<file>: <problem>"); all images must
// have one size.
#include <string>
#include <vector>

#include "data/view.h"

namespace nns::data {

// One image as OpenImageIO decodes it, every channel as float.
struct Image {
  int width = 0, height = 0;
  std::vector<std::string> channels;  // as the file names them
  std::vector<float> pixels;          // width*height*channels.size(), interleaved
  bool integer = false;               // stored as integers: values are code/max in [0, 1]
  std::string format;                 // OpenImageIO's name: png, tiff, hdr, openexr, ...
  std::string source;

  int channel_index(const std::string& name) const;  // -1 when absent
  std::string channel_list() const;                  // "R, G, B" for messages
};

// The largest image read, in values (width * height * channels): 2^27 floats, 512 MiB.
inline constexpr long long kMaxImageValues = 1ll << 27;
// ...and the longest side.
inline constexpr int kMaxImageSide = 65536;

// Throws "<file>: <problem>": unreadable, truncated, not one of the four formats, deep,
// too large.
Image read_image(const std::string& path);

struct ChannelMapping {
  std::string target, file;
  std::vector<std::string> channels;  // empty: the whole file (see above)
  std::string text;                   // as given, for messages
};
// Parses "TARGET=FILE[:CH,...]"; throws "--channel '<text>': <problem>". A FILE that
// itself contains ':' needs the channel list (the last ':' separates it).
ChannelMapping parse_channel_mapping(const std::string& text);

// The targets and the dataset channels each one fills.
struct ChannelTarget {
  const char* name;
  std::vector<std::string> view_channels;
  bool colour;  // integer files are sRGB-decoded
};
const std::vector<ChannelTarget>& channel_targets();

struct ImageViewOptions {
  float fov_y_deg = 0;                // the camera's vertical field of view; required
  float depth_scale = 0;              // integer depth: view-space depth at the full-scale code
  std::vector<std::string> targets;   // what the command reads; these are required
  std::vector<std::string> optional;  // ... and these may be given
  std::string command;                // for messages ("nnao-infer")
};

// "a, b, c": target and channel lists in messages (here and data/frame_images.cpp).
std::string comma_list(const std::vector<std::string>& v);

// Reads every mapped file once and assembles the View (fovY from the options, scene =
// the depth file's stem, source = the files). Throws naming the file and the problem.
View view_from_images(const std::vector<ChannelMapping>& mappings, const ImageViewOptions& options);

}  // namespace nns::data
