#include "render/material_texture.h"

#include <algorithm>
#include <cmath>

#include "render/noise.h"

namespace nns::render {

const char* texture_kind_name(TextureKind k) {
  switch (k) {
    case TextureKind::none:
      return "none";
    case TextureKind::noise:
      return "noise";
    case TextureKind::bricks:
      return "bricks";
    case TextureKind::tiles:
      return "tiles";
    case TextureKind::wood:
      return "wood";
    case TextureKind::stains:
      return "stains";
  }
  return "?";
}

namespace {

float smoothstep(float a, float b, float x) {
  float t = std::clamp((x - a) / (b - a), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}

// What a pattern gives at one point: a multiplier on the base albedo and how much of
// the point the joint colour (mortar, grout) covers.
struct Texel {
  Vec3 mul{1, 1, 1};
  float joint = 0;
};

// Joint coverage at distance d from the nearest cell edge: the joint is `width` wide,
// centred on the edge, with an edge softened over 30% of it (no hard aliasing step).
float joint_cover(float d, float width) { return 1 - smoothstep(0.35f * width, 0.65f * width, d); }

// Per-cell salt so the hash streams of a texture's parts differ.
constexpr uint64_t kToneSalt = 0x7A3D1F29C4E5B681ull, kHueSalt = 0x3C6EF372FE94F82Bull;
constexpr uint64_t kGrainSalt = 0xA54FF53A5F1D36F1ull, kDirtSalt = 0x510E527FADE682D1ull;

// Bricks in running bond in the plane (u along the course, v up the wall): every other
// course shifted half a brick; a tone and a slight red-brown hue per brick, a fine
// grain (2 cm value noise) across its face.
Texel bricks(const MaterialTexture& t, float u, float v, int axis) {
  const float L = t.scale, H = t.scale * t.aspect;
  const float row = std::floor(v / H);
  const int64_t r = int64_t(row);
  const float us = u + ((r & 1) ? 0.5f * L : 0.0f);
  const float col = std::floor(us / L);
  const float fu = us - col * L, fv = v - row * H;
  Texel x;
  x.joint = joint_cover(std::min({fu, L - fu, fv, H - fv}), t.joint);
  const int64_t c = int64_t(col);
  const float tone = 1 + t.contrast * (2 * hash_unit(t.seed ^ kToneSalt, r, c, axis) - 1);
  const float hue = t.contrast * 0.5f * (2 * hash_unit(t.seed ^ kHueSalt, r, c, axis) - 1);
  const float grain = 1 + 0.3f * t.contrast * fbm(t.seed ^ kGrainSalt, Vec3(u, v, float(axis) * 7.31f) * 50.0f, 2);
  x.mul = Vec3(1 + hue, 1, 1 - hue) * (tone * grain);
  return x;
}

// A grid of tiles (side `scale`, rows `scale * aspect`) with grout; each tile its own
// faint tone, every other tile times (1 - checker), and a faint 5 cm cloud over the
// glaze (wear: no real tile is one flat colour).
Texel tiles(const MaterialTexture& t, float u, float v, int axis) {
  const float A = t.scale, B = t.scale * t.aspect;
  const float i = std::floor(u / A), j = std::floor(v / B);
  const float fu = u - i * A, fv = v - j * B;
  Texel x;
  x.joint = joint_cover(std::min({fu, A - fu, fv, B - fv}), t.joint);
  const int64_t a = int64_t(i), b = int64_t(j);
  float tone = 1 + 0.4f * t.contrast * (2 * hash_unit(t.seed ^ kToneSalt, a, b, axis) - 1);
  if ((a + b) & 1) tone *= 1 - t.checker;
  tone *= 1 + 0.15f * t.contrast * value_noise(t.seed ^ kGrainSalt, u * 20, v * 20, float(axis) * 7.31f);
  x.mul = Vec3(tone);
  return x;
}

// Triplanar: the 2D pattern in the plane of each axis the normal leans on, weighted by
// (|n_k| - 0.5)^2. Every unit vector has a component of at least 1/sqrt(3) > 0.5, so
// the weights never all vanish; a wall or floor aligned with an axis evaluates one
// plane. Floors turn the pattern by t.angle; walls keep their courses level.
template <class Pattern>
Texel triplanar(const MaterialTexture& t, Vec3 p, Vec3 n, Pattern pattern) {
  float w[3];
  float sum = 0;
  for (int k = 0; k < 3; ++k) {
    float e = std::max(std::fabs(n[k]) - 0.5f, 0.0f);
    sum += w[k] = e * e;
  }
  Texel acc;
  if (!(sum > 0)) return acc;  // a zero normal: no texture rather than a NaN
  acc.mul = Vec3(0);
  float ca = 1, sa = 0;  // only a floor's plane turns: walls need no sine (the same bits either way)
  if (w[1] > 0) ca = std::cos(t.angle), sa = std::sin(t.angle);
  for (int k = 0; k < 3; ++k) {
    if (w[k] <= 0) continue;
    float u, v;
    if (k == 1) u = ca * p.x + sa * p.z, v = -sa * p.x + ca * p.z;
    else if (k == 0) u = p.z, v = p.y;
    else u = p.x, v = p.y;
    Texel x = pattern(t, u, v, k);
    float f = w[k] / sum;
    acc.mul += x.mul * f;
    acc.joint += x.joint * f;
  }
  return acc;
}

// Mottled stone or plaster: fine fbm (the texture's scale, 3 octaves) over blotches four
// times larger, and a hue that drifts with the blotches along a per-texture direction.
// Octaves are the cost: a texture is evaluated at every path vertex (4 + 2 octaves here
// and 3 + 2 in the dirt took 18% more CPU per corridor/courtyard/multiroom frame than no
// textures; 3 + 1 and 2 + 1, 14%).
Vec3 mottled(const MaterialTexture& t, Vec3 p, float strength) {
  const Vec3 q = p / t.scale;
  const float f = fbm(t.seed, q, 3), g = value_noise(t.seed ^ kHueSalt, q.x * 0.25f, q.y * 0.25f, q.z * 0.25f);
  const float m = 1 + strength * (1.6f * f + 0.8f * g);
  const Vec3 drift(hash_unit(t.seed, 1, 0) - 0.5f, hash_unit(t.seed, 2, 0) - 0.5f, hash_unit(t.seed, 3, 0) - 0.5f);
  return (Vec3(1) + drift * (strength * 1.2f * g)) * m;
}

// Wooden boards along the grain axis (angle in the horizontal plane): planks `scale`
// wide, boards 6-10 planks long with staggered ends, dark joints between them; growth
// rings around a per-board log axis below the surface, wobbling along the grain.
Vec3 wood(const MaterialTexture& t, Vec3 p) {
  const Vec3 a(std::cos(t.angle), 0, std::sin(t.angle)), b(-a.z, 0, a.x);
  const float W = t.scale, along = dot(p, a), across = dot(p, b);
  const float k = std::floor(across / W);
  const int64_t plank = int64_t(k);
  const float Lb = W * (6 + 4 * hash_unit(t.seed, plank, 0, 11));
  const float s = along + Lb * hash_unit(t.seed, plank, 0, 12);
  const float board = std::floor(s / Lb);
  const int64_t id = int64_t(board);
  const float fb = across - k * W, fs = s - board * Lb;
  const float joint = joint_cover(std::min({fb, W - fb, fs, Lb - fs}), t.joint);
  // The log's axis runs along the grain through (cb, cy) in the (across, up) plane.
  const float cb = (k + hash_unit(t.seed ^ kToneSalt, plank, id, 1)) * W;
  const float cy = -W * (0.5f + 2 * hash_unit(t.seed ^ kToneSalt, plank, id, 2));
  const float spacing = W * t.aspect;
  const float wobble = fbm(t.seed ^ kGrainSalt, Vec3(along * 0.5f, across * 4, p.y * 4) / W, 2);
  const float r = std::sqrt((across - cb) * (across - cb) + (p.y - cy) * (p.y - cy)) + 0.6f * spacing * wobble;
  const float ring = r / spacing - std::floor(r / spacing);
  const float late = smoothstep(0.55f, 0.85f, ring) * (1 - smoothstep(0.9f, 1.0f, ring));  // the dark latewood band
  const float tone =
      (1 + 0.5f * t.contrast * (2 * hash_unit(t.seed ^ kHueSalt, plank, id) - 1)) * (1 - 0.6f * t.contrast * late);
  // Latewood is redder and darker; a joint is a dark gap.
  return Vec3(1, 1 - 0.1f * late, 1 - 0.2f * late) * (tone * (1 - 0.65f * joint));
}

// Dirt: patches of low-frequency fbm (t.dirt_scale) and vertical streaks (noise
// stretched 12x along y), darkening towards a brown-grey; `amount` 0..1.
Vec3 dirt(const MaterialTexture& t, Vec3 p, float amount) {
  const float size = t.dirt_scale;
  const float patches = smoothstep(0.05f, 0.35f, fbm(t.seed ^ kDirtSalt, p / size, 2));
  const Vec3 q = Vec3(p.x * 3, p.y * 0.25f, p.z * 3) / size;
  const float streaks = smoothstep(0.1f, 0.4f, value_noise((t.seed ^ kDirtSalt) + 1, q.x, q.y, q.z));
  const float d = amount * std::max(patches, 0.7f * streaks);
  return lerp(Vec3(1), Vec3(0.45f, 0.4f, 0.33f), d);
}

}  // namespace

Vec3 textured_albedo(const MaterialTexture& t, Vec3 base, Vec3 p, Vec3 n) {
  Vec3 a = base;
  float dirt_amount = t.dirt;
  switch (t.kind) {
    case TextureKind::none:
      return base;
    case TextureKind::noise:
      a = base * mottled(t, p, t.contrast);
      break;
    case TextureKind::bricks:
    case TextureKind::tiles: {
      Texel x = t.kind == TextureKind::bricks ? triplanar(t, p, n, bricks) : triplanar(t, p, n, tiles);
      a = lerp(base * x.mul, t.joint_albedo, x.joint);
      break;
    }
    case TextureKind::wood:
      a = base * wood(t, p);
      break;
    case TextureKind::stains:
      a = base * mottled(t, p, 0.4f * t.contrast);
      dirt_amount = std::max(dirt_amount, 0.4f + 0.6f * t.contrast);
      break;
  }
  if (dirt_amount > 0) a = a * dirt(t, p, dirt_amount);
  return vmin(vmax(a, Vec3(0)), Vec3(kMaxTexturedAlbedo));
}

}  // namespace nns::render
