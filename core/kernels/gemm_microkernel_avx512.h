#pragma once
// AVX-512 SGEMM micro-kernel: one MR x NR block of C from packed panels.
//   a: packed A micro-panel, kc steps of MR values (row r of the block at a[k*MR + r])
//   b: packed B micro-panel, kc steps of NR values, 64-byte aligned
//   c: the block's top-left element in C (row stride ldc); only the first m rows and n
//      columns are real (edge tiles: the panels are zero-padded, stores are masked)
// C := alpha * acc + beta * C, with C never read when beta == 0.
//
// Zen 5 has two 512-bit FMA pipes of latency 4, so at least 8 independent accumulators
// are needed to hide the latency; MR x NR = 14 x 32 keeps 28 of the 32 zmm registers as
// accumulators, which also gives the best ratio of FMAs to loads (28 per 2 + 14).
// Edge tiles run a copy of the loop with only the rows (and 16-column halves) they
// need (gemm_tile_avx512.h). Every element of C is still
// produced by the same sequence of FMAs whatever tile computes it, so results do not
// depend on how the work is cut between threads.
#include <immintrin.h>

#include <cstdint>

#include "core/kernels/gemm_tile_avx512.h"

namespace nns::gemm_detail {

template <int MR, int NV>
struct Avx512Kernel : TileDispatch<Avx512Kernel<MR, NV>, MR, NV, float> {
  static constexpr int mr = MR;
  static constexpr int nr = NV * 16;
  static constexpr int kPrefetchA = 16;  // k steps ahead

  // ROWS x (V * 16) of C; the panels keep their full strides MR and nr.
  // noipa: a clone specialised on constant arguments (alpha = 1) keeps one more zmm
  // live across the k loop and spills a B vector in the full 14 x 32 tile (-30%).
  template <int ROWS, int V>
  __attribute__((noipa)) static void tile(int64_t kc, const float* __restrict a, const float* __restrict b,
                                          float* __restrict c, int64_t ldc, float alpha, float beta, int m, int n) {
    __m512 acc[ROWS][V];
#pragma GCC unroll 32
    for (int r = 0; r < ROWS; ++r)
#pragma GCC unroll 4
      for (int v = 0; v < V; ++v) acc[r][v] = _mm512_setzero_ps();
    prefetch_c_tile<ROWS, V>(c, ldc);
    for (int64_t k = 0; k < kc; ++k) {
      __m512 bv[V];
#pragma GCC unroll 4
      for (int v = 0; v < V; ++v) bv[v] = _mm512_load_ps(b + v * 16);
      // The B micro-panel stays in L1 across the IR loop; the A micro-panel streams
      // from L2, so that is the one to fetch ahead (prefetching B as well measured no
      // better).
      _mm_prefetch(reinterpret_cast<const char*>(a + kPrefetchA * MR), _MM_HINT_T0);
#pragma GCC unroll 32
      for (int r = 0; r < ROWS; ++r) {
        __m512 ar = _mm512_set1_ps(a[r]);
#pragma GCC unroll 4
        for (int v = 0; v < V; ++v) acc[r][v] = _mm512_fmadd_ps(ar, bv[v], acc[r][v]);
      }
      a += MR;
      b += nr;
    }
    store_c_tile<ROWS, V>(acc, c, ldc, alpha, beta, m, n);
  }
};

}  // namespace nns::gemm_detail
