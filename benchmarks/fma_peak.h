#pragma once
// The machine's measured FP32 FMA peak, so benchmarks can report an honest "% of peak"
// instead of a figure derived from a nominal clock (boost clocks and the number of FMA
// pipes vary; on Zen 5 it is 2 x 512-bit FMA per cycle per core).
//
// Each thread runs kChains independent FMA chains in registers: with FMA latency 4 and
// 2 pipes, 8 chains saturate the pipes; 24 leave a margin. Nothing touches memory.
#include <immintrin.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>

#include "core/thread_pool.h"

namespace nns::benchmarks {

#if defined(__AVX512F__)
using FmaVec = __m512;
inline constexpr int kFmaLanes = 16;
inline FmaVec fma_set1(float x) { return _mm512_set1_ps(x); }
inline FmaVec fma_op(FmaVec a, FmaVec b, FmaVec c) { return _mm512_fmadd_ps(a, b, c); }
inline float fma_sum(FmaVec v) { return _mm512_reduce_add_ps(v); }
#elif defined(__AVX2__) && defined(__FMA__)
using FmaVec = __m256;
inline constexpr int kFmaLanes = 8;
inline FmaVec fma_set1(float x) { return _mm256_set1_ps(x); }
inline FmaVec fma_op(FmaVec a, FmaVec b, FmaVec c) { return _mm256_fmadd_ps(a, b, c); }
inline float fma_sum(FmaVec v) {
  alignas(32) float t[8];
  _mm256_store_ps(t, v);
  return t[0] + t[1] + t[2] + t[3] + t[4] + t[5] + t[6] + t[7];
}
#else
using FmaVec = float;
inline constexpr int kFmaLanes = 1;
inline FmaVec fma_set1(float x) { return x; }
inline FmaVec fma_op(FmaVec a, FmaVec b, FmaVec c) { return a * b + c; }
inline float fma_sum(FmaVec v) { return v; }
#endif

inline constexpr int kChains = 24;

// Runs `iters` rounds of kChains FMAs; returns a value that depends on all of them so
// the compiler cannot drop the work.
__attribute__((noinline)) inline float fma_chains(int64_t iters, float seed) {
  FmaVec acc[kChains];
  for (int c = 0; c < kChains; ++c) acc[c] = fma_set1(seed + float(c));
  const FmaVec m = fma_set1(0.999999f), a = fma_set1(1e-7f);
  for (int64_t i = 0; i < iters; ++i) {
#pragma GCC unroll 24
    for (int c = 0; c < kChains; ++c) acc[c] = fma_op(acc[c], m, a);
  }
  float s = 0;
  for (int c = 0; c < kChains; ++c) s += fma_sum(acc[c]);
  return s;
}

inline double fma_flops_per_iter() { return double(kChains) * kFmaLanes * 2.0; }

// GFLOP/s of `threads` threads of the global pool running FMA chains at once (best of
// a few short runs). Sets the pool to `threads` and leaves it so.
inline double measure_fma_peak_gflops(int threads, int64_t iters = 20'000'000 / kChains * 4) {
  set_num_threads(threads);
  std::atomic<float> sink{0};
  double best = 0;
  for (int rep = 0; rep < 5; ++rep) {
    auto t0 = std::chrono::steady_clock::now();
    ThreadPool::global().run([&](int w, int) { sink.store(fma_chains(iters, float(w)), std::memory_order_relaxed); });
    auto t1 = std::chrono::steady_clock::now();
    double s = std::chrono::duration<double>(t1 - t0).count();
    best = std::max(best, fma_flops_per_iter() * double(iters) * threads / s / 1e9);
  }
  return best;
}

}  // namespace nns::benchmarks
