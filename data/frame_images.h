#pragma once
// A surround frame made of a user's own images: six faces, each read by
// view_from_images (data/image_read.h) from the mappings that name it.
//
//   --channel front.depth=f_depth.exr:Z --channel back.normal=b_n.png ...
//   std::array<View, 6> faces = frame_from_images(mappings, options);   // Face order
//
// A mapping's target is FACE.TARGET, FACE one of kFaceNames (data/dataset.h). Every
// face needs every required target of `options`; what is missing, on all faces, is
// listed in one message. The faces of a surround frame are square 90-degree views, so
// fov_y_deg must be 90 or 0 (then 90). Each face's source says which face it is, so
// later messages (validation, sizes: check_frame_sizes) name the face and its files.
#include <array>
#include <string>
#include <vector>

#include "data/image_read.h"
#include "data/view.h"

namespace nns::data {

// True when the mapping's target carries a face ("back.normal"): the target names have
// no '.', so any '.' is a face prefix (a valid one or not).
bool face_prefixed(const ChannelMapping& m);

// Throws naming the mapping, face or file: unprefixed or mixed targets, an unknown face
// or target, missing faces or targets, a field of view other than 90, faces of
// different sizes, and every error of view_from_images.
std::array<View, 6> frame_from_images(const std::vector<ChannelMapping>& mappings, const ImageViewOptions& options);

}  // namespace nns::data
