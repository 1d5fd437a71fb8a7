#pragma once
// SSAO+ (the normal-oriented hemisphere method of the 2015 deferred-rendering report,
// after Chapman): a hemisphere kernel around the normal with samples clustered near the
// origin (lengths scaled by lerp(0.1, 1, (i/n)^2)), rotated about the normal by a 4x4
// noise tile, a sample counting as occluded when the depth buffer is in front of it by
// more than a small bias, weighted by the range check smoothstep(0, 1, r / |z - zbuf|);
// AO = 1 - occluded / n, then a 4x4 box blur.
#include <vector>

#include "models/classical_ao/common.h"

namespace nns::ao {

inline std::vector<Vec3> hemisphere_kernel(int n, uint64_t seed) {
  std::vector<Vec3> k = sphere_kernel(n, seed);
  for (int i = 0; i < n; ++i) {
    Vec3 v = normalize(k[size_t(i)]);
    v.z = std::abs(v.z);
    float t = float(i) / float(n);
    float scale = 0.1f + 0.9f * t * t;
    k[size_t(i)] = (scale * length(k[size_t(i)])) * v;
  }
  return k;
}

inline float smoothstep01(float x) {
  x = saturate(x);
  return x * x * (3 - 2 * x);
}

inline void ssao_plus(const GBuffer& g, int samples, float* out) {
  const std::vector<Vec3> kernel = hemisphere_kernel(samples, 0x5A0B + uint64_t(samples));
  std::vector<float> raw(size_t(g.pixels()));
  const float r = g.radius, bias = 0.05f * r;
  for_each_pixel(g, [&](int x, int y, int64_t i) {
    if (g.sky(i)) {
      raw[size_t(i)] = 1;
      return;
    }
    const Vec3 P = g.position(x, y);
    const Vec3 N = normalize(g.normal(i));
    const float a = noise_angle_4x4(x, y);
    // Gram-Schmidt of the noise vector against the normal gives the tangent frame.
    Vec3 rv{std::cos(a), std::sin(a), 0};
    Vec3 T = rv - dot(rv, N) * N;
    if (dot(T, T) < 1e-6f) T = Vec3{0, 0, 1} - N.z * N;
    T = normalize(T);
    const Vec3 B = cross(N, T);
    float occlusion = 0;
    for (const Vec3& k : kernel) {
      const Vec3 S = P + r * (k.x * T + k.y * B + k.z * N);
      if (S.z >= 0) continue;
      float sx, sy;
      g.project(S, sx, sy);
      const float zb = g.z[g.clamped_index(sx, sy)];
      if (zb < -S.z - bias) {
        float dz = std::abs(-P.z - zb);
        occlusion += dz > 0 ? smoothstep01(r / dz) : 1.0f;
      }
    }
    raw[size_t(i)] = 1.0f - occlusion / float(samples);
  });
  box_blur_4x4(g, raw.data(), out);
}

}  // namespace nns::ao
