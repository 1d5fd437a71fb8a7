#pragma once
// The light of a frame whose generator ran on a box-filtered copy of it: the low
// prediction's indirect part (prediction - direct - env at the low size) brought up by
// the guided upsample (guided_upsample.h), added to the full-resolution direct + env,
// which the renderer gives at full resolution, so their shadow edges stay sharp:
//     light_full = direct_env_full + upsample(light_low - direct_env_low).
// eval-gi (--upsample-from) and gi-infer (faces larger than the model's) both call it, so
// what eval-gi scores is what gi-infer writes.
#include "models/gi/gi_inputs.h"
#include "models/gi/guided_upsample.h"

namespace nns::gi {

// low_light: (3, h, w) linear light predicted for `low`; `full`: the same frame at k times
// the size (direct_env and front_geometry are read). Returns (3, H, W).
inline Tensor<float> upsampled_light(Tensor<float> low_light, const GiSample& low, const GiSample& full) {
  for (int64_t i = 0; i < low_light.numel(); ++i) low_light[i] -= low.direct_env[i];
  Tensor<float> light = guided_upsample(low_light, low.front_geometry, full.front_geometry);
  for (int64_t i = 0; i < light.numel(); ++i) light[i] += full.direct_env[i];
  return light;
}

}  // namespace nns::gi
