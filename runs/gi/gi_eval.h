#pragma once
// Scoring predicted light against the ray-traced target, as the thesis's Table 5.3 does
// (MSE, PSNR, SSIM), in two spaces:
//  * mapped: Reinhard unit(x) = x / (x + k) in [0, 1] (hdr_mapping.h), the space the
//    network is trained in and the analogue of the thesis's 8-bit light maps;
//    PSNR with peak 1, SSIM with its constants for range 1. This is the primary table.
//  * linear: the HDR values themselves. PSNR and SSIM need a range: we use the frame's
//    peak target value over the geometry pixels (documented in docs/gan.md), MSE is raw.
// Per colour channel, then averaged; only pixels with geometry count (sky has no light
// to predict).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/tensor.h"
#include "report/image_metrics.h"
#include "models/gi/hdr_mapping.h"

namespace nns::gi {

struct LightMetrics {
  double mse = 0, psnr = 0, ssim = 0;                      // mapped space
  double mse_linear = 0, psnr_linear = 0, ssim_linear = 0;  // linear HDR
};

// pred, target: linear light (3, h, w). geometry: h * w mask (1 = geometry).
inline LightMetrics light_metrics(const Tensor<float>& pred, const Tensor<float>& target,
                                  const std::vector<uint8_t>& geometry, const HdrMapping& hdr) {
  const int h = int(target.size(1)), w = int(target.size(2));
  const int64_t n = int64_t(h) * w;
  const uint8_t* mask = geometry.data();
  float peak = 1e-12f;
  for (int64_t i = 0; i < 3 * n; ++i)
    if (mask[i % n]) peak = std::max(peak, target[i]);
  LightMetrics m;
  const size_t un = static_cast<size_t>(n);
  std::vector<float> pu(un), tu(un), pl(un), tl(un);
  for (int c = 0; c < 3; ++c) {
    for (int64_t i = 0; i < n; ++i) {
      float p = pred[c * n + i], t = target[c * n + i];
      pu[size_t(i)] = hdr.to_unit(p), tu[size_t(i)] = hdr.to_unit(t);
      pl[size_t(i)] = p / peak, tl[size_t(i)] = t / peak;
    }
    m.mse += data::masked_mse(pu.data(), tu.data(), mask, n) / 3;
    m.ssim += data::masked_ssim(pu.data(), tu.data(), mask, w, h) / 3;
    m.mse_linear += data::masked_mse(pl.data(), tl.data(), mask, n) * double(peak) * peak / 3;
    m.ssim_linear += data::masked_ssim(pl.data(), tl.data(), mask, w, h) / 3;
  }
  m.psnr = data::psnr_from_mse(m.mse);
  m.psnr_linear = data::psnr_from_mse(m.mse_linear, peak);
  return m;
}

// Running means of metrics over frames (NaN frames, e.g. all sky, are skipped).
struct MetricsMean {
  LightMetrics sum;
  int64_t frames = 0;
  void add(const LightMetrics& m) {
    if (!std::isfinite(m.mse) || !std::isfinite(m.ssim)) return;
    sum.mse += m.mse, sum.psnr += m.psnr, sum.ssim += m.ssim;
    sum.mse_linear += m.mse_linear, sum.psnr_linear += m.psnr_linear, sum.ssim_linear += m.ssim_linear;
    ++frames;
  }
  LightMetrics mean() const {
    LightMetrics m = sum;
    double k = frames ? 1.0 / double(frames) : NAN;
    m.mse *= k, m.psnr *= k, m.ssim *= k, m.mse_linear *= k, m.psnr_linear *= k, m.ssim_linear *= k;
    return m;
  }
};

// Temporal flicker along a camera path: the mean absolute difference between the
// predicted and the true frame-to-frame change, in mapped space, over geometry present
// in both frames. 0 when the prediction changes exactly as the ground truth does.
inline double temporal_flicker(const Tensor<float>& pred_prev, const Tensor<float>& pred,
                               const Tensor<float>& gt_prev, const Tensor<float>& gt,
                               const std::vector<uint8_t>& geo_prev,
                               const std::vector<uint8_t>& geo, const HdrMapping& hdr) {
  const int64_t n = int64_t(geo.size());
  double s = 0;
  int64_t count = 0;
  for (int c = 0; c < 3; ++c)
    for (int64_t i = 0; i < n; ++i) {
      if (!geo[size_t(i)] || !geo_prev[size_t(i)]) continue;
      int64_t k = c * n + i;
      double dp = hdr.to_unit(pred[k]) - hdr.to_unit(pred_prev[k]);
      double dg = hdr.to_unit(gt[k]) - hdr.to_unit(gt_prev[k]);
      s += std::abs(dp - dg);
      ++count;
    }
  return count ? s / double(count) : NAN;
}

}  // namespace nns::gi
