#pragma once
// What a GI dataset varies per scene beyond its geometry (the surround-v2 preset): a
// model that saw every family lit one way and painted one way learns those as
// constants. Every scene gets new albedos (greys and saturated colours, so walls bleed
// colour), its lights a new colour temperature and exposure, its sun a new direction
// and size, and often extra point lamps placed where cameras stand, so many of them
// light the frame from outside the view. Geometry and camera regions are untouched.
#include "core/rng.h"
#include "render/scene.h"

namespace nns::render {

struct LightingVariation {
  // Albedo: grey-ish in [grey_min, grey_max] (real walls, floors, stone: 0.05-0.85),
  // or with probability `colour_share` a saturated colour (HSV, value in the same range).
  float grey_min = 0.05f, grey_max = 0.85f;
  float colour_share = 0.4f;
  float saturation_min = 0.3f, saturation_max = 0.85f;
  // Every light and the sky times one exposure, log-uniform in [exposure_min, exposure_max].
  float exposure_min = 0.6f, exposure_max = 1.7f;
  // Sun elevation (degrees) and angular radius (radians: the real sun's 0.0093 to a hazy 0.04).
  float sun_elevation_min = 8, sun_elevation_max = 75;
  float sun_radius_min = 0.0093f, sun_radius_max = 0.04f;
  // Extra point lamps: with probability `lamp_share`, 1..lamps_max of them in the camera
  // region (grown by `lamp_region_grow` metres, kept inside the scene's bounds), intensity
  // (as colour = I/pi) log-uniform in [lamp_min, lamp_max]: 1 to 6 is 0.25 to 1.5 at 2 m.
  // No growth: the camera region keeps clear of walls, and a lamp grown into a wall's
  // last 10 cm lit it 60x brighter than the sun (direct up to 188 in a first render).
  float lamp_share = 0.6f;
  int lamps_max = 2;
  float lamp_region_grow = 0.0f;
  float lamp_min = 1.0f, lamp_max = 6.0f;
};

// Redraws materials and lights of `s` from `rng` (docs/renderer.md, "surround-v2").
void vary_materials_and_lights(Scene& s, Rng& rng, const LightingVariation& v = {});

}  // namespace nns::render
