#pragma once
// SSAO+ (the normal-oriented hemisphere method of the 2015 deferred-rendering report,
// after Chapman): a hemisphere kernel around the normal with samples clustered near the
// origin (lengths scaled by lerp(0.1, 1, (i/n)^2)), rotated about the normal by a 4x4
// noise tile, a sample counting as occluded when the depth buffer is in front of it by
// more than a small bias, weighted by the range check smoothstep(0, 1, r / |z - zbuf|);
// AO = 1 - occluded / n, then a 4x4 box blur.
//
// ssao_plus() runs 16 pixels of a row at once (simd16.h); ssao_plus_reference() is the
// scalar per-pixel loop it must match (tests compare them).
#include <vector>

#include "classical_ao/screen_space_names.h"

namespace nns::classical_ao {

inline std::vector<Vec3> hemisphere_kernel(int n, uint64_t seed) {
  std::vector<Vec3> k = sphere_kernel(n, seed);
  for (int i = 0; i < n; ++i) {
    Vec3 v = normalize_or_facing(k[size_t(i)]);
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

// Free parameters (tune-classical-ao fits them; the defaults are the values used before).
struct SsaoPlusParams {
  float bias = 0.05f;  // of the radius
  float radius_scale = 1.0f;
};

inline void ssao_plus_reference_with(const GBuffer& g, int samples, float* out, const SsaoPlusParams& p) {
  const std::vector<Vec3> kernel = hemisphere_kernel(samples, 0x5A0B + uint64_t(samples));
  std::vector<float> raw(size_t(g.pixels()));
  const float r = g.radius * p.radius_scale, bias = p.bias * r;
  for_each_surface_pixel(g, raw.data(), [&](int x, int y, int64_t i, const Vec3& P, const Vec3& N) -> float {
    const float a = noise_angle_4x4(x, y);
    // Gram-Schmidt of the noise vector against the normal gives the tangent frame.
    Vec3 rv{std::cos(a), std::sin(a), 0};
    Vec3 T = rv - dot(rv, N) * N;
    if (dot(T, T) < 1e-6f) T = Vec3{0, 0, 1} - N.z * N;
    T = normalize_or_facing(T);
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
    return 1.0f - occlusion / float(samples);
  });
  box_blur_4x4_reference(g, raw.data(), out);
}

inline void ssao_plus_reference(const GBuffer& g, int samples, float* out) {
  ssao_plus_reference_with(g, samples, out, SsaoPlusParams{});
}

inline void ssao_plus_with(const GBuffer& g, int samples, float* out, const SsaoPlusParams& p) {
  using namespace screen_space::simd;
  const std::vector<Vec3> kernel = hemisphere_kernel(samples, 0x5A0B + uint64_t(samples));
  const NoiseTile noise;
  std::vector<float> raw(size_t(g.pixels()));
  const float r = g.radius * p.radius_scale, bias = p.bias * r;
  for_each_block(g, [&](int x0, int y, Mask valid) {
    const Block b(g, x0, y, valid);
    const VF zero = splat(0.0f), one = splat(1.0f), R = splat(r);
    // normalize_or_facing(N), with its fallback (0, 0, 1) for a zero vector.
    VF nx, ny, nz;
    load_unit_normals(g, b.i0, valid, nx, ny, nz);
    const VF rvx = load(noise.cos[y & 3]), rvy = load(noise.sin[y & 3]);
    const VF rn = rvx * nx + rvy * ny;  // dot(rv, N), rv.z = 0
    VF tx = rvx - rn * nx, ty = rvy - rn * ny, tz = zero - rn * nz;
    const Mask degenerate = lt(tx * tx + ty * ty + tz * tz, splat(1e-6f));
    tx = select(degenerate, zero - nz * nx, tx);
    ty = select(degenerate, zero - nz * ny, ty);
    tz = select(degenerate, one - nz * nz, tz);
    normalize_or_facing(tx, ty, tz);
    const VF bx = ny * tz - nz * ty, by = nz * tx - nx * tz, bz = nx * ty - ny * tx;
    const VF pz = -b.z;
    VF occlusion = zero;
    for (const Vec3& k : kernel) {
      const VF kx = splat(k.x), ky = splat(k.y), kz = splat(k.z);
      const VF sx = b.px + R * (kx * tx + ky * bx + kz * nx);
      const VF sy = b.py + R * (kx * ty + ky * by + kz * ny);
      const VF sz = pz + R * (kx * tz + ky * bz + kz * nz);
      Mask m = b.live & lt(sz, zero);
      if (!m) continue;
      VF qx, qy;
      VI ix, iy;
      project(g, sx, sy, -sz, qx, qy);
      clamped_pixel(g, qx, qy, ix, iy);
      const VF zb = gather(g.z, pixel_index(g, ix, iy), m, 0.0f);
      m &= lt(zb, -sz - splat(bias));
      const VF dz = abs(b.z - zb);
      const VF x = saturate(R / dz);
      const VF w = select(gt(dz, zero), x * x * (splat(3.0f) - splat(2.0f) * x), one);
      occlusion = occlusion + select(m, w, zero);
    }
    const VF ao = one - occlusion / splat(float(samples));
    store(raw.data() + b.i0, select(b.live, ao, one), valid);
  });
  box_blur_4x4(g, raw.data(), out);
}

inline void ssao_plus(const GBuffer& g, int samples, float* out) { ssao_plus_with(g, samples, out, SsaoPlusParams{}); }

}  // namespace nns::classical_ao
