#pragma once
// Direction sampling for the integrators.
//
// Hemisphere directions are cosine-weighted (pdf cos(theta)/pi), which makes both AO
// (the spec defines it cosine-weighted) and irradiance/pi estimates a plain average of
// the sample values. Sample sets are a Hammersley point set shifted per pixel by a
// random offset (Cranley-Patterson rotation): stratified for any count, unbiased, and
// decorrelated between neighbouring pixels.
#include <cmath>
#include <cstdint>

#include "core/vec3.h"

namespace nns::render {

inline constexpr float kPi = 3.14159265358979323846f;

// An orthonormal basis (t, b, n) around a unit normal (Duff et al. 2017, branchless).
struct Frame {
  Vec3 t, b, n;
  explicit Frame(Vec3 normal) : n(normal) {
    float s = std::copysign(1.0f, n.z);
    float a = -1.0f / (s + n.z);
    float c = n.x * n.y * a;
    t = Vec3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
    b = Vec3(c, s + n.y * n.y * a, -n.y);
  }
  Vec3 to_world(Vec3 l) const { return t * l.x + b * l.y + n * l.z; }
};

inline float radical_inverse2(uint32_t i) {
  i = (i << 16) | (i >> 16);
  i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
  i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
  i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
  i = ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
  return float(i) * 0x1.0p-32f;
}

// Sample i of n of the Hammersley set, shifted by (s1, s2) modulo 1.
inline void hammersley(uint32_t i, uint32_t n, float s1, float s2, float& u1, float& u2) {
  u1 = (float(i) + 0.5f) / float(n) + s1;
  u2 = radical_inverse2(i) + s2;
  u1 -= std::floor(u1);
  u2 -= std::floor(u2);
}

// Cosine-weighted direction in local coordinates (z = normal), Malley's method.
inline Vec3 cosine_hemisphere(float u1, float u2) {
  float r = std::sqrt(u1);
  float phi = 2 * kPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1 - u1))};
}

// Uniform direction inside a cone of half-angle acos(cos_max) around local z.
inline Vec3 uniform_cone(float u1, float u2, float cos_max) {
  float c = 1 - u1 * (1 - cos_max);
  float s = std::sqrt(std::max(0.0f, 1 - c * c));
  float phi = 2 * kPi * u2;
  return {s * std::cos(phi), s * std::sin(phi), c};
}

}  // namespace nns::render
