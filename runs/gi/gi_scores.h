#pragma once
// Scoring predicted light against the ray-traced target, as the thesis's Table 5.3 does
// (MSE, PSNR, SSIM), in two spaces:
//  * mapped: Reinhard unit(x) = x / (x + k) in [0, 1] (hdr_mapping.h), the space the
//    network is trained in and the analogue of the thesis's 8-bit light maps;
//    PSNR with peak 1, SSIM with its constants for range 1. This is the primary table.
//  * linear: the HDR values themselves. PSNR and SSIM need a range: we use the frame's
//    peak target value over the geometry pixels (documented in docs/gan.md), MSE is raw.
// Per colour channel, then averaged; only pixels with geometry count (sky has no light
// to predict). Two measures that see detail, in mapped space (frame_detail below):
//  * FLIP (report/flip.h): the mapped light read as the display's linear RGB (the previews
//    sRGB-encode exactly it), at the paper's 67 pixels per degree;
//  * gradient error: mean |finite difference of prediction - that of the truth| per channel.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/tensor.h"
#include "report/flip.h"
#include "report/image_metrics.h"
#include "classical_ao/temporal.h"
#include "models/gi/gi_inputs.h"
#include "models/gi/hdr_mapping.h"
#include "screen_space/discontinuities.h"
#include "screen_space/gbuffer.h"

namespace nns::runs {

struct LightMetrics {
  double mse = 0, psnr = 0, ssim = 0;                       // mapped space
  double mse_linear = 0, psnr_linear = 0, ssim_linear = 0;  // linear HDR
  double flip = 0, grad_error = 0;                          // mapped space (frame_detail)
};

// pred, target: linear light (3, h, w). geometry: h * w mask (1 = geometry).
inline LightMetrics light_metrics(const Tensor<float>& pred, const Tensor<float>& target,
                                  const std::vector<uint8_t>& geometry, const gi::HdrMapping& hdr) {
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
    m.mse += report::masked_mse(pu.data(), tu.data(), mask, n) / 3;
    m.ssim += report::masked_ssim(pu.data(), tu.data(), mask, w, h) / 3;
    m.mse_linear += report::masked_mse(pl.data(), tl.data(), mask, n) * double(peak) * peak / 3;
    m.ssim_linear += report::masked_ssim(pl.data(), tl.data(), mask, w, h) / 3;
  }
  m.psnr = report::psnr_from_mse(m.mse);
  m.psnr_linear = report::psnr_from_mse(m.mse_linear, peak);
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
    sum.flip += m.flip, sum.grad_error += m.grad_error;
    ++frames;
  }
  LightMetrics mean() const {
    LightMetrics m = sum;
    double k = frames ? 1.0 / double(frames) : NAN;
    m.mse *= k, m.psnr *= k, m.ssim *= k, m.mse_linear *= k, m.psnr_linear *= k, m.ssim_linear *= k;
    m.flip *= k, m.grad_error *= k;
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
inline bool next_on_path(const gi::GiSample& prev, const gi::GiSample& cur) {
  namespace fs = std::filesystem;
  int fp = -1, fc = -1;
  const std::string pp = classical_ao::path_of_frame(fs::path(prev.name).stem().string(), fp);
  const std::string pc = classical_ao::path_of_frame(fs::path(cur.name).stem().string(), fc);
  return !pc.empty() && pc == pp && fc == fp + 1 && prev.scene == cur.scene;
}

inline std::vector<int64_t> reproject_front(const gi::GiSample& cur, const gi::GiSample& prev) {
  // The AO radius is unused by reprojection; 1 stands in for the attribute GI views lack.
  const screen_space::GBuffer c = screen_space::gbuffer_from_view(cur.front_geometry, 1.0f);
  const screen_space::GBuffer p = screen_space::gbuffer_from_view(prev.front_geometry, 1.0f);
  return classical_ao::reproject_to_previous(c, cur.front_geometry.world_to_camera, p,
                                             prev.front_geometry.world_to_camera);
}

// A (3, h, w) linear-light frame in mapped space.
inline std::vector<float> mapped(const Tensor<float>& t, const gi::HdrMapping& hdr) {
  std::vector<float> out(size_t(t.numel()));
  for (int64_t i = 0; i < t.numel(); ++i) out[size_t(i)] = hdr.to_unit(t[i]);
  return out;
}

// Adds one frame pair of a method (m) against the ground truth (g), every channel.
inline void add_flicker_pair(classical_ao::TemporalStats& st, const std::vector<int64_t>& map,
                             const std::vector<float>& m, const std::vector<float>& m_prev, const std::vector<float>& g,
                             const std::vector<float>& g_prev) {
  const size_t n = map.size();
  for (size_t c = 0; c < 3; ++c)
    st.add_pair(map, m.data() + c * n, m_prev.data() + c * n, g.data() + c * n, g_prev.data() + c * n);
}

// FLIP and gradient error of one frame, from its mapped prediction and truth (3, h, w).
// FLIP's filters reach about 10 pixels, so a difference in the sky (which no metric
// scores) would bleed into the geometry next to it: the prediction takes the truth's sky
// first, as a renderer would composite the same sky behind either. The gradient error
// takes only pairs of geometry pixels. Returns the per-pixel FLIP map for the bands.
inline std::vector<float> frame_detail(const std::vector<float>& pred, const std::vector<float>& truth,
                                       const std::vector<uint8_t>& geometry, int w, int h, LightMetrics& m) {
  const size_t n = size_t(w) * size_t(h);
  std::vector<float> composited = pred;
  for (size_t c = 0; c < 3; ++c)
    for (size_t i = 0; i < n; ++i)
      if (!geometry[i]) composited[c * n + i] = truth[c * n + i];
  std::vector<float> map = report::flip_map(truth.data(), composited.data(), w, h);
  m.flip = report::masked_mean(map.data(), geometry.data(), int64_t(n));
  m.grad_error = 0;
  for (size_t c = 0; c < 3; ++c)
    m.grad_error += report::masked_gradient_error(pred.data() + c * n, truth.data() + c * n, geometry.data(), w, h) / 3;
  return map;
}

// Error by distance to the nearest surface break of the front view — a depth jump of
// more than 10% of the nearer depth, a crease (normals more than 30 degrees apart) or the
// sky's edge (screen_space/discontinuities.h) — where contact shadows and creases put
// the detail that a mean over the frame drowns. Distance is Chebyshev (the half-width of
// the smallest square holding a break pixel; both pixels of a broken pair are at 0), in
// bands that double: 0-1, 2-3, 4-7, 8-15, 16+ pixels. Pooled over the pixels of all
// frames (a band can hold few pixels of one frame), per band: mapped MSE (over the three
// channels) and mean FLIP.
struct DistanceBands {
  static constexpr int kCount = 5;
  static constexpr std::array<int, kCount> kLower = {0, 2, 4, 8, 16};
  static constexpr float kDepthRatio = 0.1f, kCreaseCos = 0.8660254f;  // cos 30°
  static std::string name(int b) {
    return b + 1 < kCount ? std::to_string(kLower[size_t(b)]) + "-" + std::to_string(kLower[size_t(b) + 1] - 1)
                          : std::to_string(kLower[size_t(b)]) + "+";
  }
  static int band_of(int distance) {
    int b = 0;
    while (b + 1 < kCount && distance >= kLower[size_t(b) + 1]) ++b;
    return b;
  }

  std::array<double, kCount> squared{}, flip{};
  std::array<int64_t, kCount> pixels{};

  double mse(int b) const { return pixels[size_t(b)] ? squared[size_t(b)] / double(3 * pixels[size_t(b)]) : NAN; }
  double mean_flip(int b) const { return pixels[size_t(b)] ? flip[size_t(b)] / double(pixels[size_t(b)]) : NAN; }
  double share(int b) const {
    int64_t all = 0;
    for (int64_t p : pixels) all += p;
    return all ? double(pixels[size_t(b)]) / double(all) : NAN;
  }
};

// Per front pixel its band, -1 for sky.
inline std::vector<int8_t> distance_bands_of(const gi::GiSample& s) {
  const screen_space::GBuffer g = screen_space::gbuffer_from_view(s.front_geometry, 1.0f);  // the radius is unused here
  const std::vector<int> d = screen_space::chebyshev_distance(
      screen_space::discontinuity_pixels(
          g.width, g.height, screen_space::surface_break(g, DistanceBands::kDepthRatio, DistanceBands::kCreaseCos)),
      g.width, g.height);
  std::vector<int8_t> band(d.size(), -1);
  for (size_t i = 0; i < d.size(); ++i)
    if (!g.sky(int64_t(i))) band[i] = int8_t(DistanceBands::band_of(d[i]));
  return band;
}

// Adds a frame's mapped prediction and truth (3, n) and its FLIP map to the bands; only
// geometry pixels count.
inline void add_to_bands(DistanceBands& bands, const std::vector<int8_t>& band, const std::vector<float>& pred,
                         const std::vector<float>& truth, const std::vector<float>& flip_map,
                         const std::vector<uint8_t>& geometry) {
  const size_t n = band.size();
  for (size_t i = 0; i < n; ++i) {
    if (band[i] < 0 || !geometry[i]) continue;
    const size_t b = size_t(band[i]);
    for (size_t c = 0; c < 3; ++c) {
      const double d = double(pred[c * n + i]) - truth[c * n + i];
      bands.squared[b] += d * d;
    }
    bands.flip[b] += flip_map[i];
    ++bands.pixels[b];
  }
}

}  // namespace nns::runs
