#pragma once
// HBAO (Bavoil, Sainz & Dimitrov 2008): march `steps` pixels along each of `dirs`
// screen directions (rotated per pixel by a 4x4 noise tile, step start jittered); along
// a direction keep the highest horizon elevation seen so far above the tangent plane,
// and each time it rises add the rise, sin(h_i) - sin(h_{i-1}), attenuated by
// W = 1 - d^2 / r^2 at the sample's distance d. AO = 1 - mean over directions; then a
// 4x4 box blur. Off-screen samples are invisible to it (a screen-space limitation).
// samples = dirs x steps: 16 = 4x4, 32 = 8x4, 64 = 8x8.
//
// hbao() marches 16 pixels of a row at once (simd16.h; a lane whose march left the
// screen is masked off, the vector form of `break`), with the directions' cosines and
// sines from per-row tables and 1/r^2 instead of a division per step; hbao_reference()
// is the scalar loop it must match (tests compare them).
#include <cmath>
#include <vector>

#include "classical_ao/screen_space_names.h"

namespace nns::classical_ao {

// Free parameters (tune-classical-ao fits them; the defaults are the values used before).
struct HbaoParams {
  float angle_bias = 0.1f;    // sin of ~6 degrees: hides tessellation-level creases
  float radius_scale = 1.0f;  // multiplies the view's AO radius (march extent and attenuation)
};

inline void hbao_layout(int samples, int& dirs, int& steps) {
  dirs = samples >= 32 ? 8 : (samples >= 4 ? 4 : samples);
  if (dirs < 1) dirs = 1;
  steps = samples / dirs < 1 ? 1 : samples / dirs;
}

inline void hbao_reference_with(const GBuffer& g, int samples, float* out, const HbaoParams& p) {
  int dirs, steps;
  hbao_layout(samples, dirs, steps);
  std::vector<float> raw(size_t(g.pixels()));
  const float r = g.radius * p.radius_scale, r2 = r * r;
  const float angle_bias = p.angle_bias;
  for_each_surface_pixel(g, raw.data(), [&](int x, int y, int64_t i, const Vec3& P, const Vec3& N) -> float {
    const float r_px = r * 0.5f * float(g.width) / (g.sx * -P.z);
    if (r_px < 1.0f) {
      return 1;
    }
    const float rot = noise_angle_4x4(x, y);
    const float jitter = hash_unit(pixel_hash(uint32_t(x & 3), uint32_t(y & 3), 7));
    const float step_px = r_px / float(steps);
    float sum = 0;
    for (int d = 0; d < dirs; ++d) {
      const float a = rot + 6.2831853f * float(d) / float(dirs);
      const float dx = std::cos(a), dy = std::sin(a);
      float sin_prev = angle_bias, ao = 0;
      for (int s = 0; s < steps; ++s) {
        const float t = (float(s) + jitter) * step_px + 1.0f;
        const float qx = float(x) + dx * t, qy = float(y) + dy * t;
        if (!g.on_screen(qx, qy)) break;
        int jx, jy;
        g.clamped_pixel(qx, qy, jx, jy);
        const int64_t j = int64_t(jy) * g.width + jx;
        if (g.sky(j)) continue;
        const Vec3 V = g.position(jx, jy) - P;
        const float d2 = dot(V, V);
        if (d2 > r2 || d2 <= 0) continue;
        const float sin_h = dot(N, V) / std::sqrt(d2);
        if (sin_h > sin_prev) {
          ao += (1.0f - d2 / r2) * (sin_h - sin_prev);
          sin_prev = sin_h;
        }
      }
      sum += ao;
    }
    return saturate(1.0f - sum / float(dirs));
  });
  box_blur_4x4_reference(g, raw.data(), out);
}

inline void hbao_reference(const GBuffer& g, int samples, float* out) {
  hbao_reference_with(g, samples, out, HbaoParams{});
}

inline void hbao_with(const GBuffer& g, int samples, float* out, const HbaoParams& p) {
  using namespace screen_space::simd;
  int dirs, steps;
  hbao_layout(samples, dirs, steps);
  std::vector<float> raw(size_t(g.pixels()));
  const float r = g.radius * p.radius_scale, r2 = r * r, inv_r2 = 1.0f / r2;
  const float angle_bias = p.angle_bias;
  const NoiseTile noise;
  // Per row class yq = y & 3 and lane: each direction's (cos, sin), and the step jitter.
  std::vector<float> dcos(size_t(4 * dirs * kLanes)), dsin(dcos.size());
  alignas(64) float jitter[4][kLanes];
  for (int yq = 0; yq < 4; ++yq)
    for (int l = 0; l < kLanes; ++l) {
      jitter[yq][l] = hash_unit(pixel_hash(uint32_t(l & 3), uint32_t(yq), 7));
      for (int d = 0; d < dirs; ++d) {
        const float a = noise.angle[yq][l] + 6.2831853f * float(d) / float(dirs);
        dcos[size_t((yq * dirs + d) * kLanes + l)] = std::cos(a);
        dsin[size_t((yq * dirs + d) * kLanes + l)] = std::sin(a);
      }
    }
  for_each_block(g, [&](int x0, int y, Mask valid) {
    const Block b(g, x0, y, valid);
    const VF zero = splat(0.0f), one = splat(1.0f);
    const VF r_px = splat(r * 0.5f * float(g.width)) / (splat(g.sx) * b.z);
    const Mask live = b.live & ~lt(r_px, one);  // under a pixel: nothing to march
    VF sum = zero;
    if (live) {
      VF nx, ny, nz;
      load_unit_normals(g, b.i0, valid, nx, ny, nz);
      const VF jit = load(jitter[y & 3]);
      const VF step_px = r_px / splat(float(steps));
      for (int d = 0; d < dirs; ++d) {
        const VF dx = load(dcos.data() + size_t(((y & 3) * dirs + d) * kLanes));
        const VF dy = load(dsin.data() + size_t(((y & 3) * dirs + d) * kLanes));
        VF sin_prev = splat(angle_bias), ao = zero;
        Mask alive = live;
        for (int s = 0; s < steps && alive; ++s) {
          const VF t = (splat(float(s)) + jit) * step_px + one;
          const VF qx = b.X + dx * t, qy = b.Y + dy * t;
          VF vx, vy, vz;
          Mask m = b.sample(g, qx, qy, alive, vx, vy, vz);
          const VF d2 = vx * vx + vy * vy + vz * vz;
          m &= ~gt(d2, splat(r2)) & ~le(d2, zero);
          const VF sin_h = (nx * vx + ny * vy + nz * vz) / sqrt(d2);
          const Mask up = m & gt(sin_h, sin_prev);
          ao = select(up, ao + (one - d2 * splat(inv_r2)) * (sin_h - sin_prev), ao);
          sin_prev = select(up, sin_h, sin_prev);
        }
        sum = sum + ao;
      }
    }
    const VF res = saturate(one - sum / splat(float(dirs)));
    store(raw.data() + b.i0, select(live, res, one), valid);
  });
  box_blur_4x4(g, raw.data(), out);
}

inline void hbao(const GBuffer& g, int samples, float* out) { hbao_with(g, samples, out, HbaoParams{}); }

}  // namespace nns::classical_ao
