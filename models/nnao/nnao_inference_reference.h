#pragma once
// The scalar per-pixel NNAO inference: the reference that the vectorised paths of
// nnao_inference.h must match (tests compare them). Holden et al. 2016, section 5:
//  * exact: all w*w grid samples per pixel, the full dot products with W0;
//  * shader-style: W0 seen as four w x w filter images, sampled on an mx x my
//    stratified grid (one sample per cell, at a per-pixel 2D jitter), the sum rescaled
//    by (w*w) / (mx*my) — unbiased, since each filter pixel is picked with probability
//    proportional to its cell overlap — then a depth- and normal-aware bilateral blur.
// The shader-style path is the CPU reference of the exported GLSL shader.
// Both run over rows on the thread pool; every pixel is computed the same way
// whatever the thread count. Sky pixels get AO = 1.
#include <cmath>
#include <vector>

#include "core/thread_pool.h"
#include "screen_space/ao_common.h"
#include "models/nnao/nnao_exact_per_pixel.h"
#include "models/nnao/nnao_inference.h"
#include "models/nnao/nnao_weights.h"

namespace nns::nnao {

// bilateral_blur of nnao_inference.h, one pixel at a time.
inline void bilateral_blur_reference(const screen_space::GBuffer& g, const float* in, float* out,
                                     const BlurEdges& e = {}) {
  const float inv_dz = 1.0f / (e.depth * g.radius);
  float spatial[5];
  for (int k = -2; k <= 2; ++k) spatial[k + 2] = std::exp(-float(k * k) / (2 * 1.5f * 1.5f));
  std::vector<float> tmp(size_t(g.pixels()));
  auto pass = [&](const float* src, float* dst, int ddx, int ddy) {
    screen_space::for_each_pixel(g, [&](int x, int y, int64_t i) {
      if (g.sky(i)) {
        dst[i] = 1;
        return;
      }
      const float z = g.z[i];
      const Vec3 n = g.normal(i);
      float s = 0, ws = 0;
      for (int k = -2; k <= 2; ++k) {
        const int sx = x + k * ddx, sy = y + k * ddy;
        if (sx < 0 || sy < 0 || sx >= g.width || sy >= g.height) continue;
        const int64_t j = int64_t(sy) * g.width + sx;
        if (g.sky(j)) continue;
        const float dz = (g.z[j] - z) * inv_dz;
        const float nd = pow_by_squaring(std::max(0.0f, dot(n, g.normal(j))), e.normal_power, 1.0f);
        const float w = spatial[k + 2] * std::exp(-dz * dz) * nd;
        s += w * src[j];
        ws += w;
      }
      dst[i] = ws > 0 ? s / ws : src[i];
    });
  };
  pass(in, tmp.data(), 1, 0);
  pass(tmp.data(), out, 0, 1);
}

// The exact form: the per-pixel loop (of either input kind, nnao_exact_per_pixel.h),
// then for a horizon model the blur infer_exact applies (m.blur_passes times).
inline void infer_exact_reference(const NnaoWeights& m, const screen_space::GBuffer& g, float* out) {
  if (!m.input.is_horizon()) return infer_exact_per_pixel(m, g, out);
  if (m.downsample > 1) {  // at 1/s of the resolution, then the guided upsample
    NnaoWeights full = m;
    full.downsample = 1;
    const screen_space::LowResGBuffer lr = screen_space::downsample_gbuffer(g, m.downsample);
    std::vector<float> low(size_t(lr.g.pixels()));
    infer_exact_reference(full, lr.g, low.data());
    return screen_space::upsample_reference(g, lr, low.data(), out, {m.blur_edges.depth, m.blur_edges.normal_power});
  }
  std::vector<float> raw(size_t(g.pixels()));
  infer_exact_per_pixel(m, g, raw.data());
  for (int p = 1; p < m.blur_passes; ++p) {
    bilateral_blur_reference(g, raw.data(), out, m.blur_edges);
    std::copy(out, out + g.pixels(), raw.data());
  }
  bilateral_blur_reference(g, raw.data(), out, m.blur_edges);
}

// `blur` false gives the raw stochastic estimate (tests check its mean).
inline void infer_shader_style_reference(const NnaoWeights& m, const screen_space::GBuffer& g, int samples, float* out,
                                         bool blur = true, uint32_t seed = 0) {
  int mx, my;
  sample_grid(samples, m.input.window, mx, my);
  const int w = m.input.window, H = m.hidden;
  const int64_t F = m.features();
  const float scale = float(w * w) / float(mx * my);
  std::vector<float> raw(size_t(g.pixels()));
  screen_space::for_each_pixel(g, [&](int x, int y, int64_t i) {
    if (g.sky(i)) {
      raw[size_t(i)] = 1;
      return;
    }
    const FeatureCentre c(g, x, y, w);
    const uint32_t hsh = screen_space::pixel_hash(uint32_t(x), uint32_t(y), seed);
    const float jx = screen_space::hash_unit(hsh), jy = screen_space::hash_unit(screen_space::pixel_hash(hsh, 1, seed));
    float h[64] = {}, h4[4] = {0, 0, 0, 0};
    float f[4];
    for (int b = 0; b < my; ++b) {
      const int j = std::min(w - 1, int((float(b) + jy) * float(w) / float(my)));
      for (int a = 0; a < mx; ++a) {
        const int ii = std::min(w - 1, int((float(a) + jx) * float(w) / float(mx)));
        if (!c.sample(ii, j, f)) continue;
        const float* wq = m.w0.data() + (int64_t(j) * w + ii) * 4;
        if (H == 4) {  // the paper's size: keep the four sums in registers
          for (int k = 0; k < 4; ++k, wq += F) h4[k] += wq[0] * f[0] + wq[1] * f[1] + wq[2] * f[2] + wq[3] * f[3];
        } else {
          for (int k = 0; k < H; ++k, wq += F) h[k] += wq[0] * f[0] + wq[1] * f[1] + wq[2] * f[2] + wq[3] * f[3];
        }
      }
    }
    if (H == 4) std::copy(h4, h4 + 4, h);
    for (int k = 0; k < H; ++k) h[k] = h[k] * scale + m.b0[size_t(k)];
    raw[size_t(i)] = m.head(h);
  });
  if (blur) bilateral_blur_reference(g, raw.data(), out);
  else std::copy(raw.begin(), raw.end(), out);
}

}  // namespace nns::nnao
