#pragma once
// The G-buffer as every AO method reads it: planar depth and camera-space normals of
// one view, plus the camera model of docs/dataset-format.md. This is the one place
// that turns a pixel and its depth into a view-space position and back; NNAO's
// features and every classical baseline go through it, so they agree on the geometry.
//
// View space is OpenGL's: x right, y up, the camera looks down -z. For pixel (px, py)
// (centre at +0.5, row 0 at the top) with planar depth z:
//   x = (2(px+0.5)/W - 1) * tan(fovY/2) * (W/H) * z,  y = (1 - 2(py+0.5)/H) * tan(fovY/2) * z,
//   position = (x, y, -z).
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/vec3.h"
#include "data/view.h"

namespace nns::screen_space {

// A normal from the G-buffer as a unit vector: (1/l) * a (one division for three
// products, in the inner loops), and for a zero vector (a pixel without a normal) the
// direction that faces the camera, (0, 0, 1), not nns::normalize's zero.
inline Vec3 normalize_or_facing(Vec3 a) {
  float l = length(a);
  return l > 0 ? (1.0f / l) * a : Vec3{0, 0, 1};
}

// Non-owning: the planes belong to the View (or the test) that made it.
struct GBuffer {
  int width = 0, height = 0;
  float radius = 1;              // world-space AO radius (the view's aoRadius)
  float sx = 1, sy = 1;          // tan(fovY/2) * W/H and tan(fovY/2)
  float inv_w2 = 1, inv_h2 = 1;  // 2/W and 2/H: position() multiplies, never divides
  const float* z = nullptr;      // planar depth, sky = inf or >= 1e30
  const float* nx = nullptr;
  const float* ny = nullptr;
  const float* nz = nullptr;

  int64_t pixels() const { return int64_t(width) * height; }
  bool sky(int64_t i) const { return data::is_sky(z[i]); }
  Vec3 normal(int64_t i) const { return {nx[i], ny[i], nz[i]}; }

  // View-space position of a (possibly fractional) pixel coordinate at depth d.
  Vec3 position(float px, float py, float d) const {
    return {((px + 0.5f) * inv_w2 - 1) * sx * d, (1 - (py + 0.5f) * inv_h2) * sy * d, -d};
  }
  Vec3 position(int px, int py) const { return position(float(px), float(py), z[int64_t(py) * width + px]); }
  // Pixel coordinate (continuous, pixel centres at integers) where view-space point p
  // lands. p must be in front of the camera (p.z < 0).
  void project(Vec3 p, float& px, float& py) const {
    float d = -p.z;
    px = (p.x / (sx * d) + 1) * 0.5f * float(width) - 0.5f;
    py = (1 - p.y / (sy * d)) * 0.5f * float(height) - 0.5f;
  }
  // Nearest pixel to a continuous coordinate, clamped to the screen edge. Rounds half
  // up (floor(x + 0.5)), as a shader's texel fetch does; cheaper than lround.
  void clamped_pixel(float px, float py, int& ix, int& iy) const {
    ix = int(std::floor(px + 0.5f));
    iy = int(std::floor(py + 0.5f));
    ix = ix < 0 ? 0 : (ix >= width ? width - 1 : ix);
    iy = iy < 0 ? 0 : (iy >= height ? height - 1 : iy);
  }
  int64_t clamped_index(float px, float py) const {
    int ix, iy;
    clamped_pixel(px, py, ix, iy);
    return int64_t(iy) * width + ix;
  }
  bool on_screen(float px, float py) const {
    return px > -0.5f && py > -0.5f && px < float(width) - 0.5f && py < float(height) - 0.5f;
  }
};

inline GBuffer make_gbuffer(int width, int height, float fov_y_deg, float radius, const float* z, const float* nx,
                            const float* ny, const float* nz) {
  GBuffer g;
  g.width = width;
  g.height = height;
  g.radius = radius;
  g.sy = std::tan(fov_y_deg * 3.14159265358979f / 360.0f);
  g.sx = g.sy * float(width) / float(height);
  g.inv_w2 = 2.0f / float(width);
  g.inv_h2 = 2.0f / float(height);
  g.z = z;
  g.nx = nx;
  g.ny = ny;
  g.nz = nz;
  return g;
}

// Checks what AO needs (Z, N.*, fovY, a radius) and that the values mean something:
// depth > 0 or +inf (sky, docs/dataset-format.md), never NaN, zero or negative; normals
// and ground-truth AO finite. A NaN that got through used to train an all-NaN model and
// score NaN with exit 0. The error names the file, the channel and the pixel.
// `radius` <= 0 means "use the view's aoRadius".
inline GBuffer gbuffer_from_view(const data::View& v, float radius = 0) {
  const std::string where = v.source.empty() ? std::string("view") : v.source;
  for (const char* c : {"Z", "N.X", "N.Y", "N.Z"})
    if (!v.has(c)) throw std::runtime_error(where + ": missing channel '" + c + "'");
  if (!(v.fov_y_deg > 0 && v.fov_y_deg < 180))
    throw std::runtime_error(where + ": fovY missing or out of range (" + std::to_string(v.fov_y_deg) + ")");
  if (radius <= 0) {
    if (!v.ao_radius || !(*v.ao_radius > 0))
      throw std::runtime_error(where + ": no aoRadius attribute (needed for the AO radius)");
    radius = *v.ao_radius;
  }
  auto refuse = [&](const char* channel, size_t i, const char* what) {
    throw std::runtime_error(where + ": channel '" + channel + "' is " + what + " at pixel (" +
                             std::to_string(i % size_t(v.width)) + ", " + std::to_string(i / size_t(v.width)) + ")");
  };
  const auto& z = v.channel("Z");
  for (size_t i = 0; i < z.size(); ++i)
    if (!(z[i] > 0)) refuse("Z", i, std::isnan(z[i]) ? "NaN" : "not positive");
  for (const char* c : {"N.X", "N.Y", "N.Z", "AO"}) {
    if (!v.has(c)) continue;
    const auto& p = v.channel(c);
    for (size_t i = 0; i < p.size(); ++i)
      if (!std::isfinite(p[i])) refuse(c, i, std::isnan(p[i]) ? "NaN" : "infinite");
  }
  return make_gbuffer(v.width, v.height, v.fov_y_deg, radius, z.data(), v.channel("N.X").data(),
                      v.channel("N.Y").data(), v.channel("N.Z").data());
}

// Cheap deterministic per-pixel noise (integer hash): the same frame always gets the
// same jitter, independent of the thread that computes it.
inline uint32_t pixel_hash(uint32_t x, uint32_t y, uint32_t salt = 0) {
  uint32_t h = x * 0x8da6b343u ^ y * 0xd8163841u ^ salt * 0xcb1ab31fu;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}
inline float hash_unit(uint32_t h) { return float(h >> 8) * 0x1.0p-24f; }

}  // namespace nns::screen_space
