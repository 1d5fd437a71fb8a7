#pragma once
// Alchemy AO (McGuire et al. 2011), the modern baseline: s samples on a spiral over the
// screen-space disc that the radius r covers at the pixel's depth, each with v = Q - P,
//   A = max(0, 1 - (2 sigma r / s) * sum max(0, v.n - beta r) / (v.v + eps r^2)),
// counting only samples with |v| < r; then a 4x4 box blur. The paper's constants are in
// scene units; here they scale with r (beta = 0.01, eps = 0.01). sigma = 0.35 puts a
// right-angle crease at about 0.5, the value of the true (cosine-weighted) AO there:
// derived from the geometry, not fitted to any dataset.
#include <cmath>
#include <vector>

#include "models/classical_ao/common.h"

namespace nns::ao {

inline void alchemy_ao(const GBuffer& g, int samples, float* out) {
  std::vector<float> raw(size_t(g.pixels()));
  const float r = g.radius, r2 = r * r;
  const float sigma = 0.35f, beta = 0.01f * r, eps = 0.01f * r2;
  const float turns = 7.0f;
  for_each_pixel(g, [&](int x, int y, int64_t i) {
    if (g.sky(i)) {
      raw[size_t(i)] = 1;
      return;
    }
    const Vec3 P = g.position(x, y);
    const Vec3 N = normalize(g.normal(i));
    const float r_px = r * 0.5f * float(g.width) / (g.sx * -P.z);
    const float rot = noise_angle_4x4(x, y);
    float sum = 0;
    for (int k = 0; k < samples; ++k) {
      const float alpha = (float(k) + 0.5f) / float(samples);
      const float a = 6.2831853f * alpha * turns + rot;
      const float qx = float(x) + std::cos(a) * alpha * r_px;
      const float qy = float(y) + std::sin(a) * alpha * r_px;
      int jx, jy;
        g.clamped_pixel(qx, qy, jx, jy);
        const int64_t j = int64_t(jy) * g.width + jx;
      if (g.sky(j)) continue;
      const Vec3 v = g.position(jx, jy) - P;
      const float vv = dot(v, v);
      if (vv >= r2) continue;
      sum += std::max(0.0f, dot(v, N) - beta) / (vv + eps);
    }
    raw[size_t(i)] = std::max(0.0f, 1.0f - 2.0f * sigma * r / float(samples) * sum);
  });
  box_blur_4x4(g, raw.data(), out);
}

}  // namespace nns::ao
