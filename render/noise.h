#pragma once
// Smooth lattice noise, shared by the mesh displacement of the scene families
// (rocks, terrain, cushions) and the procedural material textures
// (render/material_texture.h). Pure functions of (seed, position): no global state.
#include <cstdint>

#include "core/vec3.h"

namespace nns::render {

// Value noise on an integer lattice with a hash of (seed, cell), trilinear with
// smoothstep weights, in [-1, 1); fbm sums `octaves` of it, each `lacunarity` times
// finer and `gain` times weaker, normalised by the sum of the weights.
float value_noise(uint64_t seed, float x, float y, float z);
float fbm(uint64_t seed, Vec3 p, int octaves, float lacunarity = 2.0f, float gain = 0.5f);

// A uniform number in [0, 1) from (seed, a, b, c): one cell of a pattern (a brick,
// a tile, a plank) draws its own colour from it.
inline float hash_unit(uint64_t seed, int64_t a, int64_t b, int64_t c = 0) {
  uint64_t h = seed ^ (uint64_t(a) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(b) * 0xC2B2AE3D27D4EB4Full) ^
               (uint64_t(c) * 0x165667B19E3779F9ull);
  h ^= h >> 31, h *= 0xBF58476D1CE4E5B9ull, h ^= h >> 29, h *= 0x94D049BB133111EBull, h ^= h >> 32;
  return float(h >> 40) * 0x1.0p-24f;
}

}  // namespace nns::render
