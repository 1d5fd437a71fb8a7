#pragma once
// The flags nnao-infer and gi-infer share for a view made of a user's own images
// instead of a dataset EXR (data/image_read.h has the rules; docs/nnao.md, "Your own
// images", the examples):
//   --channel depth=scene.exr:depth.V --channel normal=normals.png --fov-y 60
#include <string>
#include <vector>

#include "apps/args.h"
#include "data/image_read.h"

namespace nns::apps {

struct ImageInputFlags {
  std::vector<data::ChannelMapping> channels;  // empty: the command reads --in
  data::ImageViewOptions view;
};

// `targets` are required once any --channel is given, `optional` may be. `surround`:
// the command also reads a surround frame, its six faces as FACE.TARGET
// (data/frame_images.h).
inline ImageInputFlags image_input_flags(Args& a, const std::string& command, std::vector<std::string> targets,
                                         std::vector<std::string> optional = {}, bool surround = false) {
  std::string names;
  for (auto& t : targets) names += (names.empty() ? "" : ", ") + t;
  for (auto& t : optional) names += ", " + t + " (optional)";
  ImageInputFlags f;
  const auto texts = a.get_list(
      "--channel",
      "instead of --in: TARGET=FILE[:CH,...] for each of " + names +
          ". FILE is any image OpenImageIO reads (PNG 8/16-bit, TIFF, HDR, EXR, ...); CH are its channel names "
          "(without them the file's own channels, RGBA's alpha ignored). Float files are taken as stored; "
          "integer files: normal = 2*code/max - 1 then normalised, colours sRGB-decoded, depth code 0 = sky "
          "else code/max * --depth-scale. Depth is planar view-space depth in the AO radius's units" +
          std::string(surround ? ". A surround model's frame: FACE.TARGET=FILE[:CH,...] for every face front, back, "
                                 "left, right, up, down (e.g. front.depth=f_d.exr:Z, back.normal=b_n.png)"
                               : ""));
  f.view.fov_y_deg = float(a.get_double(
      "--fov-y", 0,
      "with --channel: the camera's vertical field of view, degrees" +
          std::string(surround ? " (a surround frame's faces: 90, the default for them; no other value)" : ""),
      0, 179.999));
  f.view.depth_scale = float(a.get_double(
      "--depth-scale", 0, "with --channel and an integer depth file: the depth of its largest code", 0, HUGE_VAL));
  f.view.targets = std::move(targets);
  f.view.optional = std::move(optional);
  f.view.command = command;
  for (auto& t : texts) {
    try {
      f.channels.push_back(data::parse_channel_mapping(t));
    } catch (const std::exception& e) {
      a.error(e.what());
    }
  }
  return f;
}

}  // namespace nns::apps
