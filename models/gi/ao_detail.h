#pragma once
// Contact detail for GI brought up from a lower resolution. A network run at face 64 and
// upsampled to 128 (upsampled_light.h) cannot hold occlusion finer than its own pixel:
// the darkening in a crease, under a ledge, where a column meets the floor. Engines
// multiply their half-resolution GI by full-resolution AO for the same reason. Here the
// network already predicts the occlusion a low pixel resolves, so only the finer part of
// the AO is multiplied in: its ratio to the AO box-filtered to the low size and brought
// back up by the same guided upsample,
//     indirect_full = upsample(indirect_low) * clamp(ao_full / upsample(box(ao_full)), 0, max_gain)^power,
// which is 1 wherever the AO is as smooth as a low pixel. The AO is the project's NNAO
// (models/nnao) on the full-resolution depth and normals.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/tensor.h"
#include "data/view.h"
#include "models/gi/guided_upsample.h"
#include "models/nnao/nnao_inference.h"
#include "screen_space/gbuffer.h"

namespace nns::gi {

struct AoDetail {
  const nnao::NnaoWeights* model = nullptr;  // null: no AO detail
  float power = 1;                           // exponent of the ratio (0: off)
  float max_gain = 2;                        // the ratio's cap: AO above its local mean brightens, boundedly
  float radius = 0;                          // AO radius in world units; 0: the model's, else the view's aoRadius
};

// The factor each full pixel's indirect light is multiplied by, H * W values;
// low_geo is full_geo box-filtered by an integer factor (gi_samples.h).
inline std::vector<float> ao_detail_factor(const AoDetail& d, const data::View& low_geo, const data::View& full_geo) {
  const int W = full_geo.width, H = full_geo.height, w = low_geo.width, h = low_geo.height;
  if (w <= 0 || h <= 0 || W % w || H % h || W / w != H / h)
    throw std::runtime_error("ao_detail_factor: " + std::to_string(w) + "x" + std::to_string(h) + " does not go into " +
                             std::to_string(W) + "x" + std::to_string(H) + " by one integer factor");
  const int k = W / w;
  const float radius = d.radius > 0 ? d.radius : d.model->radius;
  const screen_space::GBuffer g = screen_space::gbuffer_from_view(full_geo, radius);
  std::vector<float> ao(size_t(W) * size_t(H));
  nnao::infer_exact(*d.model, g, ao.data());
  Tensor<float> low({1, h, w});
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int dy = 0; dy < k; ++dy)
        for (int dx = 0; dx < k; ++dx) s += ao[size_t(y * k + dy) * size_t(W) + size_t(x * k + dx)];
      low[int64_t(y) * w + x] = float(s / double(k * k));
    }
  const Tensor<float> smooth = guided_upsample(low, low_geo, full_geo);
  std::vector<float> f(ao.size());
  for (size_t i = 0; i < f.size(); ++i) {
    // An AO of 0 over a smooth 0 (a fully closed pixel) carries no detail: ratio 1.
    const float r = smooth[int64_t(i)] > 1e-4f ? ao[i] / smooth[int64_t(i)] : 1.0f;
    f[i] = std::pow(std::clamp(r, 0.0f, d.max_gain), d.power);
  }
  return f;
}

}  // namespace nns::gi
