#pragma once
// What the classical screen-space AO methods share: a parallel loop over the rows of a
// frame, the 4x4 tiled rotation noise, sample kernels from a fixed seed, and the 4x4
// box blur that averages the noise pattern away (SSAO+ report, section 2.1.4).
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/rng.h"
#include "core/thread_pool.h"
#include "screen_space/gbuffer.h"
#include "screen_space/simd16.h"

namespace nns::screen_space {

// f(px, py, i) for every pixel; rows are split over the workers. Each pixel is written
// once, so the result is the same for any thread count.
template <class F>
void for_each_pixel(const GBuffer& g, F&& f) {
  parallel_for_dynamic(g.height, 2, [&](int64_t y0, int64_t y1) {  // rows of unequal cost: as for_each_block
    for (int64_t y = y0; y < y1; ++y)
      for (int x = 0; x < g.width; ++x) f(x, int(y), y * g.width + x);
  });
}

// The scalar references' loop over surface pixels: a sky pixel is unoccluded (1); every
// other gets f(x, y, i, P, N), with its view-space position and unit normal.
template <class F>
void for_each_surface_pixel(const GBuffer& g, float* raw, F&& f) {
  for_each_pixel(g, [&](int x, int y, int64_t i) {
    if (g.sky(i)) {
      raw[size_t(i)] = 1;
      return;
    }
    const Vec3 P = g.position(x, y);
    const Vec3 N = normalize_or_facing(g.normal(i));
    raw[size_t(i)] = f(x, y, i, P, N);
  });
}

// Angle of the 4x4 noise tile at a pixel: 16 evenly spaced rotations in a fixed
// scrambled order, so that every 4x4 block holds all of them (what the blur averages).
inline float noise_angle_4x4(int px, int py) {
  static const int order[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};
  return float(order[(py & 3) * 4 + (px & 3)]) * (6.2831853f / 16.0f);
}

// The noise tile as per-row lane tables for 16-pixel blocks (x0 a multiple of 16, so
// lane l sits at x & 3 = l & 3): the same angles, cosines and sines as the scalar path.
struct NoiseTile {
  alignas(64) float angle[4][16], cos[4][16], sin[4][16];
  NoiseTile() {
    for (int yq = 0; yq < 4; ++yq)
      for (int l = 0; l < 16; ++l) {
        angle[yq][l] = noise_angle_4x4(l, yq);
        cos[yq][l] = std::cos(angle[yq][l]);
        sin[yq][l] = std::sin(angle[yq][l]);
      }
  }
};

// Unit vectors (and lengths <= 1) from a fixed seed: sample kernels are constants of a
// shader, not random per frame.
inline std::vector<Vec3> sphere_kernel(int n, uint64_t seed) {
  Rng rng(seed);
  std::vector<Vec3> k;
  while (int(k.size()) < n) {
    Vec3 v{float(rng.uniform(-1, 1)), float(rng.uniform(-1, 1)), float(rng.uniform(-1, 1))};
    if (dot(v, v) <= 1 && dot(v, v) > 1e-4f) k.push_back(v);
  }
  return k;
}

// Sky pixels are not occluded: every method writes 1 there. The scalar reference of
// box_blur_4x4 below.
inline void box_blur_4x4_reference(const GBuffer& g, const float* in, float* out) {
  for_each_pixel(g, [&](int x, int y, int64_t i) {
    if (g.sky(i)) {
      out[i] = 1;
      return;
    }
    float s = 0;
    int n = 0;
    for (int dy = -2; dy < 2; ++dy)
      for (int dx = -2; dx < 2; ++dx) {
        int sx = x + dx, sy = y + dy;
        if (sx < 0 || sy < 0 || sx >= g.width || sy >= g.height) continue;
        int64_t j = int64_t(sy) * g.width + sx;
        if (g.sky(j)) continue;
        s += in[j];
        ++n;
      }
    out[i] = n ? s / float(n) : in[i];
  });
}

// 16 pixels at a time, the taps summed in the same order as the reference (bitwise
// equal to it: excluded taps add an exact 0).
inline void box_blur_4x4(const GBuffer& g, const float* in, float* out) {
  using namespace simd;
  const int W = g.width;
  for_each_block(g, [&](int x0, int y, Mask valid) {
    const int64_t i0 = int64_t(y) * W + x0;
    const Mask centre_sky = sky(load(g.z + i0, valid, INFINITY));
    VF s = splat(0.0f), n = splat(0.0f);
    for (int dy = -2; dy < 2; ++dy) {
      const int sy = y + dy;
      if (sy < 0 || sy >= g.height) continue;
      for (int dx = -2; dx < 2; ++dx) {
        const int lo = std::max(0, -(x0 + dx)), hi = std::min(kLanes, W - x0 - dx);
        if (hi <= lo) continue;
        Mask m = (Mask((1u << hi) - 1) & ~Mask((1u << lo) - 1)) & valid;
        const int64_t j0 = int64_t(sy) * W + x0 + dx;
        m &= ~sky(load(g.z + j0, m, INFINITY));
        s = s + load(in + j0, m, 0.0f);
        n = n + select(m, splat(1.0f), splat(0.0f));
      }
    }
    VF res = select(gt(n, splat(0.0f)), s / n, load(in + i0, valid, 1.0f));
    store(out + i0, select(centre_sky, splat(1.0f), res), valid);
  });
}

inline float saturate(float v) { return v < 0 ? 0 : (v > 1 ? 1 : v); }

}  // namespace nns::screen_space
