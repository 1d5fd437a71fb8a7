#pragma once
// bf16 GEMM micro-kernels with fp32 accumulation: one MR x NR block of C from panels in
// pair_bf16's layout (core/kernels/bf16.h): kp steps, each of MR words of A and NR words
// of B, a word holding two consecutive k of one row (A) or column (B).
// C := alpha * acc + beta * C (C not read when beta == 0), as the fp32 kernels.
//
// Avx512Bf16Kernel: vdpbf16ps does 32 multiply-adds per instruction where vfmadd231ps
// does 16; same 14 x 32 tile and register plan as gemm_microkernel_avx512.h (28
// accumulators, 2 B vectors, one broadcast word of A per row). It is compiled with a
// function target attribute, so every build contains it and bf16_isa()
// (gemm_precision.h) picks it from cpuid. The instruction treats denormal inputs as zero
// and flushes denormal results; its products of two bf16 are exact in fp32.
// GenericBf16Kernel: the same sums in plain float (products exact too), for CPUs
// without AVX512-BF16.
#include <immintrin.h>

#include <array>
#include <cstdint>
#include <utility>

#include "core/kernels/bf16.h"

namespace nns::gemm_detail {

template <int MR, int NV>
struct Avx512Bf16Kernel {
  static constexpr int mr = MR;
  static constexpr int nr = NV * 16;

  static void run(int64_t kp, const uint32_t* a, const uint32_t* b, float* c, int64_t ldc,
                  float alpha, float beta, int m, int n) {
    if (m == MR && n > nr - 16) return tile<MR, NV>(kp, a, b, c, ldc, alpha, beta, m, n);
    static constexpr auto full = table<NV>(std::make_integer_sequence<int, MR>());
    static constexpr auto half = table<1>(std::make_integer_sequence<int, MR>());
    (n <= 16 ? half : full)[m - 1](kp, a, b, c, ldc, alpha, beta, m, n);
  }

 private:
  using Fn = void (*)(int64_t, const uint32_t*, const uint32_t*, float*, int64_t, float, float,
                      int, int);
  template <int V, int... R>
  static constexpr std::array<Fn, MR> table(std::integer_sequence<int, R...>) {
    return {&tile<R + 1, V>...};
  }

  template <int ROWS, int V>
  __attribute__((noipa, target("avx512f,avx512bf16"))) static void tile(
      int64_t kp, const uint32_t* __restrict a, const uint32_t* __restrict b, float* __restrict c,
      int64_t ldc, float alpha, float beta, int m, int n) {
    __m512 acc[ROWS][V];
#pragma GCC unroll 32
    for (int r = 0; r < ROWS; ++r)
#pragma GCC unroll 4
      for (int v = 0; v < V; ++v) acc[r][v] = _mm512_setzero_ps();
#pragma GCC unroll 32
    for (int r = 0; r < ROWS; ++r) {
      _mm_prefetch(reinterpret_cast<const char*>(c + r * ldc), _MM_HINT_T0);
      _mm_prefetch(reinterpret_cast<const char*>(c + r * ldc + V * 16 - 1), _MM_HINT_T0);
    }
    for (int64_t p = 0; p < kp; ++p) {
      __m512bh bv[V];
#pragma GCC unroll 4
      for (int v = 0; v < V; ++v) bv[v] = (__m512bh)_mm512_load_si512(b + v * 16);
      _mm_prefetch(reinterpret_cast<const char*>(a + 16 * MR), _MM_HINT_T0);
#pragma GCC unroll 32
      for (int r = 0; r < ROWS; ++r) {
        const __m512bh ar = (__m512bh)_mm512_set1_epi32(int(a[r]));
#pragma GCC unroll 4
        for (int v = 0; v < V; ++v) acc[r][v] = _mm512_dpbf16_ps(acc[r][v], ar, bv[v]);
      }
      a += MR;
      b += nr;
    }
    __mmask16 mask[V];
#pragma GCC unroll 4
    for (int v = 0; v < V; ++v) {
      int lanes = n - v * 16;
      lanes = lanes < 0 ? 0 : (lanes > 16 ? 16 : lanes);
      mask[v] = __mmask16((1u << lanes) - 1u);
    }
    const __m512 va = _mm512_set1_ps(alpha), vb = _mm512_set1_ps(beta);
#pragma GCC unroll 32
    for (int r = 0; r < ROWS; ++r) {
      if (r >= m) break;
      float* cr = c + r * ldc;
#pragma GCC unroll 4
      for (int v = 0; v < V; ++v) {
        __m512 out;
        if (beta == 0.0f) {
          out = _mm512_mul_ps(va, acc[r][v]);
        } else {
          __m512 old = _mm512_maskz_loadu_ps(mask[v], cr + v * 16);
          out = _mm512_fmadd_ps(va, acc[r][v], beta == 1.0f ? old : _mm512_mul_ps(vb, old));
        }
        _mm512_mask_storeu_ps(cr + v * 16, mask[v], out);
      }
    }
  }
};

template <int MR, int NR>
struct GenericBf16Kernel {
  static void run(int64_t kp, const uint32_t* __restrict a, const uint32_t* __restrict b,
                  float* __restrict c, int64_t ldc, float alpha, float beta, int m, int n) {
    float acc[MR][NR] = {};
    for (int64_t p = 0; p < kp; ++p) {
      for (int r = 0; r < MR; ++r) {
        const float a0 = bf16_to_float(uint16_t(a[r])), a1 = bf16_to_float(uint16_t(a[r] >> 16));
        for (int j = 0; j < NR; ++j)
          acc[r][j] += a0 * bf16_to_float(uint16_t(b[j])) + a1 * bf16_to_float(uint16_t(b[j] >> 16));
      }
      a += MR;
      b += NR;
    }
    for (int r = 0; r < m; ++r)
      for (int j = 0; j < n; ++j) {
        float& out = c[r * ldc + j];
        out = beta == 0.0f ? alpha * acc[r][j] : alpha * acc[r][j] + beta * out;
      }
  }
};

}  // namespace nns::gemm_detail
