#pragma once
// A horizon model's exact inference on 16 pixels of a row at once (screen_space/
// simd16.h): the marches of compute_horizon_features (horizon_features.h) with the same
// expressions in the same order, then layer 0 and the head. That loop (through
// nnao_exact_per_pixel.h) is the reference this must match (tests compare them).
//
// The march writes the block's features (16 lanes x F floats, 4.5 KB at the default
// 16 x 4 bands: L1-resident) and layer 0 runs after it, feature q outer, hidden unit
// inner, with the hidden width a compile-time constant so its sums stay in registers.
// The first vectorised form added each feature into the sums as its band ended, with
// the width a runtime value: the H sums lived on the stack through the march (and 16
// of them would not fit the vector registers next to the march's own), so every add
// was a load and a store; layer 0 took 2.4 of 11.7 ms per frame (docs/nnao.md, Speed).
// The order of the additions is the same (q ascending), so the output is too.
#include <cmath>
#include <vector>

#include "models/nnao/nnao_head_simd.h"
#include "models/nnao/nnao_weights.h"
#include "screen_space/simd16.h"

namespace nns::nnao {

namespace detail {

// The march: writes the features of the 16 lanes to f[q] (q as in horizon_features.h)
// and returns the base (the last band's visibility). Only for blocks with a live lane.
inline VF horizon_march(const NnaoWeights& m, const screen_space::GBuffer& g_in, const Block& b_in, VF* f) {
  // Local copies: a store through f (a vector type, which may alias anything) would
  // otherwise make the compiler reload the frame's sizes and the block's planes, and
  // redo their conversions, at every step.
  const screen_space::GBuffer g = g_in;
  const Block b = b_in;
  const HorizonLayout L = m.input.horizon;
  const int per_band = L.steps / L.bands;
  const VF zero = splat(0.0f), one = splat(1.0f);
  VF nx, ny, nz;
  load_unit_normals(g, b.i0, b.valid, nx, ny, nz);
  const float r = g.radius, r2 = r * r;
  const VF R_px = splat(r * 0.5f * float(g.width)) / (splat(g.sx) * b.z);
  const VF sxn = nx, syn = zero - ny, sl = sqrt(sxn * sxn + syn * syn);
  const Mask tilted = gt(sl, splat(1e-4f));
  const VF c0 = select(tilted, sxn / sl, one), s0 = select(tilted, syn / sl, zero);
  VF occluded[64], t[64];  // bands, steps <= 64 (HorizonLayout::problem)
  for (int band = 0; band < L.bands; ++band) occluded[band] = zero;
  // Step s's distance in pixels: the same for every direction.
  for (int s = 0; s < L.steps; ++s) {
    const float fs = (float(s) + 0.5f) / float(L.steps);
    t[s] = one + splat(fs * fs) * R_px;
  }
  for (int k = 0; k < L.directions; ++k) {
    const float a = 6.2831853f * float(k) / float(L.directions);
    const float ca = std::cos(a), sa = std::sin(a);
    const VF ox = c0 * splat(ca) - s0 * splat(sa), oy = s0 * splat(ca) + c0 * splat(sa);
    VF horizon = zero;
    Mask alive = b.live;
    for (int s = 0, band = 0, in_band = 0; s < L.steps; ++s) {
      if (alive) {
        VF dx, dy, dz;
        Mask hit = b.sample(g, b.X + ox * t[s], b.Y + oy * t[s], alive, dx, dy, dz);
        const VF d2 = dx * dx + dy * dy + dz * dz;
        hit &= gt(d2, zero) & le(d2, splat(r2));
        if (hit) {
          const VF e = (nx * dx + ny * dy + nz * dz) / sqrt(select(hit, d2, one));
          horizon = select(hit, max(horizon, e), horizon);
        }
      }
      if (++in_band == per_band) {  // the band ends: its running maximum is a feature
        f[k * L.bands + band] = horizon;
        occluded[band] = occluded[band] + horizon * horizon;
        ++band, in_band = 0;
      }
    }
  }
  const int64_t extra = int64_t(L.directions) * L.bands;
  VF vx = zero - b.px, vy = zero - b.py, vz = b.z;  // -P
  normalize_or_facing(vx, vy, vz);
  f[extra] = nx * vx + ny * vy + nz * vz;
  alignas(64) float rp[kLanes];
  store(rp, R_px, Mask(0xffff));
  for (float& v : rp) v = std::fmin(L.radius_term_max, std::log2(1.0f + v) / 8.0f);
  f[extra + 1] = load(rp);
  for (int band = 0; band < L.bands; ++band) f[extra + 2 + band] = one - occluded[band] / splat(float(L.directions));
  return f[extra + 2 + L.bands - 1];
}

// HS > 0: the hidden width known at compile time (4, 8, 16: the presets' and the sweep's).
template <int HS>
void horizon_block(const NnaoWeights& m, const screen_space::GBuffer& g, const Block& b, VF* f, float* out) {
  const int H = HS > 0 ? HS : m.hidden;
  const int64_t F = m.features();
  VF h[HS > 0 ? HS : 64];
  for (int k = 0; k < H; ++k) h[k] = splat(0.0f);
  VF base = splat(1.0f);
  if (b.live) {
    base = horizon_march(m, g, b, f);
    // Layer 0 weight q of hidden unit k is m.w0[k * F + q].
    for (int64_t q = 0; q < F; ++q) {
      const VF v = f[q];
      const float* wq = m.w0.data() + q;
      for (int k = 0; k < H; ++k) h[k] = h[k] + splat(wq[int64_t(k) * F]) * v;
    }
  }
  finish_block<HS>(m, b, h, 1.0f, false, out, &base);
}

}  // namespace detail

inline void infer_horizon(const NnaoWeights& m, const screen_space::GBuffer& g, float* out) {
  using namespace screen_space::simd;
  const int H = m.hidden;
  for_each_block(g, [&](int x0, int y, Mask valid) {
    // One feature buffer per worker thread, reused block after block.
    thread_local std::vector<VF> f;
    f.resize(size_t(m.features()));
    const Block b(g, x0, y, valid);
    if (H == 16) detail::horizon_block<16>(m, g, b, f.data(), out);
    else if (H == 8) detail::horizon_block<8>(m, g, b, f.data(), out);
    else if (H == 4) detail::horizon_block<4>(m, g, b, f.data(), out);
    else detail::horizon_block<0>(m, g, b, f.data(), out);
  });
}

}  // namespace nns::nnao
