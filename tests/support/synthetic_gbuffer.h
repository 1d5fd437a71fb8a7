#pragma once
// A tiny analytic G-buffer for AO tests: axis-aligned boxes in view space (a floor, a
// back wall that stops short so some sky shows, and a cube or two that `variant`
// moves), ray-cast per pixel, with ground-truth AO by cosine-weighted Monte Carlo
// against the same boxes. No renderer, no files: tests own every number.
#include <cmath>
#include <limits>
#include <vector>

#include "core/rng.h"
#include "data/view.h"

namespace nns::testing {

struct Box {
  float lo[3], hi[3];
};

inline std::vector<Box> synthetic_boxes(int variant) {
  float s = float(variant % 5) * 0.35f - 0.7f;
  std::vector<Box> b = {
      {{-30, -2.0f, -30}, {30, -1.0f, 30}},        // floor, top at y = -1
      {{-30, -1.0f, -9.0f}, {2.5f, 4.0f, -8.0f}},  // back wall, ends at x = 2.5 (sky beyond)
      {{-1.2f + s, -1.0f, -5.0f + 0.3f * float(variant % 3)}, {-0.2f + s, 0.0f, -4.0f}},
      {{1.0f - s, -1.0f, -6.5f}, {1.3f - s, 1.5f, -6.2f}},  // a thin pillar
  };
  return b;
}

// Nearest hit of ray o + t d (t > tmin) with the boxes; returns t or inf, and the normal.
inline float ray_boxes(const std::vector<Box>& boxes, const float o[3], const float d[3],
                       float n[3], float tmin = 1e-4f) {
  float best = std::numeric_limits<float>::infinity();
  for (const Box& b : boxes) {
    float t0 = -1e30f, t1 = 1e30f;
    int axis = -1;
    float sign = 0;
    bool miss = false;
    for (int a = 0; a < 3; ++a) {
      if (std::abs(d[a]) < 1e-12f) {
        if (o[a] < b.lo[a] || o[a] > b.hi[a]) miss = true;
        continue;
      }
      float ta = (b.lo[a] - o[a]) / d[a], tb = (b.hi[a] - o[a]) / d[a];
      float sg = -1;
      if (ta > tb) std::swap(ta, tb), sg = 1;
      if (ta > t0) t0 = ta, axis = a, sign = d[a] > 0 ? -1.0f : 1.0f;
      (void)sg;
      t1 = std::min(t1, tb);
    }
    if (miss || t0 > t1 || t0 <= tmin || axis < 0) continue;
    if (t0 < best) {
      best = t0;
      n[0] = n[1] = n[2] = 0;
      n[axis] = sign;
    }
  }
  return best;
}

// width x height view looking down -z from the origin; AO with `spp` cosine samples.
inline data::View synthetic_view(int width, int height, int variant, int spp = 64,
                                 float radius = 1.0f, float fov_y = 60.0f) {
  data::View v;
  v.width = width;
  v.height = height;
  v.fov_y_deg = fov_y;
  v.ao_radius = radius;
  v.scene = "synthetic" + std::to_string(variant % 2);
  auto& Z = v.add_channel("Z");
  auto& NX = v.add_channel("N.X");
  auto& NY = v.add_channel("N.Y");
  auto& NZ = v.add_channel("N.Z");
  auto& AO = v.add_channel("AO");
  auto boxes = synthetic_boxes(variant);
  float ty = std::tan(fov_y * 3.14159265f / 360), tx = ty * float(width) / float(height);
  Rng rng(1000 + uint64_t(variant));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      size_t i = size_t(y) * width + x;
      float o[3] = {0, 0, 0};
      float d[3] = {(2 * (x + 0.5f) / width - 1) * tx, (1 - 2 * (y + 0.5f) / height) * ty, -1};
      float n[3];
      float t = ray_boxes(boxes, o, d, n);
      if (!(t < 1e29f)) {
        Z[i] = std::numeric_limits<float>::infinity();
        AO[i] = 1;
        continue;
      }
      Z[i] = t;  // d.z = -1: the ray parameter is the planar depth
      NX[i] = n[0], NY[i] = n[1], NZ[i] = n[2];
      float p[3] = {d[0] * t + n[0] * 1e-3f, d[1] * t + n[1] * 1e-3f, -t + n[2] * 1e-3f};
      // Tangent frame around n (axis aligned), cosine-weighted directions.
      float tvec[3] = {0, 0, 0}, bvec[3];
      tvec[std::abs(n[0]) > 0.5f ? 1 : 0] = 1;
      bvec[0] = n[1] * tvec[2] - n[2] * tvec[1];
      bvec[1] = n[2] * tvec[0] - n[0] * tvec[2];
      bvec[2] = n[0] * tvec[1] - n[1] * tvec[0];
      int visible = 0;
      for (int s = 0; s < spp; ++s) {
        float u1 = float(rng.uniform()), u2 = float(rng.uniform());
        float rr = std::sqrt(u1), phi = 6.2831853f * u2;
        float a = rr * std::cos(phi), b = rr * std::sin(phi), c = std::sqrt(std::max(0.0f, 1 - u1));
        float dir[3];
        for (int k = 0; k < 3; ++k) dir[k] = a * tvec[k] + b * bvec[k] + c * n[k];
        float nn[3];
        float th = ray_boxes(boxes, p, dir, nn);
        visible += !(th < radius);
      }
      AO[i] = float(visible) / float(spp);
    }
  return v;
}

}  // namespace nns::testing
