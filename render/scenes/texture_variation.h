#pragma once
// What the surround-v4 preset adds to surround-v3's per-scene materials: most surfaces
// of real buildings are textured (stone, brick, tiles, plaster with dirt, wood), with
// albedo edges that do not follow the geometry's. Each non-emissive material, with
// probability `share`, gets a procedural texture (render/material_texture.h) of a
// random kind, scale, orientation and contrast over the albedo it already has; the
// rest stay plain. Geometry, lights and cameras are untouched.
#include "core/rng.h"
#include "render/scene.h"

namespace nns::render {

struct TextureVariation {
  float share = 0.75f;  // materials that get a texture
  // Relative weights of the kinds: noise, bricks, tiles, wood, stains.
  float weight_noise = 0.25f, weight_bricks = 0.2f, weight_tiles = 0.2f, weight_wood = 0.15f, weight_stains = 0.2f;
  float contrast_min = 0.15f, contrast_max = 0.6f;  // uniform
  float dirt_share = 0.3f;                          // textured materials that also get dirt (0.2-0.7)
};

// Draws a texture for each non-emissive material of `s` from `rng` (docs/renderer.md,
// "Textured materials").
void vary_textures(Scene& s, Rng& rng, const TextureVariation& v = {});

// One texture of kind `k` with its kind's ranges of scale, aspect, joints (exposed for tests).
MaterialTexture draw_texture(TextureKind k, Rng& rng, const TextureVariation& v = {});

}  // namespace nns::render
