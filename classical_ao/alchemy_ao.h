#pragma once
// Alchemy AO (McGuire et al. 2011), the modern baseline: s samples on a spiral over the
// screen-space disc that the radius r covers at the pixel's depth, each with v = Q - P,
//   A = max(0, 1 - (2 sigma r / s) * sum max(0, v.n - beta r) / (v.v + eps r^2)),
// counting only samples with |v| < r; then a 4x4 box blur. The paper's constants are in
// scene units; here they scale with r (beta = 0.01, eps = 0.01). sigma = 0.35 puts a
// right-angle crease at about 0.5, the value of the true (cosine-weighted) AO there:
// derived from the geometry, not fitted to any dataset.
//
// alchemy_ao() runs 16 pixels of a row at once (simd16.h), with the spiral's cosines and
// sines from per-row tables; alchemy_ao_reference() is the scalar loop it must match.
#include <cmath>
#include <vector>

#include "classical_ao/screen_space_names.h"

namespace nns::classical_ao {

// Free parameters (tune-classical-ao fits them; the defaults are the values used before).
// kappa is the paper's contrast exponent, A^kappa (1: none).
struct AlchemyParams {
  float sigma = 0.35f, beta = 0.01f, eps = 0.01f, kappa = 1.0f;
  float radius_scale = 1.0f;  // multiplies the view's AO radius
};

// A^kappa; kappa = 1 leaves A untouched (bitwise the values before kappa existed).
inline void alchemy_contrast(float* raw, int64_t n, float kappa) {
  if (kappa != 1.0f)
    for (int64_t i = 0; i < n; ++i) raw[i] = std::pow(raw[i], kappa);
}

inline void alchemy_ao_reference_with(const GBuffer& g, int samples, float* out, const AlchemyParams& p) {
  std::vector<float> raw(size_t(g.pixels()));
  const float r = g.radius * p.radius_scale, r2 = r * r;
  const float sigma = p.sigma, beta = p.beta * r, eps = p.eps * r2;
  const float turns = 7.0f;
  for_each_surface_pixel(g, raw.data(), [&](int x, int y, int64_t i, const Vec3& P, const Vec3& N) -> float {
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
    return std::max(0.0f, 1.0f - 2.0f * sigma * r / float(samples) * sum);
  });
  alchemy_contrast(raw.data(), g.pixels(), p.kappa);
  box_blur_4x4_reference(g, raw.data(), out);
}

inline void alchemy_ao_reference(const GBuffer& g, int samples, float* out) {
  alchemy_ao_reference_with(g, samples, out, AlchemyParams{});
}

inline void alchemy_ao_with(const GBuffer& g, int samples, float* out, const AlchemyParams& p) {
  using namespace screen_space::simd;
  std::vector<float> raw(size_t(g.pixels()));
  const float r = g.radius * p.radius_scale, r2 = r * r;
  const float sigma = p.sigma, beta = p.beta * r, eps = p.eps * r2;
  const float turns = 7.0f;
  // cos(a) * alpha and sin(a) * alpha of sample k for the 16 lanes of a row with y & 3 = yq:
  // the products the reference forms first.
  const NoiseTile noise;
  std::vector<float> ca(size_t(4 * samples * kLanes)), sa(ca.size());
  for (int yq = 0; yq < 4; ++yq)
    for (int k = 0; k < samples; ++k)
      for (int l = 0; l < kLanes; ++l) {
        const float alpha = (float(k) + 0.5f) / float(samples);
        const float a = 6.2831853f * alpha * turns + noise.angle[yq][l];
        ca[size_t((yq * samples + k) * kLanes + l)] = std::cos(a) * alpha;
        sa[size_t((yq * samples + k) * kLanes + l)] = std::sin(a) * alpha;
      }
  const float coef = 2.0f * sigma * r / float(samples);
  for_each_block(g, [&](int x0, int y, Mask valid) {
    const Block b(g, x0, y, valid);
    const VF zero = splat(0.0f), one = splat(1.0f);
    VF nx, ny, nz;
    load_unit_normals(g, b.i0, valid, nx, ny, nz);
    const VF r_px = splat(r * 0.5f * float(g.width)) / (splat(g.sx) * b.z);
    const float* cs = ca.data() + size_t((y & 3) * samples * kLanes);
    const float* sn = sa.data() + size_t((y & 3) * samples * kLanes);
    VF sum = zero;
    for (int k = 0; k < samples; ++k) {
      const VF qx = b.X + load(cs + k * kLanes) * r_px, qy = b.Y + load(sn + k * kLanes) * r_px;
      VI ix, iy;
      clamped_pixel(g, qx, qy, ix, iy);
      const VF zj = gather(g.z, pixel_index(g, ix, iy), b.live, INFINITY);
      Mask m = b.live & ~sky(zj);
      if (!m) continue;
      VF vx, vy;
      position(g, to_float(ix), to_float(iy), zj, vx, vy);
      vx = vx - b.px, vy = vy - b.py;
      const VF vz = b.z - zj;  // (-zj) - (-z)
      const VF vv = vx * vx + vy * vy + vz * vz;
      m &= lt(vv, splat(r2));
      const VF term = max(zero, vx * nx + vy * ny + vz * nz - splat(beta)) / (vv + splat(eps));
      sum = sum + select(m, term, zero);
    }
    const VF ao = max(zero, one - splat(coef) * sum);
    store(raw.data() + b.i0, select(b.live, ao, one), valid);
  });
  alchemy_contrast(raw.data(), g.pixels(), p.kappa);
  box_blur_4x4(g, raw.data(), out);
}

inline void alchemy_ao(const GBuffer& g, int samples, float* out) { alchemy_ao_with(g, samples, out, AlchemyParams{}); }

}  // namespace nns::classical_ao
