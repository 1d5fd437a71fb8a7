#pragma once
// Sixteen pixels of a row at a time: the few vector operations the AO methods need
// (arithmetic, compares into bit masks, blends, masked loads and gathers from the
// G-buffer planes), in one of three backends chosen at compile time:
//   simd16_avx512.h  AVX-512: one instruction per operation;
//   simd16_avx2.h    AVX2 + FMA (Intel since Haswell, AMD since Zen): two ymm halves;
//   simd16_generic.h GCC's vector extension on 16 floats (and loops where it has no
//                    operator), lowered to what the target has (SSE2 in the portable build).
// All three give the same result in every lane for every input (NaN, -0, subnormal,
// out of range): tests/screen_space/test_simd16.cpp checks the build's backend and the
// generic one against scalar code. Expressions written with them (a * b + c) are
// contracted into FMAs by GCC on the same vector statements in the three; where GCC
// inlines a helper in one backend and not in another, the fusion can differ by an ulp
// (screen_space.backends_agree measures it: tests/screen_space/backends/ao_outputs.cpp).
// Preconditions: clamp(a, lo, hi) with lo <= hi; scale2(a, n) with n integral;
// scale2_normal(a, n) with n integral in [-126, 127] (the same result, fewer steps).
// NNSHADE_SIMD16_GENERIC=1 forces the generic backend (to compare a build with it).
//
// Lane l of a block is pixel x0 + l of one row, x0 a multiple of 16: the 4x4 noise
// tiles then depend only on (l & 3, y & 3), and per-row tables replace per-pixel trig.
#include <cmath>
#include <cstdint>

#include "core/thread_pool.h"
#include "screen_space/gbuffer.h"
#include "screen_space/simd16_lanes.h"

#if defined(__AVX512F__) && !NNSHADE_SIMD16_GENERIC
// Code with its own AVX-512 paths over VF and VI (models/nnao/nnao_inference.h) tests
// this, not __AVX512F__: a build forcing the generic backend has __AVX512F__ as well.
#define NNSHADE_SIMD16_AVX512 1
#include "screen_space/simd16_avx512.h"
#elif defined(__AVX2__) && defined(__FMA__) && !NNSHADE_SIMD16_GENERIC
#include "screen_space/simd16_avx2.h"
#else
#include "screen_space/simd16_generic.h"
#endif

namespace nns::screen_space::simd {

inline VF operator-(VF a) { return splat(0.0f) - a; }
inline VF saturate(VF a) { return min(max(a, splat(0.0f)), splat(1.0f)); }

// data::is_sky on 16 depths: !(z < 1e30) || z <= 0 (NaN is sky).
inline Mask sky(VF z) { return (~lt(z, splat(data::kSkyDepth)) | le(z, splat(0.0f))) & kAll; }

// exp(x) for x <= 0 (the bilateral weights), Cody-Waite reduction and a degree-6
// polynomial: relative error below 2.5e-7 against exp in double (2.29e-7 the worst
// found sampling [-87, 0] every 2e-4; tests/screen_space/test_simd16.cpp); 0 below -87.
inline VF exp_nonpositive(VF x) {
  const VF big = max(x, splat(-87.0f));
  const VF n = floor(big * splat(1.44269504f) + splat(0.5f));
  VF r = big - n * splat(0.693145752f);
  r = r - n * splat(1.42860677e-6f);
  VF p = splat(1.0f / 720);
  p = p * r + splat(1.0f / 120);
  p = p * r + splat(1.0f / 24);
  p = p * r + splat(1.0f / 6);
  p = p * r + splat(0.5f);
  p = p * r + splat(1.0f);
  p = p * r + splat(1.0f);
  // n = round(max(x, -87) log2 e) lies in [-126, 0]: 2^n is a normal float.
  return select(lt(x, splat(-87.0f)), splat(0.0f), scale2_normal(p, n));
}

// normalize_or_facing() (gbuffer.h) on 16 vectors in place, with its (0, 0, 1) for a zero vector.
inline void normalize_or_facing(VF& x, VF& y, VF& z) {
  const VF len = sqrt(x * x + y * y + z * z);
  const Mask ok = gt(len, splat(0.0f));
  const VF inv = splat(1.0f) / len;
  x = select(ok, inv * x, splat(0.0f)), y = select(ok, inv * y, splat(0.0f)), z = select(ok, inv * z, splat(1.0f));
}

// The unit normals of the 16 pixels from index i0 (tail lanes: (0, 0, 1)).
inline void load_unit_normals(const GBuffer& g, int64_t i0, Mask valid, VF& x, VF& y, VF& z) {
  x = load(g.nx + i0, valid, 0.0f), y = load(g.ny + i0, valid, 0.0f), z = load(g.nz + i0, valid, 1.0f);
  normalize_or_facing(x, y, z);
}

// View-space position of 16 pixels (pixel coordinates px, py as floats, depth d): the
// same expression as GBuffer::position.
inline void position(const GBuffer& g, VF px, VF py, VF d, VF& x, VF& y) {
  x = (((px + splat(0.5f)) * splat(g.inv_w2) - splat(1.0f)) * splat(g.sx)) * d;
  y = ((splat(1.0f) - (py + splat(0.5f)) * splat(g.inv_h2)) * splat(g.sy)) * d;
}

// GBuffer::project with one reciprocal of the depth instead of two divisions.
inline void project(const GBuffer& g, VF x, VF y, VF d, VF& px, VF& py) {
  const VF inv = splat(1.0f) / d;
  px = (x * inv / splat(g.sx) + splat(1.0f)) * splat(0.5f * float(g.width)) - splat(0.5f);
  py = (splat(1.0f) - y * inv / splat(g.sy)) * splat(0.5f * float(g.height)) - splat(0.5f);
}

// GBuffer::clamped_pixel: nearest pixel (half up), clamped to the screen.
inline void clamped_pixel(const GBuffer& g, VF px, VF py, VI& ix, VI& iy) {
  ix = clamp(floor_to_int(px + splat(0.5f)), 0, g.width - 1);
  iy = clamp(floor_to_int(py + splat(0.5f)), 0, g.height - 1);
}
inline VI pixel_index(const GBuffer& g, VI ix, VI iy) { return iy * splat_i(g.width) + ix; }

inline Mask on_screen(const GBuffer& g, VF px, VF py) {
  return gt(px, splat(-0.5f)) & gt(py, splat(-0.5f)) & lt(px, splat(float(g.width) - 0.5f)) &
         lt(py, splat(float(g.height) - 0.5f));
}

// f(x0, y, valid) for every block of 16 pixels of every row; rows are split over the
// workers as in for_each_pixel, so results do not depend on the thread count.
template <class F>
void for_each_block(const GBuffer& g, F&& f) {
  // Rows go to whichever worker is free, two at a time: a frame's rows cost unequal time
  // (sky rows nothing), and an even split of the rows left the second thread idle for
  // much of a 320x180 frame (docs/nnao.md, "Speed").
  parallel_for_dynamic(g.height, 2, [&](int64_t y0, int64_t y1) {
    for (int64_t y = y0; y < y1; ++y)
      for (int x0 = 0; x0 < g.width; x0 += kLanes) {
        const int n = g.width - x0 < kLanes ? g.width - x0 : kLanes;
        f(x0, int(y), Mask((1u << n) - 1));
      }
  });
}

// What every method reads first for a block: depth (tail lanes read as sky), which lanes
// are live (in the row, not sky), the pixel coordinates and the view-space position.
struct Block {
  int x0, y;
  int64_t i0;  // index of lane 0
  Mask valid, live;
  VF z, X, Y, px, py;  // depth, pixel coordinates, view-space x and y (z_view = -z)

  Block(const GBuffer& g, int x0_, int y_, Mask valid_)
      : x0(x0_), y(y_), i0(int64_t(y_) * g.width + x0_), valid(valid_) {
    z = load(g.z + i0, valid, INFINITY);
    live = valid & ~sky(z);
    X = to_float(lane_index() + splat_i(x0));
    Y = splat(float(y));
    position(g, X, Y, z, px, py);
  }

  // One step of a screen-space march from these pixels to (qx, qy): lanes that left the
  // screen drop out of `alive` (the vector form of `break`); returns the lanes that see
  // geometry there, with the sample's view-space offset (vx, vy, vz) from the pixels.
  Mask sample(const GBuffer& g, VF qx, VF qy, Mask& alive, VF& vx, VF& vy, VF& vz) const {
    alive &= on_screen(g, qx, qy);
    VI ix, iy;
    clamped_pixel(g, qx, qy, ix, iy);
    const VF zj = gather(g.z, pixel_index(g, ix, iy), alive, INFINITY);
    position(g, to_float(ix), to_float(iy), zj, vx, vy);
    vx = vx - px, vy = vy - py;
    vz = z - zj;  // (-zj) - (-z)
    return alive & ~sky(zj);
  }
};

}  // namespace nns::screen_space::simd
