#pragma once
// A horizon model's exact inference on 16 pixels of a row at once (screen_space/
// simd16.h): the marches of compute_horizon_features (horizon_features.h) with the same
// expressions in the same order, fused with layer 0 — each feature is added into the
// hidden sums as soon as its band ends (feature order q = k * bands + b, then the
// extras, as the per-pixel loop of nnao_exact_per_pixel.h sums them), so no feature
// vector is stored. That loop is the reference this must match (tests compare them).
#include <cmath>

#include "models/nnao/nnao_head_simd.h"
#include "models/nnao/nnao_weights.h"
#include "screen_space/simd16.h"

namespace nns::nnao {

namespace detail {

inline void horizon_block(const NnaoWeights& m, const ao::GBuffer& g, const Block& b, float* out) {
  const HorizonLayout& L = m.input.horizon;
  const int H = m.hidden, per_band = L.steps / L.bands;
  const int64_t F = m.features();
  const VF zero = splat(0.0f), one = splat(1.0f);
  VF h[64];
  for (int k = 0; k < H; ++k) h[k] = zero;
  VF base = one;
  if (b.live) {
    // Layer 0 weight q of hidden unit k is m.w0[k * F + q]: add feature q's value.
    auto add = [&](int64_t q, VF v) {
      const float* wq = m.w0.data() + q;
      for (int k = 0; k < H; ++k) h[k] = h[k] + splat(wq[int64_t(k) * F]) * v;
    };
    VF nx, ny, nz;
    load_unit_normals(g, b.i0, b.valid, nx, ny, nz);
    const float r = g.radius, r2 = r * r;
    const VF R_px = splat(r * 0.5f * float(g.width)) / (splat(g.sx) * b.z);
    const VF sxn = nx, syn = zero - ny, sl = sqrt(sxn * sxn + syn * syn);
    const Mask tilted = gt(sl, splat(1e-4f));
    const VF c0 = select(tilted, sxn / sl, one), s0 = select(tilted, syn / sl, zero);
    VF occluded[64];  // bands <= 64 (HorizonLayout::problem)
    for (int band = 0; band < L.bands; ++band) occluded[band] = zero;
    for (int k = 0; k < L.directions; ++k) {
      const float a = 6.2831853f * float(k) / float(L.directions);
      const float ca = std::cos(a), sa = std::sin(a);
      const VF ox = c0 * splat(ca) - s0 * splat(sa), oy = s0 * splat(ca) + c0 * splat(sa);
      VF horizon = zero;
      Mask alive = b.live;
      for (int s = 0; s < L.steps; ++s) {
        if (alive) {
          const float f = (float(s) + 0.5f) / float(L.steps);
          const VF t = one + splat(f * f) * R_px;
          VF dx, dy, dz;
          Mask hit = b.sample(g, b.X + ox * t, b.Y + oy * t, alive, dx, dy, dz);
          const VF d2 = dx * dx + dy * dy + dz * dz;
          hit &= gt(d2, zero) & le(d2, splat(r2));
          if (hit) {
            const VF e = (nx * dx + ny * dy + nz * dz) / sqrt(select(hit, d2, one));
            horizon = select(hit, max(horizon, e), horizon);
          }
        }
        if ((s + 1) % per_band == 0) {
          const int band = (s + 1) / per_band - 1;
          add(int64_t(k) * L.bands + band, horizon);
          occluded[band] = occluded[band] + horizon * horizon;
        }
      }
    }
    const int64_t extra = int64_t(L.directions) * L.bands;
    VF vx = zero - b.px, vy = zero - b.py, vz = b.z;  // -P
    normalize(vx, vy, vz);
    add(extra, nx * vx + ny * vy + nz * vz);
    alignas(64) float rp[kLanes];
    store(rp, R_px, Mask(0xffff));
    for (float& v : rp) v = std::log2(1.0f + v) / 8.0f;
    add(extra + 1, load(rp));
    for (int band = 0; band < L.bands; ++band) {
      const VF vis = one - occluded[band] / splat(float(L.directions));
      add(extra + 2 + band, vis);
      if (band == L.bands - 1) base = vis;
    }
  }
  finish_block(m, b, h, 1.0f, false, out, &base);
}

}  // namespace detail

inline void infer_horizon(const NnaoWeights& m, const ao::GBuffer& g, float* out) {
  using namespace ao::simd;
  for_each_block(g, [&](int x0, int y, Mask valid) {
    const Block b(g, x0, y, valid);
    detail::horizon_block(m, g, b, out);
  });
}

}  // namespace nns::nnao
