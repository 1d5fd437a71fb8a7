#pragma once
// NNAO's input features (Holden et al. 2016, section 3), exactly as the paper states them.
//
// For a non-sky centre pixel with view-space position P, normal N and depth z: a w x w
// grid of view-space points P + (gx, gy, 0), gx and gy spanning [-r, r] (row 0 of the
// grid is +r, the top, so the grid reads like the screen); each point is projected to
// the nearest pixel (clamped to the screen edge) whose normal Ns, depth zs and
// reconstructed position Ps are read. The sample's 4 features are
//     f * (Ns - N, (zs - z) / r),   f = 1 - clamp(|Ps - P| / r, 0, 1),
// so anything farther than r from the centre contributes exactly zero. A sky sample
// contributes zero too (its distance is infinite).
//
// Layout: sample-major, 4 values per grid point: out[(j*w + i)*4 + c], c = Nx,Ny,Nz,depth.
// A column of W0 is then a w x w RGBA image: the paper's "filters" (section 5).
#include <cstdint>
#include <vector>

#include "screen_space/gbuffer.h"

namespace nns::nnao {

inline int64_t feature_count(int w) { return int64_t(w) * w * 4; }

// Grid offset of index i in [0, w): -r .. r (w = 1 gives the centre only).
inline float grid_offset(int i, int w, float r) { return w == 1 ? 0.0f : r * (2.0f * float(i) / float(w - 1) - 1.0f); }

// The per-centre quantities every grid sample needs. All grid points share the
// centre's depth, so their projection is affine in the offset: pixel = centre pixel +
// offset * (pixels per view-space unit at depth z).
struct FeatureCentre {
  const screen_space::GBuffer* g;
  int w;
  float z, r, inv_r, cx, cy, kx, ky;
  float step;  // grid spacing 2r/(w-1): offset(i) = -r + i * step
  Vec3 P, N;

  FeatureCentre(const screen_space::GBuffer& gb, int px, int py, int window) : g(&gb), w(window) {
    const int64_t c = int64_t(py) * gb.width + px;
    z = gb.z[c];
    r = gb.radius;
    inv_r = 1.0f / r;
    P = gb.position(px, py);
    N = gb.normal(c);
    kx = 0.5f * float(gb.width) / (gb.sx * z);
    ky = 0.5f * float(gb.height) / (gb.sy * z);
    gb.project(P, cx, cy);
    step = window == 1 ? 0.0f : 2.0f * r / float(window - 1);
  }
  float offset(int i) const { return w == 1 ? 0.0f : float(i) * step - r; }

  // The 4 features of grid point (i, j) (column i, row j; row 0 is the top, +r).
  // Returns false when they are all zero (sky, or farther than r: falloff 0), so
  // callers may skip the multiply-adds.
  bool sample(int i, int j, float* o) const {
    const float sx = cx + offset(i) * kx;
    // Row j's view-space offset is -grid_offset(j) (row 0 = +r, up), and up on screen
    // is a smaller row: the two signs cancel.
    const float sy = cy + offset(j) * ky;
    int ix, iy;
    g->clamped_pixel(sx, sy, ix, iy);
    const int64_t s = int64_t(iy) * g->width + ix;
    const float zs = g->z[s];
    if (data::is_sky(zs)) {
      o[0] = o[1] = o[2] = o[3] = 0;
      return false;
    }
    const Vec3 D = g->position(ix, iy) - P;
    const float d2 = dot(D, D) * (inv_r * inv_r);
    if (!(d2 < 1.0f)) {
      o[0] = o[1] = o[2] = o[3] = 0;
      return false;
    }
    const float f = 1.0f - __builtin_sqrtf(d2);
    o[0] = f * (g->nx[s] - N.x);
    o[1] = f * (g->ny[s] - N.y);
    o[2] = f * (g->nz[s] - N.z);
    o[3] = f * (zs - z) * inv_r;
    return true;
  }
};

// Writes feature_count(w) floats for centre pixel (px, py), which must not be sky.
inline void compute_features(const screen_space::GBuffer& g, int px, int py, int w, float* out) {
  const FeatureCentre c(g, px, py, w);
  for (int j = 0; j < w; ++j)
    for (int i = 0; i < w; ++i) c.sample(i, j, out + (int64_t(j) * w + i) * 4);
}

// Non-sky pixel indices of a frame (row-major order).
inline std::vector<int64_t> non_sky_pixels(const screen_space::GBuffer& g) {
  std::vector<int64_t> out;
  out.reserve(size_t(g.pixels()));
  for (int64_t i = 0; i < g.pixels(); ++i)
    if (!g.sky(i)) out.push_back(i);
  return out;
}

}  // namespace nns::nnao
