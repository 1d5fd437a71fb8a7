#pragma once
// The screen-space kit every classical method is written with (screen_space/ao_common.h:
// the G-buffer, the loop over surface pixels, the 4x4 noise and the blur that removes
// it, the pixel hashes, the SSAO kernel), named once in nns::classical_ao so that the
// methods read as the papers write them.
#include "screen_space/ao_common.h"

namespace nns::classical_ao {

using screen_space::box_blur_4x4;
using screen_space::box_blur_4x4_reference;
using screen_space::for_each_surface_pixel;
using screen_space::GBuffer;
using screen_space::hash_unit;
using screen_space::noise_angle_4x4;
using screen_space::NoiseTile;
using screen_space::normalize_or_facing;
using screen_space::pixel_hash;
using screen_space::saturate;
using screen_space::sphere_kernel;

}  // namespace nns::classical_ao
