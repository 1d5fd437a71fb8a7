#pragma once
// Sixteen pixels of a row at a time: the few vector operations the AO methods need
// (arithmetic, compares into bit masks, blends, masked loads and gathers from the
// G-buffer planes). With AVX-512 they are single instructions; without it the same
// functions are plain loops over 16 floats, which the compiler vectorises as far as the
// target allows (AVX2, SSE) — so every build computes the same thing.
//
// Lane l of a block is pixel x0 + l of one row, x0 a multiple of 16: the 4x4 noise
// tiles then depend only on (l & 3, y & 3), and per-row tables replace per-pixel trig.
#include <cmath>
#include <cstdint>

#include "core/thread_pool.h"
#include "screen_space/gbuffer.h"

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace nns::ao::simd {

constexpr int kLanes = 16;
using Mask = uint32_t;  // bit l = lane l (only the low 16 bits are used)

#if defined(__AVX512F__)
struct VF {
  __m512 v;
};
struct VI {
  __m512i v;
};
inline VF splat(float a) { return {_mm512_set1_ps(a)}; }
inline VI splat_i(int a) { return {_mm512_set1_epi32(a)}; }
inline VF load(const float* p) { return {_mm512_loadu_ps(p)}; }
// Lanes outside m read `fill` and touch no memory.
inline VF load(const float* p, Mask m, float fill) {
  return {_mm512_mask_loadu_ps(_mm512_set1_ps(fill), __mmask16(m), p)};
}
inline void store(float* p, VF a, Mask m) { _mm512_mask_storeu_ps(p, __mmask16(m), a.v); }
inline VF operator+(VF a, VF b) { return {_mm512_add_ps(a.v, b.v)}; }
inline VF operator-(VF a, VF b) { return {_mm512_sub_ps(a.v, b.v)}; }
inline VF operator*(VF a, VF b) { return {_mm512_mul_ps(a.v, b.v)}; }
inline VF operator/(VF a, VF b) { return {_mm512_div_ps(a.v, b.v)}; }
inline VF sqrt(VF a) { return {_mm512_sqrt_ps(a.v)}; }
inline VF min(VF a, VF b) { return {_mm512_min_ps(a.v, b.v)}; }
inline VF max(VF a, VF b) { return {_mm512_max_ps(a.v, b.v)}; }
inline VF abs(VF a) { return {_mm512_abs_ps(a.v)}; }
inline VF floor(VF a) { return {_mm512_roundscale_ps(a.v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)}; }
inline VI to_int(VF a) { return {_mm512_cvttps_epi32(a.v)}; }  // truncates, as int(float)
// int(floor(a)) in one instruction (the conversion rounds down): what to_int(floor(a))
// gives, for every float (out of range and NaN: INT_MIN from both).
inline VI floor_to_int(VF a) { return {_mm512_cvt_roundps_epi32(a.v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)}; }
inline VF to_float(VI a) { return {_mm512_cvtepi32_ps(a.v)}; }
inline VI operator+(VI a, VI b) { return {_mm512_add_epi32(a.v, b.v)}; }
inline VI operator*(VI a, VI b) { return {_mm512_mullo_epi32(a.v, b.v)}; }
inline VI clamp(VI a, int lo, int hi) {
  return {_mm512_min_epi32(_mm512_max_epi32(a.v, _mm512_set1_epi32(lo)), _mm512_set1_epi32(hi))};
}
inline VI lane_index() { return {_mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15)}; }
inline Mask lt(VF a, VF b) { return _mm512_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ); }
inline Mask le(VF a, VF b) { return _mm512_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ); }
inline Mask gt(VF a, VF b) { return _mm512_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ); }
inline Mask ge(VF a, VF b) { return _mm512_cmp_ps_mask(a.v, b.v, _CMP_GE_OQ); }
inline VF select(Mask m, VF a, VF b) { return {_mm512_mask_blend_ps(__mmask16(m), b.v, a.v)}; }
inline VF gather(const float* base, VI idx, Mask m, float fill) {
  return {_mm512_mask_i32gather_ps(_mm512_set1_ps(fill), __mmask16(m), idx.v, base, 4)};
}
inline VF scale2(VF a, VF n) { return {_mm512_scalef_ps(a.v, n.v)}; }  // a * 2^n, n integral
// PReLU with beta (the NNAO head): x > 0 ? beta x : alpha x.
inline VF prelu(VF x, VF alpha, VF beta) {
  return {_mm512_mask_blend_ps(_mm512_cmp_ps_mask(x.v, _mm512_setzero_ps(), _CMP_GT_OQ), _mm512_mul_ps(alpha.v, x.v),
                               _mm512_mul_ps(beta.v, x.v))};
}
#else
struct VF {
  float v[kLanes];
};
struct VI {
  int32_t v[kLanes];
};
#define NNS_LANES for (int l = 0; l < kLanes; ++l)
inline VF splat(float a) { VF r; NNS_LANES r.v[l] = a; return r; }
inline VI splat_i(int a) { VI r; NNS_LANES r.v[l] = a; return r; }
inline VF load(const float* p) { VF r; NNS_LANES r.v[l] = p[l]; return r; }
inline VF load(const float* p, Mask m, float fill) { VF r; NNS_LANES r.v[l] = (m >> l & 1) ? p[l] : fill; return r; }
inline void store(float* p, VF a, Mask m) { NNS_LANES if (m >> l & 1) p[l] = a.v[l]; }
inline VF operator+(VF a, VF b) { NNS_LANES a.v[l] += b.v[l]; return a; }
inline VF operator-(VF a, VF b) { NNS_LANES a.v[l] -= b.v[l]; return a; }
inline VF operator*(VF a, VF b) { NNS_LANES a.v[l] *= b.v[l]; return a; }
inline VF operator/(VF a, VF b) { NNS_LANES a.v[l] /= b.v[l]; return a; }
inline VF sqrt(VF a) { NNS_LANES a.v[l] = std::sqrt(a.v[l]); return a; }
inline VF min(VF a, VF b) { NNS_LANES a.v[l] = b.v[l] < a.v[l] ? b.v[l] : a.v[l]; return a; }
inline VF max(VF a, VF b) { NNS_LANES a.v[l] = b.v[l] > a.v[l] ? b.v[l] : a.v[l]; return a; }
inline VF abs(VF a) { NNS_LANES a.v[l] = std::fabs(a.v[l]); return a; }
inline VF floor(VF a) { NNS_LANES a.v[l] = std::floor(a.v[l]); return a; }
inline VI to_int(VF a) { VI r; NNS_LANES r.v[l] = int32_t(a.v[l]); return r; }
inline VI floor_to_int(VF a) { VI r; NNS_LANES r.v[l] = int32_t(std::floor(a.v[l])); return r; }
inline VF to_float(VI a) { VF r; NNS_LANES r.v[l] = float(a.v[l]); return r; }
inline VI operator+(VI a, VI b) { NNS_LANES a.v[l] += b.v[l]; return a; }
inline VI operator*(VI a, VI b) { NNS_LANES a.v[l] *= b.v[l]; return a; }
inline VI clamp(VI a, int lo, int hi) { NNS_LANES a.v[l] = a.v[l] < lo ? lo : (a.v[l] > hi ? hi : a.v[l]); return a; }
inline VI lane_index() { VI r; NNS_LANES r.v[l] = l; return r; }
inline Mask lt(VF a, VF b) { Mask m = 0; NNS_LANES m |= Mask(a.v[l] < b.v[l]) << l; return m; }
inline Mask le(VF a, VF b) { Mask m = 0; NNS_LANES m |= Mask(a.v[l] <= b.v[l]) << l; return m; }
inline Mask gt(VF a, VF b) { Mask m = 0; NNS_LANES m |= Mask(a.v[l] > b.v[l]) << l; return m; }
inline Mask ge(VF a, VF b) { Mask m = 0; NNS_LANES m |= Mask(a.v[l] >= b.v[l]) << l; return m; }
inline VF select(Mask m, VF a, VF b) { NNS_LANES a.v[l] = (m >> l & 1) ? a.v[l] : b.v[l]; return a; }
inline VF gather(const float* base, VI idx, Mask m, float fill) {
  VF r; NNS_LANES r.v[l] = (m >> l & 1) ? base[idx.v[l]] : fill; return r;
}
inline VF scale2(VF a, VF n) { NNS_LANES a.v[l] = std::ldexp(a.v[l], int(n.v[l])); return a; }
// A per-lane choice, not a bit mask and a blend: the compiler vectorises it (with
// select(gt(..)) the portable head built and tested a mask bit by bit).
inline VF prelu(VF x, VF alpha, VF beta) { NNS_LANES x.v[l] = x.v[l] > 0 ? beta.v[l] * x.v[l] : alpha.v[l] * x.v[l]; return x; }
#undef NNS_LANES
#endif

inline VF operator-(VF a) { return splat(0.0f) - a; }
inline VF saturate(VF a) { return min(max(a, splat(0.0f)), splat(1.0f)); }
constexpr Mask kAll = 0xFFFFu;

// data::is_sky on 16 depths: !(z < 1e30) || z <= 0 (NaN is sky).
inline Mask sky(VF z) {
  return (~lt(z, splat(data::kSkyDepth)) | le(z, splat(0.0f))) & kAll;
}

// exp(x) for x <= 0 (the bilateral weights), Cody-Waite reduction and a degree-6
// polynomial: relative error below 2e-7 against std::exp; 0 below -87.
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
  return select(lt(x, splat(-87.0f)), splat(0.0f), scale2(p, n));
}

// normalize() (gbuffer.h) on 16 vectors in place, with its (0, 0, 1) for a zero vector.
inline void normalize(VF& x, VF& y, VF& z) {
  const VF len = sqrt(x * x + y * y + z * z);
  const Mask ok = gt(len, splat(0.0f));
  const VF inv = splat(1.0f) / len;
  x = select(ok, inv * x, splat(0.0f)), y = select(ok, inv * y, splat(0.0f)), z = select(ok, inv * z, splat(1.0f));
}

// The unit normals of the 16 pixels from index i0 (tail lanes: (0, 0, 1)).
inline void load_unit_normals(const GBuffer& g, int64_t i0, Mask valid, VF& x, VF& y, VF& z) {
  x = load(g.nx + i0, valid, 0.0f), y = load(g.ny + i0, valid, 0.0f), z = load(g.nz + i0, valid, 1.0f);
  normalize(x, y, z);
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

}  // namespace nns::ao::simd
