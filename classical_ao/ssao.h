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
//
// ssao() runs 16 pixels of a row at once (simd16.h); ssao_reference() is the scalar
// per-pixel loop it must match (tests compare them).
#include <vector>

#include "classical_ao/screen_space_names.h"
#include "screen_space/simd16.h"

namespace nns::classical_ao {

// Free parameters (tune-classical-ao fits them; the defaults are the values used before):
// the range check accepts occluders within range * r behind the sample, and gain is the
// 2 of clamp(2 (1 - occluded / n)).
struct SsaoParams {
  float radius_scale = 1.0f, range = 1.0f, gain = 2.0f;
};

inline void ssao_reference_with(const GBuffer& g, int samples, float* out, const SsaoParams& p) {
  const std::vector<Vec3> kernel = sphere_kernel(samples, 0x55A0 + uint64_t(samples));
  std::vector<float> raw(size_t(g.pixels()));
  const float r = g.radius * p.radius_scale, range = p.range * r;
  for_each_surface_pixel(g, raw.data(), [&](int x, int y, int64_t i, const Vec3& P, const Vec3& N) -> float {
    const float a = noise_angle_4x4(x, y), c = std::cos(a), s = std::sin(a);
    int occluded = 0;
    for (const Vec3& k0 : kernel) {
      const Vec3 S = P + r * Vec3{c * k0.x - s * k0.y, s * k0.x + c * k0.y, k0.z};
      if (S.z >= 0) continue;
      float sx, sy;
      g.project(S, sx, sy);
      const float zb = g.z[g.clamped_index(sx, sy)];
      const float behind = -S.z - zb;
      occluded += (behind > 0.0f && behind < range);
    }
    return saturate(p.gain * (1.0f - float(occluded) / float(samples)));
  });
  box_blur_4x4_reference(g, raw.data(), out);
}

inline void ssao_reference(const GBuffer& g, int samples, float* out) {
  ssao_reference_with(g, samples, out, SsaoParams{});
}

inline void ssao_with(const GBuffer& g, int samples, float* out, const SsaoParams& p) {
  using namespace screen_space::simd;
  const std::vector<Vec3> kernel = sphere_kernel(samples, 0x55A0 + uint64_t(samples));
  const NoiseTile noise;
  std::vector<float> raw(size_t(g.pixels()));
  const float r = g.radius * p.radius_scale, range = p.range * r;
  for_each_block(g, [&](int x0, int y, Mask valid) {
    const Block b(g, x0, y, valid);
    const VF c = load(noise.cos[y & 3]), s = load(noise.sin[y & 3]), R = splat(r);
    VF occluded = splat(0.0f);
    for (const Vec3& k0 : kernel) {
      const VF kx = splat(k0.x), ky = splat(k0.y);
      const VF sx = b.px + R * (c * kx - s * ky), sy = b.py + R * (s * kx + c * ky);
      const VF sz = -b.z + R * splat(k0.z);
      Mask m = b.live & lt(sz, splat(0.0f));
      if (!m) continue;
      VF qx, qy;
      VI ix, iy;
      project(g, sx, sy, -sz, qx, qy);
      clamped_pixel(g, qx, qy, ix, iy);
      const VF behind = -sz - gather(g.z, pixel_index(g, ix, iy), m, 0.0f);
      m &= gt(behind, splat(0.0f)) & lt(behind, splat(range));
      occluded = occluded + select(m, splat(1.0f), splat(0.0f));
    }
    const VF ao = saturate(splat(p.gain) * (splat(1.0f) - occluded / splat(float(samples))));
    store(raw.data() + b.i0, select(b.live, ao, splat(1.0f)), valid);
  });
  box_blur_4x4(g, raw.data(), out);
}

inline void ssao(const GBuffer& g, int samples, float* out) { ssao_with(g, samples, out, SsaoParams{}); }

}  // namespace nns::classical_ao
