#pragma once
// simd16's AVX2 + FMA backend (include screen_space/simd16.h, not this): a vector is two
// ymm registers (lanes 0-7 and 8-15), with the generic backend's results lane for lane.
// A Mask stays the bits of a uint32: compares come out through movemask, and blends,
// masked loads and gathers take it back as whole lanes (AND with each lane's bit, then
// compare equal), since the instructions read each lane's sign bit.
#include <immintrin.h>

#include <cstdint>

#include "screen_space/simd16_lanes.h"

namespace nns::screen_space::simd {

constexpr const char* kBackend = "avx2";

struct VF {
  __m256 lo, hi;  // lanes 0-7, 8-15
};
struct VI {
  __m256i lo, hi;
};

namespace avx2 {
// Lane l all ones when bit l of m is set.
inline __m256i lanes_lo(Mask m) {
  const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  return _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(m)), bit), bit);
}
inline __m256i lanes_hi(Mask m) {
  const __m256i bit = _mm256_setr_epi32(256, 512, 1024, 2048, 4096, 8192, 16384, 32768);
  return _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(m)), bit), bit);
}
inline Mask bits(__m256 lo, __m256 hi) { return Mask(_mm256_movemask_ps(lo)) | Mask(_mm256_movemask_ps(hi)) << 8; }
template <int kPredicate>
inline Mask compare(__m256 a_lo, __m256 a_hi, __m256 b_lo, __m256 b_hi) {
  return bits(_mm256_cmp_ps(a_lo, b_lo, kPredicate), _mm256_cmp_ps(a_hi, b_hi, kPredicate));
}
inline __m256i clamp8(__m256i a, int lo, int hi) {
  return _mm256_min_epi32(_mm256_max_epi32(a, _mm256_set1_epi32(lo)), _mm256_set1_epi32(hi));
}
// 2^k for integral k in [-126, 127] (a normal float): k + 127 is its exponent field.
inline __m256 pow2(__m256i k) {
  return _mm256_castsi256_ps(_mm256_slli_epi32(_mm256_add_epi32(k, _mm256_set1_epi32(127)), 23));
}
// ldexp(a, int(n)) rounded once, as std::ldexp does, also where the result is subnormal
// (adding n to the exponent field is wrong there, and 2^n alone is no float for n < -126).
// int(n) is what the generic backend takes (INT_MIN for NaN and out of range, as the
// conversion gives), clamped to +-300: 2^-149 * 2^300 and 2^128 * 2^-300 already give
// inf and 0, so no result changes. Two exact steps then bring n into [-126, 127], and
// only the last multiply, by 2^n, rounds:
//  - up (n > 127): a * 2^127 is exact, or it overflows and so does a * 2^n (the factors
//    left are >= 1, inf stays inf);
//  - down (n < -126): a * 2^-102 is exact unless |a| < 2^-24; then the factors left are
//    < 2^-24, so the computed value is <= 2^-126 * 2^-25 and the true one < 2^-151,
//    both below half the least subnormal (2^-150): +-0 from both, sign kept.
// (musl's scalbnf steps down by 2^-102 for the same reason.)
inline __m256 scale2(__m256 a, __m256 nf) {
  __m256i n = clamp8(_mm256_cvttps_epi32(nf), -300, 300);
  for (int step = 0; step < 2; ++step) {
    const __m256i up = _mm256_cmpgt_epi32(n, _mm256_set1_epi32(127));
    const __m256i down = _mm256_cmpgt_epi32(_mm256_set1_epi32(-126), n);
    const __m256i k =
        _mm256_or_si256(_mm256_and_si256(up, _mm256_set1_epi32(127)), _mm256_and_si256(down, _mm256_set1_epi32(-102)));
    a = _mm256_mul_ps(a, pow2(k));
    n = _mm256_sub_epi32(n, k);
  }
  return _mm256_mul_ps(a, pow2(n));  // n in [-126, 127] now (|n| <= 300 at the start)
}
}  // namespace avx2

inline VF splat(float a) { return {_mm256_set1_ps(a), _mm256_set1_ps(a)}; }
inline VI splat_i(int a) { return {_mm256_set1_epi32(a), _mm256_set1_epi32(a)}; }
inline VF load(const float* p) { return {_mm256_loadu_ps(p), _mm256_loadu_ps(p + 8)}; }
// Lanes outside m read `fill` and touch no memory: vmaskmovps neither reads nor faults
// on a lane whose mask is clear (it reads 0 there, replaced by `fill`).
inline VF load(const float* p, Mask m, float fill) {
  const __m256i l = avx2::lanes_lo(m), h = avx2::lanes_hi(m);
  const __m256 f = _mm256_set1_ps(fill);
  return {_mm256_blendv_ps(f, _mm256_maskload_ps(p, l), _mm256_castsi256_ps(l)),
          _mm256_blendv_ps(f, _mm256_maskload_ps(p + 8, h), _mm256_castsi256_ps(h))};
}
// A whole block (all but a row's last) takes plain stores.
inline void store(float* p, VF a, Mask m) {
  if ((m & kAll) == kAll) {
    _mm256_storeu_ps(p, a.lo), _mm256_storeu_ps(p + 8, a.hi);
  } else {
    _mm256_maskstore_ps(p, avx2::lanes_lo(m), a.lo), _mm256_maskstore_ps(p + 8, avx2::lanes_hi(m), a.hi);
  }
}
inline VF operator+(VF a, VF b) { return {_mm256_add_ps(a.lo, b.lo), _mm256_add_ps(a.hi, b.hi)}; }
inline VF operator-(VF a, VF b) { return {_mm256_sub_ps(a.lo, b.lo), _mm256_sub_ps(a.hi, b.hi)}; }
inline VF operator*(VF a, VF b) { return {_mm256_mul_ps(a.lo, b.lo), _mm256_mul_ps(a.hi, b.hi)}; }
inline VF operator/(VF a, VF b) { return {_mm256_div_ps(a.lo, b.lo), _mm256_div_ps(a.hi, b.hi)}; }
inline VF sqrt(VF a) { return {_mm256_sqrt_ps(a.lo), _mm256_sqrt_ps(a.hi)}; }
// vminps(x, y) is x < y ? x : y; the generic min(a, b) is b < a ? b : a, so b goes
// first (they differ when a lane holds a NaN, or -0 against +0).
inline VF min(VF a, VF b) { return {_mm256_min_ps(b.lo, a.lo), _mm256_min_ps(b.hi, a.hi)}; }
inline VF max(VF a, VF b) { return {_mm256_max_ps(b.lo, a.lo), _mm256_max_ps(b.hi, a.hi)}; }
inline VF abs(VF a) {
  const __m256 magnitude = _mm256_castsi256_ps(_mm256_set1_epi32(0x7FFFFFFF));
  return {_mm256_and_ps(a.lo, magnitude), _mm256_and_ps(a.hi, magnitude)};
}
inline VF floor(VF a) {
  return {_mm256_round_ps(a.lo, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC),
          _mm256_round_ps(a.hi, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)};
}
// Truncates, as int(float); out of range and NaN give INT_MIN, as the scalar conversion.
inline VI to_int(VF a) { return {_mm256_cvttps_epi32(a.lo), _mm256_cvttps_epi32(a.hi)}; }
// floor is exact and keeps out-of-range and NaN lanes so: INT_MIN from the conversion.
inline VI floor_to_int(VF a) { return to_int(floor(a)); }
inline VF to_float(VI a) { return {_mm256_cvtepi32_ps(a.lo), _mm256_cvtepi32_ps(a.hi)}; }
inline VI operator+(VI a, VI b) { return {_mm256_add_epi32(a.lo, b.lo), _mm256_add_epi32(a.hi, b.hi)}; }
inline VI operator*(VI a, VI b) { return {_mm256_mullo_epi32(a.lo, b.lo), _mm256_mullo_epi32(a.hi, b.hi)}; }
inline VI clamp(VI a, int lo, int hi) { return {avx2::clamp8(a.lo, lo, hi), avx2::clamp8(a.hi, lo, hi)}; }
inline VI lane_index() {
  return {_mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), _mm256_setr_epi32(8, 9, 10, 11, 12, 13, 14, 15)};
}
// Ordered compares: false where either side is NaN, as the scalar <, <=, >, >=.
inline Mask lt(VF a, VF b) { return avx2::compare<_CMP_LT_OQ>(a.lo, a.hi, b.lo, b.hi); }
inline Mask le(VF a, VF b) { return avx2::compare<_CMP_LE_OQ>(a.lo, a.hi, b.lo, b.hi); }
inline Mask gt(VF a, VF b) { return avx2::compare<_CMP_GT_OQ>(a.lo, a.hi, b.lo, b.hi); }
inline Mask ge(VF a, VF b) { return avx2::compare<_CMP_GE_OQ>(a.lo, a.hi, b.lo, b.hi); }
inline VF select(Mask m, VF a, VF b) {
  return {_mm256_blendv_ps(b.lo, a.lo, _mm256_castsi256_ps(avx2::lanes_lo(m))),
          _mm256_blendv_ps(b.hi, a.hi, _mm256_castsi256_ps(avx2::lanes_hi(m)))};
}
// vgatherdps loads only the lanes of its mask (the others keep `fill`, and fault on
// nothing).
inline VF gather(const float* base, VI idx, Mask m, float fill) {
  const __m256 f = _mm256_set1_ps(fill);
  return {_mm256_mask_i32gather_ps(f, base, idx.lo, _mm256_castsi256_ps(avx2::lanes_lo(m)), 4),
          _mm256_mask_i32gather_ps(f, base, idx.hi, _mm256_castsi256_ps(avx2::lanes_hi(m)), 4)};
}
inline VF scale2(VF a, VF n) { return {avx2::scale2(a.lo, n.lo), avx2::scale2(a.hi, n.hi)}; }
// scale2 for n in [-126, 127]: 2^n is a normal float, and the one multiply by it rounds
// once, as ldexp does (also to a subnormal result), so the steps above are not needed.
inline VF scale2_normal(VF a, VF n) {
  return {_mm256_mul_ps(a.lo, avx2::pow2(_mm256_cvttps_epi32(n.lo))),
          _mm256_mul_ps(a.hi, avx2::pow2(_mm256_cvttps_epi32(n.hi)))};
}
// PReLU with beta (the NNAO head): x > 0 ? beta x : alpha x.
inline VF prelu(VF x, VF alpha, VF beta) {
  const __m256 zero = _mm256_setzero_ps();
  const __m256 pos_lo = _mm256_cmp_ps(x.lo, zero, _CMP_GT_OQ), pos_hi = _mm256_cmp_ps(x.hi, zero, _CMP_GT_OQ);
  return {_mm256_blendv_ps(_mm256_mul_ps(alpha.lo, x.lo), _mm256_mul_ps(beta.lo, x.lo), pos_lo),
          _mm256_blendv_ps(_mm256_mul_ps(alpha.hi, x.hi), _mm256_mul_ps(beta.hi, x.hi), pos_hi)};
}

}  // namespace nns::screen_space::simd
