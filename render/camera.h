#pragma once
// Camera: a pinhole camera in the spec's convention (docs/dataset-format.md): OpenGL
// camera space (x right, y up, looking down -z), vertical fovY, square pixels,
// principal point at the image centre, pixel centres at +0.5, row 0 at the top.
#include <array>
#include <cmath>

#include "render/sampling.h"
#include "core/vec3.h"

namespace nns::render {

struct Camera {
  Vec3 eye;
  Vec3 right{1, 0, 0}, up{0, 1, 0}, back{0, 0, 1};  // world-space camera axes
  float fov_y_deg = 60;
  int width = 320, height = 180;

  Vec3 forward() const { return -back; }

  // Camera looking from `eye` at `target`; `world_up` must not be parallel to the view.
  static Camera look_at(Vec3 eye, Vec3 target, Vec3 world_up = {0, 1, 0}) {
    Camera c;
    c.eye = eye;
    c.back = normalize(eye - target);
    c.right = normalize(cross(world_up, c.back));
    c.up = cross(c.back, c.right);
    return c;
  }
  // Yaw about +y (0 looks down -z, positive turns left), then pitch (positive looks up).
  static Camera from_yaw_pitch(Vec3 eye, float yaw_rad, float pitch_rad) {
    Vec3 f(-std::sin(yaw_rad) * std::cos(pitch_rad), std::sin(pitch_rad), -std::cos(yaw_rad) * std::cos(pitch_rad));
    return look_at(eye, eye + f);
  }

  // Unit world-space direction through the centre of pixel (px, py), and the factor
  // that turns distance along it into planar depth (z = t * depth_per_t).
  Vec3 pixel_ray(int px, int py, float& depth_per_t) const {
    float tan_half = std::tan(fov_y_deg * kPi / 360.0f);
    float x = (2.0f * (float(px) + 0.5f) / float(width) - 1.0f) * tan_half * float(width) / float(height);
    float y = (1.0f - 2.0f * (float(py) + 0.5f) / float(height)) * tan_half;
    float len = std::sqrt(x * x + y * y + 1.0f);
    depth_per_t = 1.0f / len;
    return (right * x + up * y - back) / len;
  }

  // World vector -> this camera's space (no translation).
  Vec3 to_camera(Vec3 v) const { return {dot(v, right), dot(v, up), dot(v, back)}; }

  // The view matrix, row-major (the `worldToCamera` attribute).
  std::array<float, 16> world_to_camera() const {
    return {right.x, right.y, right.z, -dot(right, eye), up.x, up.y, up.z, -dot(up, eye),
            back.x,  back.y,  back.z,  -dot(back, eye),  0,    0,    0,    1};
  }
};

}  // namespace nns::render
