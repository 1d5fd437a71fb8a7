#pragma once
// Invertible mapping of linear HDR light into Tanh's range (-1, 1).
//
// The generator ends in Tanh, the light it predicts is unbounded HDR irradiance. We use
// Reinhard's operator per channel with a scale k (the "white" of the data set):
//
//   unit(x)  = x / (x + k)          in [0, 1)   for x >= 0
//   tanh(x)  = 2 * unit(x) - 1      in [-1, 1)
//   inverse  x = k * u / (1 - u),   u = (y + 1) / 2
//
// Why Reinhard and not a clamp or a log: it is exactly invertible on [0, inf), it never
// saturates (a sun-lit wall 50x brighter than the shadow still maps below 1), and x = k
// lands at 0, the middle of Tanh's range, where its gradient is largest. k is chosen per
// data set (the median of the training target over geometry pixels, see gi_inputs.h), so
// typical light sits mid-range whatever the scene's units. Negative light (never
// physical, possible from MC noise) is clamped to 0. The inverse clamps u below 1 so a
// saturated network output maps to a large but finite value.
//
// The thesis stores its light as 8-bit PNGs (an implicit clamp at 1); the "mapped space"
// metrics of eval-gi are computed on unit(x) in [0, 1], the linear ones on x itself.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace nns::gi {

struct HdrMapping {
  float scale = 1.0f;  // k: the linear value that maps to unit 0.5 / tanh 0

  explicit HdrMapping(float k = 1.0f) : scale(k) {
    if (!(k > 0) || !std::isfinite(k))
      throw std::invalid_argument("HdrMapping: scale must be positive and finite, got " + std::to_string(k));
  }

  float to_unit(float x) const {
    x = x > 0 ? x : 0.0f;  // negative light is MC noise; NaN is rejected earlier (gi_inputs.h)
    return x / (x + scale);
  }
  float from_unit(float u) const {
    u = std::clamp(u, 0.0f, kMaxUnit);
    return scale * u / (1.0f - u);
  }
  float to_tanh(float x) const { return 2.0f * to_unit(x) - 1.0f; }
  float from_tanh(float y) const { return from_unit(0.5f * (y + 1.0f)); }

  // The largest unit value the inverse accepts: 1 - 2^-20 maps to about 1e6 * k.
  static constexpr float kMaxUnit = 1.0f - 0x1.0p-20f;
};

}  // namespace nns::gi
