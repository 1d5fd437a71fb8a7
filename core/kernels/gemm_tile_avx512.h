#pragma once
// What the AVX-512 micro-kernels (fp32: gemm_microkernel_avx512.h; bf16:
// gemm_microkernel_bf16.h) share around their k loops: the choice of tile function for an
// edge tile, the prefetch of the C tile before the loop and its store after it. Kernel
// provides tile<ROWS, V>(kc, a, b, c, ldc, alpha, beta, m, n) over panels of type P.
// The helpers carry a target attribute so that the bf16 kernel, compiled for
// AVX512-BF16 by attribute in any build, can inline them.
#include <immintrin.h>

#include <array>
#include <cstdint>
#include <utility>

namespace nns::gemm_detail {

template <class Kernel, int MR, int NV, class P>
struct TileDispatch {
  static constexpr int mr = MR;
  static constexpr int nr = NV * 16;

  // Edge tiles run a copy of the loop with only the rows (and 16-column halves) they
  // need, so M = 128 does not pay for 10 full tiles of 14.
  static void run(int64_t kc, const P* a, const P* b, float* c, int64_t ldc, float alpha, float beta, int m, int n) {
    if (m == MR && n > nr - 16) return Kernel::template tile<MR, NV>(kc, a, b, c, ldc, alpha, beta, m, n);
    static constexpr auto full = table<NV>(std::make_integer_sequence<int, MR>());
    static constexpr auto half = table<1>(std::make_integer_sequence<int, MR>());
    (n <= 16 ? half : full)[m - 1](kc, a, b, c, ldc, alpha, beta, m, n);
  }

 private:
  using Fn = void (*)(int64_t, const P*, const P*, float*, int64_t, float, float, int, int);
  template <int V, int... R>
  static constexpr std::array<Fn, MR> table(std::integer_sequence<int, R...>) {
    return {&Kernel::template tile<R + 1, V>...};
  }
};

// The C tile is touched only after the k loop: start fetching it now (+8% measured).
// Into L1 (the fp32 kernel) or only L2 (kHint = _MM_HINT_T1, the bf16 kernel, below).
// kHint is an int because GCC's hints are an enum _mm_hint and clang's plain int macros.
template <int ROWS, int V, int kHint = _MM_HINT_T0>
__attribute__((target("avx512f"), always_inline)) inline void prefetch_c_tile(const float* c, int64_t ldc) {
  constexpr auto hint = static_cast<decltype(_MM_HINT_T0)>(kHint);
#pragma GCC unroll 32
  for (int r = 0; r < ROWS; ++r) {
    _mm_prefetch(reinterpret_cast<const char*>(c + r * ldc), hint);
    _mm_prefetch(reinterpret_cast<const char*>(c + r * ldc + V * 16 - 1), hint);
  }
}

// C := alpha * acc + beta * C on the first m rows and n columns (C not read when beta == 0).
template <int ROWS, int V>
__attribute__((target("avx512f"), always_inline)) inline void store_c_tile(const __m512 (&acc)[ROWS][V],
                                                                           float* __restrict c, int64_t ldc,
                                                                           float alpha, float beta, int m, int n) {
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

}  // namespace nns::gemm_detail
