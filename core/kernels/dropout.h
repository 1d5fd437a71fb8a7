#pragma once
// Inverted dropout as a kernel pair:  inp, out, mask, dout, dinp all (n).
// Forward keeps each element with probability 1 - p and scales it by 1 / (1 - p), so
// the expected output equals the input; mask holds 0 or 1 / (1 - p) per element and is
// all the backward needs (dinp += dout * mask).
//
// Speed: NNAO drops 16 x 3844 inputs per step, so drawing one 64-bit number per element
// from the scalar generator would cost more than the layer. Instead eight xoshiro256**
// streams run in the lanes of one vector; each 32-bit half of a lane's output gives one
// 24-bit uniform integer, compared against round(p * 2^24), so p is resolved to 2^-24
// (6e-8) and one step masks 16 elements (~10 us for 64K elements on one core here).
// The streams are seeded per fixed chunk of elements from (seed, chunk index), so the
// mask does not depend on the thread count.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/thread_pool.h"

namespace nns {

namespace detail {
// Eight xoshiro256** generators in the lanes of one 512-bit vector (GCC vector
// extensions: AVX-512 registers when available, plain code otherwise). The multiplies
// by 5 and 9 are shifts and adds, so no 64-bit vector multiply is needed.
struct Xoshiro8 {
  typedef uint64_t u64x8 __attribute__((vector_size(64)));
  u64x8 s0, s1, s2, s3;

  static uint64_t splitmix64(uint64_t& x) {
    uint64_t z = (x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  Xoshiro8(uint64_t seed, uint64_t stream) {
    uint64_t x = seed ^ (stream * 0xD1B54A32D192ED03ull);
    for (int l = 0; l < 8; ++l) {
      s0[l] = splitmix64(x);
      s1[l] = splitmix64(x);
      s2[l] = splitmix64(x);
      s3[l] = splitmix64(x);
    }
  }
  static u64x8 rotl(u64x8 v, int k) { return (v << k) | (v >> (64 - k)); }
  // Writes 64 random bytes.
  void next(void* out) {
    const u64x8 t5 = (s1 << 2) + s1;
    const u64x8 r = (rotl(t5, 7) << 3) + rotl(t5, 7);
    const u64x8 t = s1 << 17;
    s2 ^= s0;
    s3 ^= s1;
    s1 ^= s2;
    s0 ^= s3;
    s2 ^= t;
    s3 = rotl(s3, 45);
    std::memcpy(out, &r, sizeof r);
  }
};
}  // namespace detail

inline constexpr int64_t kDropoutChunk = 16 * 1024;  // elements per seeded chunk

template <class T>
void dropout_forward(T* out, T* mask, const T* inp, int64_t n, double p, uint64_t seed) {
  if (p >= 1) {  // everything dropped; 1 / (1 - p) would be inf
    for (int64_t i = 0; i < n; ++i) out[i] = mask[i] = T(0);
    return;
  }
  const uint32_t thresh = uint32_t(std::llround(p * double(1 << 24)));
  const T scale = T(1.0 / (1.0 - p));
  auto chunk = [=](int64_t c, int64_t b, int64_t e) {
    detail::Xoshiro8 gen(seed, uint64_t(c));
    // Random words for a block first, then one plain loop the compiler vectorizes
    // (deciding per element inside the generator loop compiled to scalar code).
    constexpr int64_t kBlock = 1024;
    alignas(64) uint32_t bits[kBlock];
    for (int64_t i = b; i < e; i += kBlock) {
      const int64_t len = e - i < kBlock ? e - i : kBlock;
      for (int64_t k = 0; k < len; k += 16) gen.next(bits + k);
      T* m = mask + i;
      T* y = out + i;
      const T* x = inp + i;
      // Top 24 bits of each word; arithmetic, not a branch (a random branch mispredicts).
      for (int64_t k = 0; k < len; ++k) {
        const T mk = scale * T(int32_t((bits[k] >> 8) >= thresh));
        m[k] = mk;
        y[k] = x[k] * mk;
      }
    }
  };
  // Fixed chunks (the mask must not depend on the thread count), at least four per
  // worker: NNAO's 61504 inputs take ~10 us, less than waking a second thread costs.
  const int64_t nchunks = (n + kDropoutChunk - 1) / kDropoutChunk;
  parallel_for(
      nchunks,
      [&](int64_t c0, int64_t c1) {
        for (int64_t c = c0; c < c1; ++c) chunk(c, c * kDropoutChunk, std::min(n, (c + 1) * kDropoutChunk));
      },
      4);
}

template <class T>
void dropout_backward(T* dinp, const T* dout, const T* mask, int64_t n) {
  parallel_for(
      n,
      [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) dinp[i] += dout[i] * mask[i];
      },
      1 << 15, 16);
}

}  // namespace nns
