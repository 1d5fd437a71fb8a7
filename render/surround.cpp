#include "render/surround.h"

#include <algorithm>

namespace nns::render {

std::array<Camera, 6> cube_face_cameras(const Camera& f, int size) {
  const Vec3 R = f.right, U = f.up, B = f.back;
  // {right, up, back} of each face in world space: a face looking along direction D
  // with image-up V has back = -D and right = cross(V, back) (right-handed, R x U = B).
  const Vec3 axes[6][3] = {
      {R, U, B},    // front: looks -B
      {-R, U, -B},  // back: looks +B (yaw 180)
      {-B, U, R},   // left: looks -R (yaw +90)
      {B, U, -R},   // right: looks +R (yaw -90)
      {R, B, -U},   // up: looks +U, image up +B (towards the back)
      {R, -B, U},   // down: looks -U, image up -B
  };
  std::array<Camera, 6> cams;
  for (int i = 0; i < 6; ++i) {
    Camera c;
    c.eye = f.eye;
    c.right = axes[i][0], c.up = axes[i][1], c.back = axes[i][2];
    c.fov_y_deg = 90;
    c.width = c.height = size;
    cams[i] = c;
  }
  return cams;
}

std::array<data::View, 6> render_surround(const RayTracer& rt, const Camera& front, int size, const RenderSettings& s,
                                          uint64_t frame_id, bool gi_on_all_faces, RenderStats* stats) {
  auto cams = cube_face_cameras(front, size);
  std::array<data::View, 6> views;
  for (int i = 0; i < 6; ++i) {
    RenderSettings fs = s;
    if (i != 0 && !gi_on_all_faces) {
      fs.indirect = false;
      // env alone is smooth (no bright off-screen patches to find): 64 rays suffice.
      fs.gi_spp = std::min(fs.gi_spp, 64);
      if (s.side_spp > 0) fs.ao_spp = fs.gi_spp = s.side_spp;
    }
    views[i] = render_view(rt, cams[i], fs, frame_id * 6 + uint64_t(i), &cams[0], stats);
  }
  return views;
}

}  // namespace nns::render
