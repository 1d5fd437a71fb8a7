#include "render/scenes/texture_variation.h"

#include <cmath>

#include "render/sampling.h"

namespace nns::render {

namespace {
float log_uniform(Rng& rng, float lo, float hi) {
  return float(std::exp(rng.uniform(std::log(double(lo)), std::log(double(hi)))));
}

TextureKind draw_kind(Rng& rng, const TextureVariation& v) {
  const float w[5] = {v.weight_noise, v.weight_bricks, v.weight_tiles, v.weight_wood, v.weight_stains};
  const TextureKind kinds[5] = {TextureKind::noise, TextureKind::bricks, TextureKind::tiles, TextureKind::wood,
                                TextureKind::stains};
  float total = 0;
  for (float x : w) total += x;
  float u = float(rng.uniform()) * total;
  for (int i = 0; i < 5; ++i) {
    if (u < w[i]) return kinds[i];
    u -= w[i];
  }
  return kinds[4];
}
}  // namespace

MaterialTexture draw_texture(TextureKind k, Rng& rng, const TextureVariation& v) {
  MaterialTexture t;
  t.kind = k;
  t.seed = rng.next_u64();
  t.contrast = float(rng.uniform(v.contrast_min, v.contrast_max));
  t.angle = float(rng.uniform(0, kPi));
  // Mortar and grout: light lime to dark cement, slightly warm or cool.
  const float g = float(rng.uniform(0.25, 0.8)), tint = float(rng.uniform(-0.05, 0.05));
  t.joint_albedo = Vec3(g * (1 + tint), g, g * (1 - tint));
  switch (k) {
    case TextureKind::noise:  // stone, plaster, concrete: features from 2 cm to 0.5 m
    case TextureKind::stains:
      t.scale = log_uniform(rng, 0.02f, 0.5f);
      break;
    case TextureKind::bricks:  // bricks 0.2-0.45 m, courses a quarter to half that; 6-20 mm joints
      t.scale = float(rng.uniform(0.2, 0.45));
      t.aspect = float(rng.uniform(0.25, 0.5));
      t.joint = float(rng.uniform(0.006, 0.02));
      break;
    case TextureKind::tiles:  // 5 cm mosaic to 60 cm slabs; square, or rows half as high
      t.scale = log_uniform(rng, 0.05f, 0.6f);
      t.aspect = rng.below(3) == 0 ? 0.5f : 1.0f;
      t.joint = t.scale * float(rng.uniform(0.02, 0.06));
      t.checker = rng.below(4) == 0 ? float(rng.uniform(0.25, 0.55)) : 0.0f;
      t.angle = rng.below(3) == 0 ? kPi / 4 : 0.0f;  // floors laid square, or on the diagonal
      break;
    case TextureKind::wood:  // planks 8-30 cm, rings 3-20% of a plank apart
      t.scale = float(rng.uniform(0.08, 0.3));
      t.aspect = float(rng.uniform(0.03, 0.2));
      t.joint = float(rng.uniform(0.002, 0.006));
      break;
    case TextureKind::none:
      break;
  }
  t.dirt_scale = float(rng.uniform(0.6, 2.0));
  if (rng.uniform() < v.dirt_share) t.dirt = float(rng.uniform(0.2, 0.7));
  return t;
}

void vary_textures(Scene& s, Rng& rng, const TextureVariation& v) {
  for (Material& m : s.materials) {
    // Emissive materials (lamp panels) stand for lights and stay plain. A draw per
    // material either way, so one material's choice does not shift the others'.
    const bool textured = rng.uniform() < v.share;
    const TextureKind k = draw_kind(rng, v);
    Rng own = rng.fork(rng.next_u64());
    if (!textured || m.emission.x > 0 || m.emission.y > 0 || m.emission.z > 0) continue;
    m.texture = draw_texture(k, own, v);
  }
}

}  // namespace nns::render
