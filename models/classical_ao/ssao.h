#pragma once
// SSAO as in Crysis (Mittring 2007): points in a sphere of radius r around the pixel's
// view-space position, each counted as occluded when it lies behind the depth buffer
// (within r of it: the range check), the kernel rotated by a 4x4 noise tile, then a
// 4x4 box blur.
//
// The sphere test has no normal, so an open flat surface already hides half the
// sphere. We report AO = clamp(2 (1 - occluded / n), 0, 1): 1 on an open plane and, in
// expectation, 0.5 in a right-angle crease — the same values the ground truth gives
// there, so the comparison measures the method, not a constant offset.
#include <vector>

#include "models/classical_ao/common.h"

namespace nns::ao {

inline void ssao(const GBuffer& g, int samples, float* out) {
  const std::vector<Vec3> kernel = sphere_kernel(samples, 0x55A0 + uint64_t(samples));
  std::vector<float> raw(size_t(g.pixels()));
  const float r = g.radius;
  for_each_pixel(g, [&](int x, int y, int64_t i) {
    if (g.sky(i)) {
      raw[size_t(i)] = 1;
      return;
    }
    const Vec3 P = g.position(x, y);
    const float a = noise_angle_4x4(x, y), c = std::cos(a), s = std::sin(a);
    int occluded = 0;
    for (const Vec3& k0 : kernel) {
      const Vec3 S = P + r * Vec3{c * k0.x - s * k0.y, s * k0.x + c * k0.y, k0.z};
      if (S.z >= 0) continue;
      float sx, sy;
      g.project(S, sx, sy);
      const float zb = g.z[g.clamped_index(sx, sy)];
      const float behind = -S.z - zb;
      occluded += (behind > 0.0f && behind < r);
    }
    raw[size_t(i)] = saturate(2.0f * (1.0f - float(occluded) / float(samples)));
  });
  box_blur_4x4(g, raw.data(), out);
}

}  // namespace nns::ao
