#include "render/noise.h"

#include <cmath>

namespace nns::data {

float value_noise(uint64_t seed, float x, float y, float z) {
  auto lattice = [seed](int64_t i, int64_t j, int64_t k) {
    uint64_t h = seed ^ (uint64_t(i) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(j) * 0xC2B2AE3D27D4EB4Full) ^
                 (uint64_t(k) * 0x165667B19E3779F9ull);
    h ^= h >> 31, h *= 0xBF58476D1CE4E5B9ull, h ^= h >> 29;  // splitmix finaliser
    return float(h >> 40) * 0x1.0p-23f - 1.0f;             // in [-1, 1)
  };
  float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  int64_t ix = int64_t(fx), iy = int64_t(fy), iz = int64_t(fz);
  auto smoothstep = [](float t) { return t * t * (3 - 2 * t); };
  float u = smoothstep(x - fx), v = smoothstep(y - fy), w = smoothstep(z - fz);
  auto lerpf = [](float a, float b, float t) { return a + (b - a) * t; };
  float x00 = lerpf(lattice(ix, iy, iz), lattice(ix + 1, iy, iz), u);
  float x10 = lerpf(lattice(ix, iy + 1, iz), lattice(ix + 1, iy + 1, iz), u);
  float x01 = lerpf(lattice(ix, iy, iz + 1), lattice(ix + 1, iy, iz + 1), u);
  float x11 = lerpf(lattice(ix, iy + 1, iz + 1), lattice(ix + 1, iy + 1, iz + 1), u);
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

}  // namespace nns::data
