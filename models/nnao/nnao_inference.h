#pragma once
// NNAO inference on a whole frame, two ways (Holden et al. 2016, section 5):
//  * exact: all w*w grid samples per pixel, the full dot products with W0;
//  * shader-style: W0 seen as four w x w filter images, sampled on an mx x my
//    stratified grid (one sample per cell, at a per-pixel 2D jitter), the sum rescaled
//    by (w*w) / (mx*my) — unbiased, since each filter pixel is picked with probability
//    proportional to its cell overlap — then a depth- and normal-aware bilateral blur.
// The shader-style path is the CPU reference of the exported GLSL shader.
//
// Both run 16 pixels of a row at once (screen_space/simd16.h), rows over the
// thread pool; every pixel is computed the same way whatever the thread count. The
// exact path broadcasts each W0 weight to the 16 pixels; the shader path gathers them
// (each pixel has its own jitter, so its own filter taps). The scalar per-pixel loops
// they must match are in nnao_inference_reference.h. Sky pixels get AO = 1.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <cmath>
#include <memory>
#include <vector>

#include "screen_space/ao_common.h"
#include "screen_space/low_resolution.h"
#include "screen_space/simd16.h"
#include "models/nnao/horizon_simd.h"
#include "models/nnao/nnao_exact_per_pixel.h"
#include "models/nnao/nnao_head_simd.h"
#include "models/nnao/nnao_features.h"
#include "models/nnao/nnao_weights.h"

namespace nns::nnao {

// The stratification grid for a sample count: mx x my cells, mx the power of two
// nearest above sqrt(n) (64 = 8x8, 128 = 16x8, 256 = 16x16, 32 = 8x4, 16 = 4x4).
inline void sample_grid(int samples, int window, int& mx, int& my) {
  mx = 1;
  while (mx * mx < samples) mx *= 2;
  my = samples / mx < 1 ? 1 : samples / mx;
  mx = std::min(mx, window);
  my = std::min(my, window);
}

// A sample count the model can honour: the grid has at most window x window cells, so
// a larger count would silently run fewer samples than asked for. A horizon model has
// no shader-style form: its only form is the exact one.
inline void check_sample_count(int samples, const InputSpec& input) {
  if (input.is_horizon())
    throw std::invalid_argument("--samples " + std::to_string(samples) + ": a horizon-feature model runs exact only (" +
                                std::to_string(input.samples()) + " depth samples per pixel)");
  const int window = input.window;
  if (samples < 1 || samples > window * window)
    throw std::invalid_argument("--samples " + std::to_string(samples) + ": a window-" + std::to_string(window) +
                                " model takes 1 to " + std::to_string(window * window) + " filter samples");
}

namespace detail {

using namespace screen_space::simd;

// The G-buffer interleaved per pixel as (Nx, Ny, Nz, Z): one 16-byte load per sample
// and lane instead of four gathers from four planes. Built once per frame.
inline std::vector<float> pack_normal_depth(const screen_space::GBuffer& g) {
  std::vector<float> p(size_t(4 * g.pixels()));
  for (int64_t i = 0; i < g.pixels(); ++i) {
    p[size_t(4 * i)] = g.nx[i], p[size_t(4 * i + 1)] = g.ny[i];
    p[size_t(4 * i + 2)] = g.nz[i], p[size_t(4 * i + 3)] = g.z[i];
  }
  return p;
}

#if NNSHADE_SIMD16_AVX512
// Per 128-bit chunk i: v[r] holds lane 4i + r's four values (a, b, c, d); returns the
// four planes a, b, c, d in lane order (a 4x4 transpose inside each chunk).
inline void transpose_chunks(const __m512 v[4], __m512 out[4]) {
  const __m512 t0 = _mm512_unpacklo_ps(v[0], v[1]), t1 = _mm512_unpackhi_ps(v[0], v[1]);
  const __m512 t2 = _mm512_unpacklo_ps(v[2], v[3]), t3 = _mm512_unpackhi_ps(v[2], v[3]);
  out[0] = _mm512_castpd_ps(_mm512_unpacklo_pd(_mm512_castps_pd(t0), _mm512_castps_pd(t2)));
  out[1] = _mm512_castpd_ps(_mm512_unpackhi_pd(_mm512_castps_pd(t0), _mm512_castps_pd(t2)));
  out[2] = _mm512_castpd_ps(_mm512_unpacklo_pd(_mm512_castps_pd(t1), _mm512_castps_pd(t3)));
  out[3] = _mm512_castpd_ps(_mm512_unpackhi_pd(_mm512_castps_pd(t1), _mm512_castps_pd(t3)));
}
#endif

// FeatureCentre (nnao_features.h) for the 16 pixels of a block, same expressions.
struct CentreBlock {
  VF z, px, py, nx, ny, nz, kx, ky, cx, cy, inv_r;
  float step, r;
  const float* packed;  // pack_normal_depth(g)

  CentreBlock(const screen_space::GBuffer& g, const Block& b, int w, const float* packed_)
      : z(b.z), px(b.px), py(b.py), packed(packed_) {
    nx = load(g.nx + b.i0, b.valid, 0.0f), ny = load(g.ny + b.i0, b.valid, 0.0f), nz = load(g.nz + b.i0, b.valid, 0.0f);
    r = g.radius;
    inv_r = splat(1.0f / r);
    kx = splat(0.5f * float(g.width)) / (splat(g.sx) * z);
    ky = splat(0.5f * float(g.height)) / (splat(g.sy) * z);
    cx = (px / (splat(g.sx) * z) + splat(1.0f)) * splat(0.5f * float(g.width)) - splat(0.5f);
    cy = (splat(1.0f) - py / (splat(g.sy) * z)) * splat(0.5f * float(g.height)) - splat(0.5f);
    step = w == 1 ? 0.0f : 2.0f * r / float(w - 1);
  }
  VF offset(VF i) const { return i * splat(step) - splat(r); }

  // The 4 features of the grid sample at screen point (sx, sy) for the lanes of m
  // (zero elsewhere); returns the lanes whose features are not all zero.
  Mask sample(const screen_space::GBuffer& g, VF sx, VF sy, Mask m, VF o[4]) const {
    VI ix, iy;
    clamped_pixel(g, sx, sy, ix, iy);
    const VI s = pixel_index(g, ix, iy);
#if NNSHADE_SIMD16_AVX512
    // Every lane's index is a clamped on-screen pixel, so all 16 loads are safe; lanes
    // outside m are zeroed below.
    alignas(64) int32_t idx[kLanes];
    _mm512_store_si512(idx, s.v);
    __m512 v[4], nd[4];
    for (int r = 0; r < 4; ++r) {
      __m512 t = _mm512_castps128_ps512(_mm_loadu_ps(packed + 4 * int64_t(idx[r])));
      t = _mm512_insertf32x4(t, _mm_loadu_ps(packed + 4 * int64_t(idx[4 + r])), 1);
      t = _mm512_insertf32x4(t, _mm_loadu_ps(packed + 4 * int64_t(idx[8 + r])), 2);
      v[r] = _mm512_insertf32x4(t, _mm_loadu_ps(packed + 4 * int64_t(idx[12 + r])), 3);
    }
    transpose_chunks(v, nd);
    const VF zs{nd[3]}, snx{nd[0]}, sny{nd[1]}, snz{nd[2]};
#else
    const VF zs = gather(g.z, s, m, INFINITY);
    const VF snx = gather(g.nx, s, m, 0.0f), sny = gather(g.ny, s, m, 0.0f), snz = gather(g.nz, s, m, 0.0f);
#endif
    m &= ~sky(zs);
    VF dx, dy;
    position(g, to_float(ix), to_float(iy), zs, dx, dy);
    dx = dx - px, dy = dy - py;
    const VF dz = z - zs;
    const VF d2 = (dx * dx + dy * dy + dz * dz) * (inv_r * inv_r);
    m &= lt(d2, splat(1.0f));
    const VF f = select(m, splat(1.0f) - sqrt(select(m, d2, splat(0.0f))), splat(0.0f));
    o[0] = f * (select(m, snx, nx) - nx);
    o[1] = f * (select(m, sny, ny) - ny);
    o[2] = f * (select(m, snz, nz) - nz);
    o[3] = f * select(m, zs - z, splat(0.0f)) * inv_r;
    return m;
  }
};

// HS > 0: the hidden width known at compile time (the paper's 4 stays in registers).
template <int HS>
void exact_block(const NnaoWeights& m, const screen_space::GBuffer& g, const Block& b, const float* packed,
                 float* out) {
  const int w = m.input.window, H = HS > 0 ? HS : m.hidden;
  const int64_t F = m.features();
  VF h[HS > 0 ? HS : 64];
  for (int k = 0; k < H; ++k) h[k] = splat(0.0f);
  if (b.live) {
    const CentreBlock c(g, b, w, packed);
    for (int j = 0; j < w; ++j) {
      const VF sy = c.cy + c.offset(splat(float(j))) * c.ky;
      for (int i = 0; i < w; ++i) {
        const VF sx = c.cx + c.offset(splat(float(i))) * c.kx;
        VF o[4];
        if (!c.sample(g, sx, sy, b.live, o)) continue;  // all zero: adds nothing
        const float* wq = m.w0.data() + (int64_t(j) * w + i) * 4;
        for (int k = 0; k < H; ++k, wq += F)  // the reference's order: q ascending
          h[k] = h[k] + splat(wq[0]) * o[0] + splat(wq[1]) * o[1] + splat(wq[2]) * o[2] + splat(wq[3]) * o[3];
      }
    }
  }
  finish_block<HS>(m, b, h, 1.0f, false, out);
}

}  // namespace detail

// Depth- and normal-aware blur, separable (a 5-tap horizontal then a 5-tap vertical
// pass, the usual SSAO blur): Gaussian in screen space (sigma 1.5 px), times
// exp(-(dz / (e.depth r))^2) and max(0, n.n')^e.normal_power, so it does not average
// across a depth discontinuity or a sharp crease (the terms: nnao_weights.h).
inline void bilateral_blur(const screen_space::GBuffer& g, const float* in, float* out, const BlurEdges& e = {}) {
  using namespace screen_space::simd;
  const float inv_dz = 1.0f / (e.depth * g.radius);
  const bool normals = e.normal_power > 0;  // power 0: the term is 1, its three planes not read
  float spatial[5];
  for (int k = -2; k <= 2; ++k) spatial[k + 2] = std::exp(-float(k * k) / (2 * 1.5f * 1.5f));
  // Every pixel of tmp is written before it is read: no zeroing (a serial memset).
  const std::unique_ptr<float[]> tmp(new float[size_t(g.pixels())]);
  const int W = g.width;
  auto pass = [&](const float* src, float* dst, bool horizontal) {
    for_each_block(g, [&](int x0, int y, Mask valid) {
      const int64_t i0 = int64_t(y) * W + x0;
      const VF z = load(g.z + i0, valid, INFINITY);
      const Mask centre_sky = sky(z);
      VF nx = splat(0.0f), ny = splat(0.0f), nz = splat(0.0f);
      if (normals)
        nx = load(g.nx + i0, valid, 0.0f), ny = load(g.ny + i0, valid, 0.0f), nz = load(g.nz + i0, valid, 0.0f);
      VF s = splat(0.0f), ws = splat(0.0f);
      for (int k = -2; k <= 2; ++k) {
        Mask m = valid;
        int64_t j0 = i0;
        if (horizontal) {
          const int lo = std::max(0, -(x0 + k)), hi = std::min(kLanes, W - x0 - k);
          if (hi <= lo) continue;
          m &= Mask((1u << hi) - 1) & ~Mask((1u << lo) - 1);
          j0 += k;
        } else {
          if (y + k < 0 || y + k >= g.height) continue;
          j0 += int64_t(k) * W;
        }
        const VF zj = load(g.z + j0, m, INFINITY);
        m &= ~sky(zj);
        if (!m) continue;
        const VF dz = (zj - z) * splat(inv_dz);  // lanes outside m reach nothing: wk selects 0 there
        VF nd = splat(1.0f);
        if (normals) {
          nd = max(splat(0.0f),
                   nx * load(g.nx + j0, m, 0.0f) + ny * load(g.ny + j0, m, 0.0f) + nz * load(g.nz + j0, m, 0.0f));
          nd = pow_by_squaring(nd, e.normal_power, splat(1.0f));
        }
        const VF wk = select(m, splat(spatial[k + 2]) * exp_nonpositive(-(dz * dz)) * nd, splat(0.0f));
        s = s + wk * load(src + j0, m, 0.0f);
        ws = ws + wk;
      }
      const VF res = select(gt(ws, splat(0.0f)), s / ws, load(src + i0, valid, 1.0f));
      store(dst + i0, select(centre_sky, splat(1.0f), res), valid);
    });
  };
  pass(in, tmp.get(), true);
  pass(tmp.get(), out, false);
}

// A horizon model's march and network, then its blur passes, at the G-buffer's resolution.
inline void infer_horizon_blurred(const NnaoWeights& m, const screen_space::GBuffer& g, float* out) {
  // Each pass reads one buffer and writes the other, the last one writing `out` (no
  // copies between passes: serial, they held the second thread back).
  const std::unique_ptr<float[]> a(new float[size_t(g.pixels())]), b(new float[size_t(g.pixels())]);
  float* src = a.get();
  infer_horizon(m, g, src);
  for (int p = 1; p <= m.blur_passes; ++p) {
    float* dst = p == m.blur_passes ? out : (src == a.get() ? b.get() : a.get());
    bilateral_blur(g, src, dst, m.blur_edges);
    src = dst;
  }
}

inline void infer_exact(const NnaoWeights& m, const screen_space::GBuffer& g, float* out) {
  using namespace screen_space::simd;
  // A horizon model (nnao_inputs.h) marches its directions instead (horizon_simd.h),
  // then the bilateral blur: chosen on the validation families of the default data
  // (3 seeds: MSE -7%, SSIM 0.84-0.86 -> 0.89-0.90, flicker 1.6x -> 1.0-1.07x the
  // ground truth's; docs/nnao.md), for ~1 ms at 320x180; applied m.blur_passes times
  // (the default model's 4: flicker 1.11x -> 0.93x the truth's, SSIM +0.019 and MSE -2%
  // on the validation families, 3 seeds; docs/nnao.md, "Flicker").
  if (m.input.is_horizon()) {
    if (m.downsample > 1) {
      // The same passes on one pixel of every s x s block, then the guided upsample
      // with the blur's edge terms (screen_space/low_resolution.h).
      const screen_space::LowResGBuffer lr = screen_space::downsample_gbuffer(g, m.downsample);
      std::vector<float> low(size_t(lr.g.pixels()));
      infer_horizon_blurred(m, lr.g, low.data());
      return screen_space::upsample(g, lr, low.data(), out, {m.blur_edges.depth, m.blur_edges.normal_power});
    }
    return infer_horizon_blurred(m, g, out);
  }
  const std::vector<float> packed = detail::pack_normal_depth(g);
  for_each_block(g, [&](int x0, int y, Mask valid) {
    const Block b(g, x0, y, valid);
    if (m.hidden == 4) detail::exact_block<4>(m, g, b, packed.data(), out);
    else detail::exact_block<0>(m, g, b, packed.data(), out);
  });
}

// `blur` false gives the raw stochastic estimate (tests check its mean).
inline void infer_shader_style(const NnaoWeights& m, const screen_space::GBuffer& g, int samples, float* out,
                               bool blur = true, uint32_t seed = 0) {
  using namespace screen_space::simd;
  int mx, my;
  sample_grid(samples, m.input.window, mx, my);
  const int w = m.input.window, H = m.hidden;
  const int64_t F = m.features();
  const float scale = float(w * w) / float(mx * my);
  // W0 regrouped per grid point (q, k, c), so one gather index q * 4H + k * 4 + c
  // reads tap q of filter k for every lane.
  std::vector<float> taps(size_t(H * F));
  for (int k = 0; k < H; ++k)
    for (int64_t q = 0; q < F / 4; ++q)
      for (int c = 0; c < 4; ++c) taps[size_t(q * 4 * H + k * 4 + c)] = m.w0[size_t(k * F + q * 4 + c)];
  const std::vector<float> packed = detail::pack_normal_depth(g);
  std::vector<float> raw(size_t(g.pixels()));
  for_each_block(g, [&](int x0, int y, Mask valid) {
    const Block b(g, x0, y, valid);
    VF h[64];
    for (int k = 0; k < H; ++k) h[k] = splat(0.0f);
    if (!b.live) {
      detail::finish_block(m, b, h, scale, true, raw.data());
      return;
    }
    const detail::CentreBlock c(g, b, w, packed.data());
    alignas(64) float jx_[kLanes], jy_[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      const uint32_t hsh = screen_space::pixel_hash(uint32_t(x0 + l), uint32_t(y), seed);
      jx_[l] = screen_space::hash_unit(hsh), jy_[l] = screen_space::hash_unit(screen_space::pixel_hash(hsh, 1, seed));
    }
    const VF jx = load(jx_), jy = load(jy_);
    // One feature sample per stratum (cell a, bb) at this pixel's jitter: f(j, ii, live, o)
    // for grid point (ii, j) when any lane's features are non-zero.
    auto stratum = [&](int cell, int cells, VF jit) {
      return clamp(to_int((splat(float(cell)) + jit) * splat(float(w)) / splat(float(cells))), 0, w - 1);
    };
    auto for_each_stratum = [&](auto&& f) {
      for (int bb = 0; bb < my; ++bb) {
        const VI j = stratum(bb, my, jy);
        const VF sy = c.cy + c.offset(to_float(j)) * c.ky;
        for (int a = 0; a < mx; ++a) {
          const VI ii = stratum(a, mx, jx);
          VF o[4];
          const Mask live = c.sample(g, c.cx + c.offset(to_float(ii)) * c.kx, sy, b.live, o);
          if (live) f(j, ii, live, o);
        }
      }
    };
#if NNSHADE_SIMD16_AVX512
    // H = 4: a grid point's 16 weights (4 filters x 4 channels) are one 64-byte row of
    // `taps`, so each lane multiplies its own row by its 4 features repeated 4 times and
    // keeps 16 partial sums; summed per filter at the end. 16 row loads per sample
    // instead of 16 gathers (the dot products' order of addition differs from the
    // reference: within float rounding, see the tests).
    if (H == 4) {
      __m512 acc[kLanes];
      for (auto& a : acc) a = _mm512_setzero_ps();
      for_each_stratum([&](VI j, VI ii, Mask, const VF* o) {
        alignas(64) int32_t qa[kLanes];
        _mm512_store_si512(qa, (j * splat_i(w) + ii).v);
        // The 4x4-per-chunk transpose: u[r] chunk i = lane 4i + r's (o0, o1, o2, o3).
        const __m512 of[4] = {o[0].v, o[1].v, o[2].v, o[3].v};
        __m512 u[4];
        detail::transpose_chunks(of, u);
#define NNS_LANE(i, r)                                                                         \
  acc[4 * i + r] = _mm512_fmadd_ps(_mm512_loadu_ps(taps.data() + int64_t(qa[4 * i + r]) * 16), \
                                   _mm512_shuffle_f32x4(u[r], u[r], i * 0x55), acc[4 * i + r]);
#define NNS_CHUNK(i) NNS_LANE(i, 0) NNS_LANE(i, 1) NNS_LANE(i, 2) NNS_LANE(i, 3)
        NNS_CHUNK(0) NNS_CHUNK(1) NNS_CHUNK(2) NNS_CHUNK(3)
#undef NNS_CHUNK
#undef NNS_LANE
      });
      alignas(64) float part[kLanes][16], hk[4][kLanes];
      for (int l = 0; l < kLanes; ++l) _mm512_store_ps(part[l], acc[l]);
      for (int k = 0; k < 4; ++k)
        for (int l = 0; l < kLanes; ++l)
          hk[k][l] = part[l][4 * k] + part[l][4 * k + 1] + part[l][4 * k + 2] + part[l][4 * k + 3];
      for (int k = 0; k < 4; ++k) h[k] = load(hk[k]);
      detail::finish_block(m, b, h, scale, true, raw.data());
      return;
    }
#endif
    for_each_stratum([&](VI j, VI ii, Mask live, const VF* o) {
      const VI q = (j * splat_i(w) + ii) * splat_i(4 * H);
      const float* t = taps.data();
      for (int k = 0; k < H; ++k, t += 4)
        h[k] = h[k] + (gather(t, q, live, 0.0f) * o[0] + gather(t + 1, q, live, 0.0f) * o[1] +
                       gather(t + 2, q, live, 0.0f) * o[2] + gather(t + 3, q, live, 0.0f) * o[3]);
    });
    detail::finish_block(m, b, h, scale, true, raw.data());
  });
  if (blur) bilateral_blur(g, raw.data(), out);
  else std::copy(raw.begin(), raw.end(), out);
}

}  // namespace nns::nnao
