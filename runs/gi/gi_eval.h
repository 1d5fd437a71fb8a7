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
#include <filesystem>
#include <string>
#include <vector>

#include "core/tensor.h"
#include "report/image_metrics.h"
#include "classical_ao/temporal.h"
#include "models/gi/gi_inputs.h"
#include "models/gi/hdr_mapping.h"
#include "screen_space/gbuffer.h"

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

// Temporal stability on camera paths, measured as eval-ao measures it
// (classical_ao/temporal.h): each front pixel of frame t reprojected onto frame t-1 with
// the views' worldToCamera and depth (disocclusions skipped), and over the mapped pixels
// of the three channels, in mapped space (Reinhard x/(x+k)):
//   flicker        mean |m_t(i) - m_t-1(j)|   (the ground truth's own for g)
//   temporal error mean |(m_t(i) - m_t-1(j)) - (g_t(i) - g_t-1(j))|
// Without reprojection a moving camera's true change would count as flicker.

// Whether `cur` is the frame after `prev` on one camera path ("<scene>-pNN-fNNN").
inline bool next_on_path(const GiSample& prev, const GiSample& cur) {
  namespace fs = std::filesystem;
  int fp = -1, fc = -1;
  const std::string pp = ao::path_of_frame(fs::path(prev.name).stem().string(), fp);
  const std::string pc = ao::path_of_frame(fs::path(cur.name).stem().string(), fc);
  return !pc.empty() && pc == pp && fc == fp + 1 && prev.scene == cur.scene;
}

inline std::vector<int64_t> reproject_front(const GiSample& cur, const GiSample& prev) {
  // The AO radius is unused by reprojection; 1 stands in for the attribute GI views lack.
  const ao::GBuffer c = ao::gbuffer_from_view(cur.front_geometry, 1.0f);
  const ao::GBuffer p = ao::gbuffer_from_view(prev.front_geometry, 1.0f);
  return ao::reproject_to_previous(c, cur.front_geometry.world_to_camera, p, prev.front_geometry.world_to_camera);
}

// A (3, h, w) linear-light frame in mapped space.
inline std::vector<float> mapped(const Tensor<float>& t, const HdrMapping& hdr) {
  std::vector<float> out(size_t(t.numel()));
  for (int64_t i = 0; i < t.numel(); ++i) out[size_t(i)] = hdr.to_unit(t[i]);
  return out;
}

// Adds one frame pair of a method (m) against the ground truth (g), every channel.
inline void add_flicker_pair(ao::TemporalStats& st, const std::vector<int64_t>& map, const std::vector<float>& m,
                             const std::vector<float>& m_prev, const std::vector<float>& g,
                             const std::vector<float>& g_prev) {
  const size_t n = map.size();
  for (size_t c = 0; c < 3; ++c)
    st.add_pair(map, m.data() + c * n, m_prev.data() + c * n, g.data() + c * n, g_prev.data() + c * n);
}

}  // namespace nns::gi
