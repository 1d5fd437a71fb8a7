#pragma once
// AVX-512 packing of the operands that arrive "the wrong way round" (op(A) rows or
// op(B) columns strided in memory): 16 x 16 register transposes instead of one scalar
// load and store per element. Same layout as gemm_pack.h. Compiled by target attribute,
// so that the bf16 packers (gemm_pack_bf16.h), chosen at run time, have them in any build.
#include <immintrin.h>

#include <cstdint>

namespace nns::gemm_detail {

// r[i] holds row i of a 16 x 16 block; afterwards r[c] holds column c.
__attribute__((target("avx512f"))) inline void transpose16x16(__m512 (&r)[16]) {
  __m512 t[16];
  for (int i = 0; i < 8; ++i) {
    t[2 * i] = _mm512_unpacklo_ps(r[2 * i], r[2 * i + 1]);
    t[2 * i + 1] = _mm512_unpackhi_ps(r[2 * i], r[2 * i + 1]);
  }
  // Per 128-bit lane L, r[4g + j] now holds column 4L + j of rows 4g .. 4g+3.
  for (int g = 0; g < 4; ++g) {
    r[4 * g + 0] = _mm512_shuffle_ps(t[4 * g], t[4 * g + 2], _MM_SHUFFLE(1, 0, 1, 0));
    r[4 * g + 1] = _mm512_shuffle_ps(t[4 * g], t[4 * g + 2], _MM_SHUFFLE(3, 2, 3, 2));
    r[4 * g + 2] = _mm512_shuffle_ps(t[4 * g + 1], t[4 * g + 3], _MM_SHUFFLE(1, 0, 1, 0));
    r[4 * g + 3] = _mm512_shuffle_ps(t[4 * g + 1], t[4 * g + 3], _MM_SHUFFLE(3, 2, 3, 2));
  }
  __m512 out[16];
  for (int j = 0; j < 4; ++j) {
    const __m512 x0 = _mm512_shuffle_f32x4(r[j], r[4 + j], 0x88);
    const __m512 x1 = _mm512_shuffle_f32x4(r[j], r[4 + j], 0xDD);
    const __m512 y0 = _mm512_shuffle_f32x4(r[8 + j], r[12 + j], 0x88);
    const __m512 y1 = _mm512_shuffle_f32x4(r[8 + j], r[12 + j], 0xDD);
    out[j] = _mm512_shuffle_f32x4(x0, y0, 0x88);
    out[8 + j] = _mm512_shuffle_f32x4(x0, y0, 0xDD);
    out[4 + j] = _mm512_shuffle_f32x4(x1, y1, 0x88);
    out[12 + j] = _mm512_shuffle_f32x4(x1, y1, 0xDD);
  }
  for (int i = 0; i < 16; ++i) r[i] = out[i];
}

// dst[k * W + w0 + i] = src[i * ld + k] for i < rows (<= 16), k < kc; zero for rows
// <= i < 16 within the first `width` lanes. W is the packed panel width (MR or NR).
__attribute__((target("avx512f"))) inline void pack_transposed16(float* dst, int W, int width, const float* src,
                                                                 int64_t ld, int rows, int64_t kc) {
  const __mmask16 keep = __mmask16((1u << width) - 1u);
  for (int64_t k = 0; k < kc; k += 16) {
    const int n = kc - k >= 16 ? 16 : int(kc - k);
    const __mmask16 kmask = __mmask16((1u << n) - 1u);
    __m512 r[16];
    for (int i = 0; i < 16; ++i) r[i] = i < rows ? _mm512_maskz_loadu_ps(kmask, src + i * ld + k) : _mm512_setzero_ps();
    transpose16x16(r);
    for (int c = 0; c < n; ++c) _mm512_mask_storeu_ps(dst + (k + c) * W, keep, r[c]);
  }
}

}  // namespace nns::gemm_detail
