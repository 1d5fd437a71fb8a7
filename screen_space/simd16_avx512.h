#pragma once
// simd16's AVX-512 backend (include screen_space/simd16.h, not this): one instruction per
// operation on a zmm register, with the generic backend's results lane for lane.
#include <immintrin.h>

#include <cstdint>

#include "screen_space/simd16_lanes.h"

namespace nns::screen_space::simd {

constexpr const char* kBackend = "avx512";

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
// vminps(x, y) is x < y ? x : y; the generic min(a, b) is b < a ? b : a, so b goes
// first (they differ when a lane holds a NaN, or -0 against +0).
inline VF min(VF a, VF b) { return {_mm512_min_ps(b.v, a.v)}; }
inline VF max(VF a, VF b) { return {_mm512_max_ps(b.v, a.v)}; }
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
// a * 2^n rounded once, as std::ldexp, for integral n (non-integral n: scalef floors it,
// ldexp(a, int(n)) truncates).
inline VF scale2(VF a, VF n) { return {_mm512_scalef_ps(a.v, n.v)}; }
inline VF scale2_normal(VF a, VF n) { return scale2(a, n); }  // n in [-126, 127]
// PReLU with beta (the NNAO head): x > 0 ? beta x : alpha x.
inline VF prelu(VF x, VF alpha, VF beta) {
  return {_mm512_mask_blend_ps(_mm512_cmp_ps_mask(x.v, _mm512_setzero_ps(), _CMP_GT_OQ), _mm512_mul_ps(alpha.v, x.v),
                               _mm512_mul_ps(beta.v, x.v))};
}

}  // namespace nns::screen_space::simd
