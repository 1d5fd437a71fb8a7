#pragma once
// Packing for the BLIS-style SGEMM: copies a block of op(A) or op(B) into the layout
// the micro-kernel streams, contiguous and zero-padded to whole micro-panels, so the
// kernel never branches on edges or transposes.
//   packed A: panels of MR rows; panel p holds kc steps of MR values (k-major)
//   packed B: panels of NR columns; panel p holds kc steps of NR values (k-major)
#include <algorithm>
#include <cstdint>
#include <cstring>

#if defined(__AVX512F__)
#include "core/kernels/gemm_pack_avx512.h"
#endif

namespace nns::gemm_detail {

// A row-major matrix seen through an optional transpose: at(r, c) = op(M)[r][c].
struct MatView {
  const float* p;
  int64_t ld;
  bool trans;
  const float* ptr(int64_t r, int64_t c) const { return trans ? p + c * ld + r : p + r * ld + c; }
};

// Packs op(A)[i0 : i0+mc, k0 : k0+kc] into ceil(mc/MR) panels.
template <int MR>
inline void pack_a(float* __restrict dst, const MatView& A, int64_t i0, int64_t mc, int64_t k0, int64_t kc) {
  for (int64_t ip = 0; ip < mc; ip += MR, dst += MR * kc) {
    const int m = int(std::min<int64_t>(MR, mc - ip));
    if (A.trans) {
      // op(A) columns are rows of A: each k step is a contiguous run of m values.
      for (int64_t k = 0; k < kc; ++k) {
        const float* src = A.ptr(i0 + ip, k0 + k);
        float* d = dst + k * MR;
        for (int r = 0; r < m; ++r) d[r] = src[r];
        for (int r = m; r < MR; ++r) d[r] = 0.0f;
      }
    } else {
#if defined(__AVX512F__)
      if constexpr (MR <= 16) {
        pack_transposed16(dst, MR, MR, A.ptr(i0 + ip, k0), A.ld, m, kc);
        continue;
      }
#endif
      for (int r = 0; r < m; ++r) {
        const float* src = A.ptr(i0 + ip + r, k0);
        for (int64_t k = 0; k < kc; ++k) dst[k * MR + r] = src[k];
      }
      for (int r = m; r < MR; ++r)
        for (int64_t k = 0; k < kc; ++k) dst[k * MR + r] = 0.0f;
    }
  }
}

// Packs op(B)[k0 : k0+kc, j0 : j0+nc] into ceil(nc/NR) panels.
template <int NR>
inline void pack_b(float* __restrict dst, const MatView& B, int64_t k0, int64_t kc, int64_t j0, int64_t nc) {
  for (int64_t jp = 0; jp < nc; jp += NR, dst += NR * kc) {
    const int n = int(std::min<int64_t>(NR, nc - jp));
    if (!B.trans) {
      for (int64_t k = 0; k < kc; ++k) {
        const float* src = B.ptr(k0 + k, j0 + jp);
        float* d = dst + k * NR;
        if (n == NR) {
          // Rows of B are usually far apart (a page or more): fetch this row's part of
          // the next panel now, so packing one panel at a time (gemm_packed.h) finds it
          // in cache instead of paying a miss per row.
          for (int j = 0; j < NR; j += 16) __builtin_prefetch(src + NR + j);
          std::memcpy(d, src, sizeof(float) * NR);
        } else {
          for (int j = 0; j < n; ++j) d[j] = src[j];
          for (int j = n; j < NR; ++j) d[j] = 0.0f;
        }
      }
    } else {
#if defined(__AVX512F__)
      if constexpr (NR % 16 == 0) {
        for (int j = 0; j < NR; j += 16)
          pack_transposed16(dst + j, NR, 16, B.ptr(k0, j0 + jp + j), B.ld, n - j < 0 ? 0 : (n - j > 16 ? 16 : n - j),
                            kc);
        continue;
      }
#endif
      for (int j = 0; j < n; ++j) {
        const float* src = B.ptr(k0, j0 + jp + j);
        for (int64_t k = 0; k < kc; ++k) dst[k * NR + j] = src[k];
      }
      for (int j = n; j < NR; ++j)
        for (int64_t k = 0; k < kc; ++k) dst[k * NR + j] = 0.0f;
    }
  }
}

}  // namespace nns::gemm_detail
