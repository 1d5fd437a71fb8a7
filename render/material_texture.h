#pragma once
// Procedural albedo textures: what makes a stone wall, a brick facade, a tiled floor or a
// wooden board look like one, evaluated at a world-space hit point. No UVs: the 3D kinds
// (noise, wood, stains) are solid textures, the 2D ones (bricks, tiles) are projected
// along the axes of the surface normal and blended where it is oblique (triplanar).
// The pattern multiplies or blends into the material's base albedo, so the scene
// variation's colours stay the surface's colour (dirt, stains, latewood and mortar
// darken: a surround-v4 frame's mean albedo is ~4% below surround-v3's); the result is
// clamped to [0, kMaxTexturedAlbedo]. Deterministic: a pure function of (texture,
// base, p, n).
//
// The G-buffer's albedo and every bounce of the integrator read the albedo through
// surface_albedo() (render/scene.h), so the ground truth and the G-buffer agree.
#include <cstdint>

#include "core/vec3.h"

namespace nns::render {

enum class TextureKind : uint32_t {
  none,    // the base albedo everywhere (every preset before surround-v4)
  noise,   // mottled stone or plaster: fbm at two scales, a hue drift
  bricks,  // courses of bricks in running bond with mortar joints (floors: pavers)
  tiles,   // a grid of tiles with grout, per-tile tone, sometimes a checkerboard
  wood,    // planks with growth rings around a grain axis and dark joints
  stains,  // plaster with dirt patches and vertical streaks
};
const char* texture_kind_name(TextureKind k);

// Laid out without padding (static_assert below): scenes are compared byte for byte.
struct MaterialTexture {
  uint64_t seed = 0;  // the pattern's own hash stream (cells, noise)
  TextureKind kind = TextureKind::none;
  float scale = 1;                        // metres: noise feature, brick length, tile side, plank width
  float contrast = 0.3f;                  // 0..1: how far the pattern moves the albedo away from the base
  float angle = 0;                        // radians: the pattern's turn in the horizontal plane (floors) / grain axis
  float aspect = 0.5f;                    // bricks: course height / brick length; tiles: row height / tile side;
                                          // wood: ring spacing / plank width
  float joint = 0.01f;                    // metres: mortar / grout / plank-joint width
  Vec3 joint_albedo{0.55f, 0.53f, 0.5f};  // mortar / grout colour (absolute, not a multiplier)
  float dirt = 0;                         // 0..1: dirt patches and streaks over any kind
  float dirt_scale = 1;                   // metres: the size of the dirt patches
  float checker = 0;                      // tiles: every other tile times (1 - checker)
};
static_assert(sizeof(MaterialTexture) == 56, "MaterialTexture must have no padding bytes");

// The brightest albedo a texture may produce: below 1, as energy conservation needs,
// and at the top of real materials (fresh white paint ~0.9).
inline constexpr float kMaxTexturedAlbedo = 0.95f;

// The textured albedo at world point p with unit normal n (either side: the result
// does not depend on the normal's sign, so every ray that reaches p agrees).
Vec3 textured_albedo(const MaterialTexture& t, Vec3 base, Vec3 p, Vec3 n);

}  // namespace nns::render
