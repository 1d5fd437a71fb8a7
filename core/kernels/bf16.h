#pragma once
// bfloat16: the top 16 bits of an IEEE float (8 exponent bits, 7 stored mantissa bits).
// fp32 -> bf16 rounds to nearest, ties to even, on the bit pattern: adding 0x7fff plus the
// lowest kept bit and truncating carries into the exponent exactly when the value rounds
// up to the next binade (or to infinity past the largest finite bf16), and handles
// denormals the same way as normals. A NaN would lose its payload to that carry (a NaN
// whose set bits are all in the low half turns into infinity), so it is kept a NaN with
// the quiet bit set instead. The vector version gives the same bits (tests/core/test_bf16.cpp).
#include <immintrin.h>

#include <bit>
#include <cstdint>

#include "core/kernels/cpu_features.h"

namespace nns {

inline uint16_t bf16_bits(float x) {
  const uint32_t u = std::bit_cast<uint32_t>(x);
  if ((u & 0x7fffffffu) > 0x7f800000u) return uint16_t((u >> 16) | 0x0040u);
  return uint16_t((u + 0x7fffu + ((u >> 16) & 1u)) >> 16);
}

inline float bf16_to_float(uint16_t h) { return std::bit_cast<float>(uint32_t(h) << 16); }

// x rounded to the nearest bf16, as a float.
inline float round_to_bf16(float x) { return bf16_to_float(bf16_bits(x)); }

namespace bf16_detail {

// v rounded to the nearest bf16 (NaN: quiet bit set), as the high halves of 32-bit lanes
// with garbage in the low halves: what pair_bf16_avx512 combines with a shift and a
// ternary-logic select (14 instructions for two vectors; producing each one's 16-bit
// pattern first and then shifting and or-ing them took 20). NaN is found by an unordered
// compare, which gives the same mask as the scalar test of the bits.
__attribute__((target("avx512f"))) inline __m512i bf16_high16(__m512 v) {
  const __m512i u = _mm512_castps_si512(v);
  const __m512i lsb = _mm512_and_si512(_mm512_srli_epi32(u, 16), _mm512_set1_epi32(1));
  const __m512i rounded = _mm512_add_epi32(_mm512_add_epi32(u, _mm512_set1_epi32(0x7fff)), lsb);
  const __mmask16 nan = _mm512_cmp_ps_mask(v, v, _CMP_UNORD_Q);
  return _mm512_mask_or_epi32(rounded, nan, u, _mm512_set1_epi32(0x00400000));
}

// Lane j: bf16(lo[j]) in the low half, bf16(hi[j]) in the high half.
__attribute__((target("avx512f"))) inline __m512i pair_words(__m512 lo, __m512 hi) {
  const __m512i l = _mm512_srli_epi32(bf16_high16(lo), 16);
  // (h & high) | l: l's high half is zero.
  return _mm512_ternarylogic_epi32(bf16_high16(hi), _mm512_set1_epi32(int(0xffff0000u)), l, 0xEA);
}

__attribute__((target("avx512f"))) inline void pair_bf16_avx512(uint32_t* __restrict dst, const float* __restrict src,
                                                                int W, int64_t kc) {
  for (int64_t k = 0; k < kc; k += 2) {
    const float* lo = src + k * W;
    const float* hi = lo + W;
    uint32_t* d = dst + k / 2 * W;
    for (int j = 0; j < W; j += 16) {
      const int n = W - j >= 16 ? 16 : W - j;
      const __mmask16 m = __mmask16((1u << n) - 1u);
      const __m512 h = k + 1 < kc ? _mm512_maskz_loadu_ps(m, hi + j) : _mm512_setzero_ps();
      _mm512_mask_storeu_epi32(d + j, m, pair_words(_mm512_maskz_loadu_ps(m, lo + j), h));
    }
  }
}

inline void pair_bf16_scalar(uint32_t* __restrict dst, const float* __restrict src, int W, int64_t kc) {
  for (int64_t k = 0; k < kc; k += 2)
    for (int j = 0; j < W; ++j) {
      const uint32_t lo = bf16_bits(src[k * W + j]);
      const uint32_t hi = k + 1 < kc ? bf16_bits(src[(k + 1) * W + j]) : 0u;
      dst[k / 2 * W + j] = lo | hi << 16;
    }
}

}  // namespace bf16_detail

// A packed GEMM panel (kc steps of W floats, k-major: gemm_pack.h) in the layout that
// vdpbf16ps multiplies: ceil(kc/2) steps of W 32-bit words, word j of step p holding
// bf16(src[2p][j]) in its low half and bf16(src[2p+1][j]) in its high half (zero past kc).
inline void pair_bf16(uint32_t* dst, const float* src, int W, int64_t kc) {
  if (cpu_features().avx512f) return bf16_detail::pair_bf16_avx512(dst, src, W, kc);
  bf16_detail::pair_bf16_scalar(dst, src, W, kc);
}

// The 16 floats of v rounded to bf16 (round_to_bf16 on each lane).
__attribute__((target("avx512f"))) inline __m512 round_to_bf16_ps(__m512 v) {
  return _mm512_castsi512_ps(_mm512_and_si512(bf16_detail::bf16_high16(v), _mm512_set1_epi32(int(0xffff0000u))));
}
// v, or v rounded when kRound: for kernels instantiated for both precisions.
template <bool kRound>
__attribute__((target("avx512f"))) inline __m512 maybe_round_to_bf16_ps(__m512 v) {
  if constexpr (kRound) return round_to_bf16_ps(v);
  return v;
}

namespace bf16_detail {
__attribute__((target("avx512f"))) inline void round_row_avx512(float* __restrict dst, const float* __restrict src,
                                                                int64_t cols) {
  for (int64_t j = 0; j < cols; j += 16) {
    const __mmask16 m = cols - j >= 16 ? __mmask16(0xffff) : __mmask16((1u << (cols - j)) - 1u);
    _mm512_mask_storeu_ps(dst + j, m, round_to_bf16_ps(_mm512_maskz_loadu_ps(m, src + j)));
  }
}
}  // namespace bf16_detail

// dst[i * ldd + j] = round_to_bf16(src[i * ld + j]) for i < rows, j < cols (ldd = cols
// unless given).
inline void round_copy_bf16(float* dst, const float* src, int64_t rows, int64_t cols, int64_t ld, int64_t ldd = -1) {
  if (ldd < 0) ldd = cols;
  const bool vec = cpu_features().avx512f;
  for (int64_t i = 0; i < rows; ++i) {
    if (vec) {
      bf16_detail::round_row_avx512(dst + i * ldd, src + i * ld, cols);
      continue;
    }
    for (int64_t j = 0; j < cols; ++j) dst[i * ldd + j] = round_to_bf16(src[i * ld + j]);
  }
}

}  // namespace nns
