#include "render/noise.h"

#include <cmath>

namespace nns::render {

float value_noise(uint64_t seed, float x, float y, float z) {
  // The hash of cell (i, j, k) is seed ^ i*A ^ j*B ^ k*C: the six products of the
  // cube's corners are formed once, not eight times each (a textured frame spends ~8%
  // of its CPU time here; the numbers are the same bits).
  float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  int64_t ix = int64_t(fx), iy = int64_t(fy), iz = int64_t(fz);
  const uint64_t a0 = uint64_t(ix) * 0x9E3779B97F4A7C15ull, a1 = uint64_t(ix + 1) * 0x9E3779B97F4A7C15ull;
  const uint64_t b0 = uint64_t(iy) * 0xC2B2AE3D27D4EB4Full, b1 = uint64_t(iy + 1) * 0xC2B2AE3D27D4EB4Full;
  const uint64_t c0 = uint64_t(iz) * 0x165667B19E3779F9ull, c1 = uint64_t(iz + 1) * 0x165667B19E3779F9ull;
  auto lattice = [seed](uint64_t a, uint64_t b, uint64_t c) {
    uint64_t h = seed ^ a ^ b ^ c;
    h ^= h >> 31, h *= 0xBF58476D1CE4E5B9ull, h ^= h >> 29;  // splitmix finaliser
    return float(h >> 40) * 0x1.0p-23f - 1.0f;               // in [-1, 1)
  };
  auto smoothstep = [](float t) { return t * t * (3 - 2 * t); };
  float u = smoothstep(x - fx), v = smoothstep(y - fy), w = smoothstep(z - fz);
  auto lerpf = [](float a, float b, float t) { return a + (b - a) * t; };
  float x00 = lerpf(lattice(a0, b0, c0), lattice(a1, b0, c0), u);
  float x10 = lerpf(lattice(a0, b1, c0), lattice(a1, b1, c0), u);
  float x01 = lerpf(lattice(a0, b0, c1), lattice(a1, b0, c1), u);
  float x11 = lerpf(lattice(a0, b1, c1), lattice(a1, b1, c1), u);
  return lerpf(lerpf(x00, x10, v), lerpf(x01, x11, v), w);
}

float fbm(uint64_t seed, Vec3 p, int octaves, float lacunarity, float gain) {
  float sum = 0, amp = 1, norm = 0;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * value_noise(seed + uint64_t(o) * 0x632BE59BD9B4E019ull, p.x, p.y, p.z);
    norm += amp;
    amp *= gain;
    p = p * lacunarity;
  }
  return sum / norm;
}

}  // namespace nns::render
