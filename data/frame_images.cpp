#include "data/frame_images.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "data/dataset.h"

namespace nns::data {

bool face_prefixed(const ChannelMapping& m) { return m.target.find('.') != std::string::npos; }

namespace {

std::string faces_list() { return comma_list(std::vector<std::string>(kFaceNames.begin(), kFaceNames.end())); }

}  // namespace

std::array<View, 6> frame_from_images(const std::vector<ChannelMapping>& mappings, const ImageViewOptions& o) {
  std::vector<std::string> prefixed, plain;
  for (auto& m : mappings) (face_prefixed(m) ? prefixed : plain).push_back("'" + m.text + "'");
  if (!plain.empty() && !prefixed.empty())
    throw std::runtime_error("--channel: " + comma_list(plain) + (plain.size() == 1 ? " names" : " name") +
                             " no face but " + prefixed[0] + (prefixed.size() == 1 ? " does" : " and others do") +
                             "; a surround frame gives every target with its face: FACE.TARGET=FILE, "
                             "FACE one of " +
                             faces_list());
  if (prefixed.empty())
    throw std::runtime_error(
        "--channel without faces gives one view, but a surround frame has six: give every "
        "target with its face, --channel FACE.TARGET=FILE (FACE one of " +
        faces_list() +
        "; e.g. front.depth=f_depth.exr, back.normal=b_normal.png), or --in a folder of six "
        "view EXRs");
  // A cube map's faces each cover 90 degrees; any other angle would not be a surround frame.
  if (o.fov_y_deg != 0 && o.fov_y_deg != 90) {
    char fov[32];
    std::snprintf(fov, sizeof fov, "%g", double(o.fov_y_deg));
    throw std::runtime_error("--fov-y " + std::string(fov) +
                             ": the faces of a surround frame are "
                             "square 90-degree views (a cube map around the camera); give --fov-y 90 or leave it "
                             "out");
  }

  std::array<std::vector<ChannelMapping>, 6> by_face;
  for (auto& m : mappings) {
    const auto dot = m.target.find('.');
    const std::string face = m.target.substr(0, dot), target = m.target.substr(dot + 1);
    const auto f = std::find(kFaceNames.begin(), kFaceNames.end(), face);
    if (f == kFaceNames.end())
      throw std::runtime_error("--channel '" + m.text + "': unknown face '" + face + "' (faces: " + faces_list() + ")");
    // An unknown target is refused by view_from_images, naming the mapping as given.
    ChannelMapping face_mapping = m;  // `text` stays as given, for view_from_images's messages
    face_mapping.target = target;
    by_face[size_t(f - kFaceNames.begin())].push_back(face_mapping);
  }
  std::vector<std::string> missing;
  for (size_t f = 0; f < 6; ++f) {
    if (by_face[f].empty()) {
      missing.push_back(std::string(kFaceNames[f]) + " (all of " + comma_list(o.targets) + ")");
      continue;
    }
    for (auto& t : o.targets)
      if (std::none_of(by_face[f].begin(), by_face[f].end(), [&](const ChannelMapping& m) { return m.target == t; }))
        missing.push_back(std::string(kFaceNames[f]) + "." + t);
  }
  if (!missing.empty())
    throw std::runtime_error("--channel: a surround frame needs " + comma_list(o.targets) +
                             " on each of its six faces; missing: " + comma_list(missing));

  ImageViewOptions face_options = o;
  face_options.fov_y_deg = 90;
  std::array<View, 6> faces;
  for (size_t f = 0; f < 6; ++f) {
    faces[f] = view_from_images(by_face[f], face_options);
    faces[f].source = std::string(kFaceNames[f]) + " face (" + faces[f].source + ")";
  }
  check_frame_sizes(faces);
  return faces;
}

}  // namespace nns::data
