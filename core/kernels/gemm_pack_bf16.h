#pragma once
// Packing straight into the bf16 pairs the bf16 micro-kernel reads (pair_bf16's layout,
// core/kernels/bf16.h): the same words as packing fp32 panels (gemm_pack.h) and pairing
// them, without writing the fp32 panels out and reading them back. Pairing after packing
// cost ~17 ms of the ~470 ms bf16 pix2pix iteration (1 thread, Zen 5): 8 for op(A), 9 for
// op(B), beside the packing itself.
//   pack_a_bf16: ceil(mc/MR) panels, each ceil(kc/2) steps of MR words
//   pack_b_bf16: ceil(nc/NR) panels, each ceil(kc/2) steps of NR words
// Two shapes of source: a k step that is a contiguous run (op(A) transposed, op(B) as
// stored, an implicit convolution's column rows) pairs two runs lane by lane
// (pair_rows_avx512); a k step that is strided (op(A) as stored, op(B) transposed) loads
// 32 consecutive k of each of 16 rows, rounds them into 16 words of neighbouring pairs in
// registers and transposes 16 x 16 words: one transpose per 32 k where the fp32 packing
// does one per 16.
// The AVX-512 versions round with vcvtne2ps2bf16 (below), are compiled by target
// attribute and chosen at run time where the bf16 micro-kernel is vdpbf16ps; elsewhere
// the fp32 panel is packed and paired (the reference the tests compare with).
#include <immintrin.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/kernels/bf16.h"
#include "core/kernels/cpu_features.h"
#include "core/kernels/gemm_pack.h"
#include "core/kernels/gemm_pack_avx512.h"
#include "core/kernels/gemm_precision.h"

namespace nns::gemm_detail {

namespace bf16_pack_detail {

// The AVX-512 packers below run where the bf16 micro-kernel is vdpbf16ps: they round with
// vcvtne2ps2bf16 (AVX512-BF16) and interleave with vpermw (AVX512BW). Forcing the generic
// kernel (force_generic_bf16) forces the fallback packers too, so tests reach them here.
inline bool runs_avx512_bf16() { return bf16_isa() == Bf16Isa::avx512_bf16 && cpu_features().avx512bw; }

inline __mmask16 lanes_mask(int64_t lanes) {
  return lanes >= 16 ? __mmask16(0xffff) : lanes <= 0 ? __mmask16(0) : __mmask16((1u << lanes) - 1u);
}

// Whether a lane of a or b is denormal (exponent bits zero, mantissa bits not).
__attribute__((target("avx512f"))) inline bool any_denormal(__m512 a, __m512 b) {
  const __m512i exponent = _mm512_set1_epi32(0x7f800000), mantissa = _mm512_set1_epi32(0x007fffff);
  const __m512i ua = _mm512_castps_si512(a), ub = _mm512_castps_si512(b);
  const __mmask16 da = _mm512_mask_test_epi32_mask(_mm512_testn_epi32_mask(ua, exponent), ua, mantissa);
  const __mmask16 db = _mm512_mask_test_epi32_mask(_mm512_testn_epi32_mask(ub, exponent), ub, mantissa);
  return (da | db) != 0;
}

// vcvtne2ps2bf16 rounds to nearest even and keeps NaN a NaN with the quiet bit set, as
// bf16_bits, but turns denormal inputs into zeros where bf16_bits rounds them (checked
// on all 2^32 patterns on Zen 5: equal on every other one). A vector holding a denormal
// (rare: none among the GAN's gradients, docs/benchmarks.md) takes bf16_high16's
// integer rounding instead, so the words are those of pair_bf16 whatever the input. The
// instruction replaces the ~14 integer instructions pair_words spends per 16 words.

// Lane j: bf16(lo[j]) | bf16(hi[j]) << 16 (pair_words' result).
__attribute__((target("avx512f,avx512bw,avx512bf16"))) inline __m512i pair_words_fast(__m512 lo, __m512 hi) {
  if (any_denormal(lo, hi)) [[unlikely]]
    return bf16_detail::pair_words(lo, hi);
  // cvtne2ps(hi, lo) holds bf16(lo) in words 0-15 and bf16(hi) in words 16-31: word 2j of
  // the result takes word j, word 2j + 1 takes word 16 + j.
  const __m512i interleave = _mm512_set_epi16(31, 15, 30, 14, 29, 13, 28, 12, 27, 11, 26, 10, 25, 9, 24, 8, 23, 7, 22,
                                              6, 21, 5, 20, 4, 19, 3, 18, 2, 17, 1, 16, 0);
  return _mm512_permutexvar_epi16(interleave, (__m512i)_mm512_cvtne2ps_pbh(hi, lo));
}

// Lane q: bf16(x[2q]) | bf16(x[2q+1]) << 16 for the 32 consecutive floats x = (x0, x1).
__attribute__((target("avx512f,avx512bw,avx512bf16"))) inline __m512i pair_consecutive(__m512 x0, __m512 x1) {
  if (any_denormal(x0, x1)) [[unlikely]] {
    const __m512i even = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
    const __m512i odd = _mm512_add_epi32(even, _mm512_set1_epi32(1));
    return bf16_detail::pair_words(_mm512_permutex2var_ps(x0, even, x1), _mm512_permutex2var_ps(x0, odd, x1));
  }
  // The 32 bf16 in k order are the 16 words, little-endian: bf16(x[2q]) in the low half.
  return (__m512i)_mm512_cvtne2ps_pbh(x1, x0);
}

// d[j] = bf16(lo[j]) | bf16(hi[j]) << 16 for j < n, 0 for n <= j < W; hi null: a zero
// high half (the odd last k of a panel).
__attribute__((target("avx512f,avx512bw,avx512bf16"))) inline void pair_rows_avx512(uint32_t* __restrict d,
                                                                                    const float* lo, const float* hi,
                                                                                    int n, int W) {
  for (int j = 0; j < W; j += 16) {
    const __mmask16 load = lanes_mask(n - j);
    const __m512 h = hi ? _mm512_maskz_loadu_ps(load, hi + j) : _mm512_setzero_ps();
    _mm512_mask_storeu_epi32(d + j, lanes_mask(W - j), pair_words_fast(_mm512_maskz_loadu_ps(load, lo + j), h));
  }
}

// The bf16 counterpart of pack_transposed16: dst[q * W + i] = the pair of src[i * ld + 2q]
// and src[i * ld + 2q + 1] for i < rows (<= 16), 2q < kc (zero past kc); zero words for
// rows <= i < width.
__attribute__((target("avx512f,avx512bw,avx512bf16"))) inline void pack_transposed16_avx512(uint32_t* dst, int W,
                                                                                            int width, const float* src,
                                                                                            int64_t ld, int rows,
                                                                                            int64_t kc) {
  const __mmask16 keep = lanes_mask(width);
  for (int64_t k = 0; k < kc; k += 32) {
    const int64_t n = std::min<int64_t>(32, kc - k);
    const __mmask16 m0 = lanes_mask(n), m1 = lanes_mask(n - 16);
    __m512 r[16];
    for (int i = 0; i < 16; ++i) {
      if (i >= rows) {
        r[i] = _mm512_setzero_ps();
        continue;
      }
      // Two blocks of 32 ahead: 16 rows (ld apart) read 128 bytes at a time from memory
      // left the direct packing slower than fp32 packing plus pairing (1024 x 8192 A:
      // 2.64 against 2.56 ms); 1.49 with the prefetch.
      _mm_prefetch(reinterpret_cast<const char*>(src + i * ld + k + 64), _MM_HINT_T0);
      _mm_prefetch(reinterpret_cast<const char*>(src + i * ld + k + 80), _MM_HINT_T0);
      const __m512 x0 = _mm512_maskz_loadu_ps(m0, src + i * ld + k);
      const __m512 x1 = _mm512_maskz_loadu_ps(m1, src + i * ld + k + 16);
      r[i] = _mm512_castsi512_ps(pair_consecutive(x0, x1));
    }
    transpose16x16(r);  // a permutation of 32-bit lanes: the words are moved, not changed
    const int64_t steps = (n + 1) / 2;
    for (int64_t q = 0; q < steps; ++q)
      _mm512_mask_storeu_epi32(dst + (k / 2 + q) * W, keep, _mm512_castps_si512(r[q]));
  }
}

template <int MR>
__attribute__((target("avx512f,avx512bw,avx512bf16"))) void pack_a_avx512(uint32_t* __restrict dst, const MatView& A,
                                                                          int64_t i0, int64_t mc, int64_t k0,
                                                                          int64_t kc) {
  static_assert(MR <= 16, "one transposed block of rows per panel");
  const int64_t kp = (kc + 1) / 2;
  for (int64_t ip = 0; ip < mc; ip += MR, dst += MR * kp) {
    const int m = int(std::min<int64_t>(MR, mc - ip));
    if (!A.trans) {
      pack_transposed16_avx512(dst, MR, MR, A.ptr(i0 + ip, k0), A.ld, m, kc);
      continue;
    }
    // op(A) columns are rows of A: each k step is a contiguous run of m values.
    for (int64_t k = 0; k < kc; k += 2) {
      const float* lo = A.ptr(i0 + ip, k0 + k);
      const float* hi = k + 1 < kc ? A.ptr(i0 + ip, k0 + k + 1) : nullptr;
      // These rows' part of the panel after next: the rows are ld apart and each is read
      // MR values at a time, too short a run for the hardware prefetcher (an 8192 x 1024
      // A from memory: 2.5 ms instead of 3.3-4.8 without).
      __builtin_prefetch(lo + 2 * MR);
      if (hi) __builtin_prefetch(hi + 2 * MR);
      pair_rows_avx512(dst + k / 2 * MR, lo, hi, m, MR);
    }
  }
}

template <int NR>
__attribute__((target("avx512f,avx512bw,avx512bf16"))) void pack_b_avx512(uint32_t* __restrict dst, const MatView& B,
                                                                          int64_t k0, int64_t kc, int64_t j0,
                                                                          int64_t nc) {
  static_assert(NR % 16 == 0, "panels are whole zmm vectors");
  const int64_t kp = (kc + 1) / 2;
  for (int64_t jp = 0; jp < nc; jp += NR, dst += NR * kp) {
    const int n = int(std::min<int64_t>(NR, nc - jp));
    if (B.trans) {
      for (int j = 0; j < NR; j += 16)
        pack_transposed16_avx512(dst + j, NR, 16, B.ptr(k0, j0 + jp + j), B.ld, std::clamp(n - j, 0, 16), kc);
      continue;
    }
    for (int64_t k = 0; k < kc; k += 2) {
      const float* lo = B.ptr(k0 + k, j0 + jp);
      const float* hi = k + 1 < kc ? B.ptr(k0 + k + 1, j0 + jp) : nullptr;
      if (n == NR)
        // As pack_b: fetch these rows' part of the next panel now (rows of B are usually
        // a page or more apart).
        for (int j = 0; j < NR; j += 16) {
          __builtin_prefetch(lo + NR + j);
          if (hi) __builtin_prefetch(hi + NR + j);
        }
      pair_rows_avx512(dst + k / 2 * NR, lo, hi, n, NR);
    }
  }
}

// Elsewhere: the fp32 panels, then pair_bf16 (scratch of kc x W floats per panel).
template <int W, class PackFp32>
void pack_then_pair(uint32_t* dst, int64_t extent, int64_t kc, PackFp32&& pack_fp32) {
  thread_local std::vector<float> scratch;
  const int64_t kp = (kc + 1) / 2;
  scratch.resize(size_t(W * kc));
  for (int64_t p = 0; p < extent; p += W, dst += W * kp) {
    pack_fp32(scratch.data(), p, std::min<int64_t>(W, extent - p));
    pair_bf16(dst, scratch.data(), W, kc);
  }
}

}  // namespace bf16_pack_detail

// pair_bf16 applied to pack_a<MR>'s panels of op(A)[i0 : i0+mc, k0 : k0+kc].
template <int MR>
void pack_a_bf16(uint32_t* dst, const MatView& A, int64_t i0, int64_t mc, int64_t k0, int64_t kc) {
  if constexpr (MR <= 16)
    if (bf16_pack_detail::runs_avx512_bf16()) return bf16_pack_detail::pack_a_avx512<MR>(dst, A, i0, mc, k0, kc);
  bf16_pack_detail::pack_then_pair<MR>(dst, mc, kc,
                                       [&](float* s, int64_t p, int64_t m) { pack_a<MR>(s, A, i0 + p, m, k0, kc); });
}

// pair_bf16 applied to pack_b<NR>'s panels of op(B)[k0 : k0+kc, j0 : j0+nc].
template <int NR>
void pack_b_bf16(uint32_t* dst, const MatView& B, int64_t k0, int64_t kc, int64_t j0, int64_t nc) {
  if constexpr (NR % 16 == 0)
    if (bf16_pack_detail::runs_avx512_bf16()) return bf16_pack_detail::pack_b_avx512<NR>(dst, B, k0, kc, j0, nc);
  bf16_pack_detail::pack_then_pair<NR>(dst, nc, kc,
                                       [&](float* s, int64_t p, int64_t n) { pack_b<NR>(s, B, k0, kc, j0 + p, n); });
}

}  // namespace nns::gemm_detail
