#pragma once
// What this CPU (and the OS's saved register state) can execute, from cpuid and xgetbv
// at run time, so that a portable build (-march=x86-64) still uses AVX512-BF16 where it
// exists. AMX is detected and reported only: there is no AMX kernel (it could not be
// tested on the development machine, an AMD EPYC without AMX).
#include <cpuid.h>

#include <cstdint>

namespace nns {

struct CpuFeatures {
  bool avx512f = false;
  bool avx512bw = false;
  bool avx512_bf16 = false;
  bool amx_tile = false;
  bool amx_bf16 = false;
  bool amd = false;  // vendor "AuthenticAMD": the bf16 GEMM's speed against fp32 differs by vendor
};

namespace cpu_detail {

inline uint64_t xcr0() {
  uint32_t lo, hi;
  __asm__ volatile("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
  return uint64_t(hi) << 32 | lo;
}

inline CpuFeatures detect() {
  CpuFeatures f;
  unsigned a, b, c, d;
  if (!__get_cpuid(0, &a, &b, &c, &d)) return f;
  f.amd = b == 0x68747541u && d == 0x69746e65u && c == 0x444d4163u;  // "Auth" "enti" "cAMD"
  if (!__get_cpuid(1, &a, &b, &c, &d)) return f;
  const bool osxsave = c & (1u << 27);
  if (!osxsave || !__get_cpuid_count(7, 0, &a, &b, &c, &d)) return f;
  const uint64_t x = xcr0();
  // SSE, AVX, opmask, upper halves of zmm0-15, zmm16-31 saved by the OS.
  const bool zmm_state = (x & 0xe6) == 0xe6;
  const bool tile_state = (x & (3u << 17)) == (3u << 17);
  f.avx512f = zmm_state && (b & (1u << 16));
  f.avx512bw = f.avx512f && (b & (1u << 30));
  f.amx_bf16 = tile_state && (d & (1u << 22));
  f.amx_tile = tile_state && (d & (1u << 24));
  unsigned max_sub = a;
  if (f.avx512f && max_sub >= 1 && __get_cpuid_count(7, 1, &a, &b, &c, &d)) f.avx512_bf16 = a & (1u << 5);
  return f;
}

}  // namespace cpu_detail

inline const CpuFeatures& cpu_features() {
  static const CpuFeatures f = cpu_detail::detect();
  return f;
}

}  // namespace nns
