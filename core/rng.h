#pragma once
// Rng: a seedable generator passed explicitly to whatever needs randomness (no global
// state), so the same seed gives the same numbers wherever it is used.
//
// xoshiro256** (Blackman & Vigna 2018): fast, 256-bit state, good statistics. Seeding
// goes through splitmix64 as its authors recommend. The state is four words so it can
// be saved in a checkpoint and restored exactly.
#include <array>
#include <cmath>
#include <cstdint>

namespace nns {

class Rng {
 public:
  using State = std::array<uint64_t, 4>;

  explicit Rng(uint64_t seed = 0) { seed_with(seed); }

  void seed_with(uint64_t seed) {
    uint64_t x = seed;
    for (auto& w : s_) w = splitmix64(x);
  }

  // An independent generator for sub-stream `stream` (a worker, a layer, a view):
  // deterministic in (this generator's state, stream) and does not advance this one.
  Rng fork(uint64_t stream) const {
    uint64_t x = s_[0] ^ (s_[1] << 1) ^ (stream * 0x9E3779B97F4A7C15ull);
    Rng r;
    for (auto& w : r.s_) w = splitmix64(x);
    return r;
  }

  uint64_t next_u64() {
    const uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  uint32_t next_u32() { return uint32_t(next_u64() >> 32); }

  // Uniform in [0, 1): the top 24 (float) or 53 (double) bits as a fraction.
  float uniform_float() { return float(next_u64() >> 40) * 0x1.0p-24f; }
  double uniform() { return double(next_u64() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [0, n).
  uint64_t below(uint64_t n) { return n ? next_u64() % n : 0; }

  // Standard normal by Box-Muller; draws two uniforms per call and keeps no spare, so
  // the state stays the four words above.
  double normal() {
    double u1 = uniform();
    double u2 = uniform();
    if (u1 < 1e-300) u1 = 1e-300;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }
  double normal(double mean, double stddev) { return mean + stddev * normal(); }

  const State& state() const { return s_; }
  void set_state(const State& s) { s_ = s; }

 private:
  static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  static uint64_t splitmix64(uint64_t& x) {
    uint64_t z = (x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  State s_{};
};

}  // namespace nns
