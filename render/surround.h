#pragma once
// Surround (cube) capture per docs/dataset-format.md: six square 90-degree faces
// sharing the front camera's centre. right/left/back are the front camera yawed by
// -90/+90/180 degrees (image up stays +y); up/down are pitched by +90/-90 (image up
// becomes +z, towards the back, for up, and -z for down). Normals of every face are
// written in the front camera's space; Z is each face's own planar depth.
#include <array>
#include <string>

#include "render/render_view.h"

namespace nns::render {

inline const std::array<std::string, 6>& cube_face_names() {
  static const std::array<std::string, 6> names = {"front", "back", "left", "right", "up", "down"};
  return names;
}

// The six face cameras (order of cube_face_names()), each `size` x `size`, fov 90.
std::array<Camera, 6> cube_face_cameras(const Camera& front, int size);

// Renders the six faces. Every face gets the G-buffer, AO, direct, emission and env
// (a surround-aware network must see the sunlit patch behind the camera); the
// path-traced `indirect` target only `front`, unless gi_on_all_faces (5x the time).
std::array<data::View, 6> render_surround(const RayTracer& rt, const Camera& front, int size, const RenderSettings& s,
                                          uint64_t frame_id, bool gi_on_all_faces = false,
                                          RenderStats* stats = nullptr);

}  // namespace nns::render
