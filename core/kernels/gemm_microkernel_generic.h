#pragma once
// Portable SGEMM micro-kernel (same contract as gemm_microkernel_avx512.h) for builds
// without AVX2: plain loops over a small register block that the compiler may
// vectorise with SSE. Correct everywhere, fast nowhere.
#include <cstdint>

namespace nns::gemm_detail {

// C := alpha * acc + beta * C on the first m rows and n columns (C not read when beta == 0).
template <int MR, int NR>
inline void store_c_block(const float (&acc)[MR][NR], float* __restrict c, int64_t ldc, float alpha, float beta, int m,
                          int n) {
  for (int r = 0; r < m; ++r)
    for (int j = 0; j < n; ++j) {
      float& out = c[r * ldc + j];
      out = beta == 0.0f ? alpha * acc[r][j] : alpha * acc[r][j] + beta * out;
    }
}

template <int MR, int NR>
struct GenericKernel {
  static constexpr int mr = MR;
  static constexpr int nr = NR;

  static void run(int64_t kc, const float* __restrict a, const float* __restrict b, float* __restrict c, int64_t ldc,
                  float alpha, float beta, int m, int n) {
    float acc[MR][NR] = {};
    for (int64_t k = 0; k < kc; ++k) {
      for (int r = 0; r < MR; ++r)
        for (int j = 0; j < NR; ++j) acc[r][j] += a[r] * b[j];
      a += MR;
      b += NR;
    }
    store_c_block<MR, NR>(acc, c, ldc, alpha, beta, m, n);
  }
};

}  // namespace nns::gemm_detail
