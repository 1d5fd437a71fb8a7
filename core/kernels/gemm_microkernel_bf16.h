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

#include <cstdint>

#include "core/kernels/bf16.h"
#include "core/kernels/gemm_microkernel_generic.h"
#include "core/kernels/gemm_tile_avx512.h"

namespace nns::gemm_detail {

template <int MR, int NV>
struct Avx512Bf16Kernel : TileDispatch<Avx512Bf16Kernel<MR, NV>, MR, NV, uint32_t> {
  static constexpr int mr = MR;
  static constexpr int nr = NV * 16;

  // kp pair steps; noipa as the fp32 kernel's tile.
  template <int ROWS, int V>
  __attribute__((noipa, target("avx512f,avx512bf16"))) static void tile(int64_t kp, const uint32_t* __restrict a,
                                                                        const uint32_t* __restrict b,
                                                                        float* __restrict c, int64_t ldc, float alpha,
                                                                        float beta, int m, int n) {
    __m512 acc[ROWS][V];
#pragma GCC unroll 32
    for (int r = 0; r < ROWS; ++r)
#pragma GCC unroll 4
      for (int v = 0; v < V; ++v) acc[r][v] = _mm512_setzero_ps();
    // Into L2 only: with half the fp32 kernel's k steps per tile, C lines fetched into L1
    // at the start were costlier than the misses they saved where the rows of C are a
    // power of two apart (the tile's rows then share L1 sets): weight gradients
    // 256 x 2048 x 512 (ldc 2048) 307 -> 342 GFLOP/s, 128 x 1024 x 512 303 -> 315
    // (median of 5, alternating; the fp32 kernel: no change, 177 / 179-180).
    prefetch_c_tile<ROWS, V, _MM_HINT_T1>(c, ldc);
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
    store_c_tile<ROWS, V>(acc, c, ldc, alpha, beta, m, n);
  }
};

template <int MR, int NR>
struct GenericBf16Kernel {
  static void run(int64_t kp, const uint32_t* __restrict a, const uint32_t* __restrict b, float* __restrict c,
                  int64_t ldc, float alpha, float beta, int m, int n) {
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
    store_c_block<MR, NR>(acc, c, ldc, alpha, beta, m, n);
  }
};

}  // namespace nns::gemm_detail
