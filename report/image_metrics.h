#pragma once
// Error metrics between two single-channel float images of the same size, restricted
// to a mask (sky pixels are excluded from every AO error). mask == nullptr means every
// pixel; a mask byte != 0 selects the pixel. Values are expected in [0, 1] (AO, or a
// channel of a tone-mapped image): PSNR uses peak 1 and SSIM its constants for range 1.
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/kernels/ssim.h"

namespace nns::report {

// Mean squared error over the selected pixels; NaN when the mask selects none.
inline double masked_mse(const float* a, const float* b, const uint8_t* mask, int64_t n) {
  double s = 0;
  int64_t count = 0;
  for (int64_t i = 0; i < n; ++i) {
    if (mask && !mask[i]) continue;
    double d = double(a[i]) - double(b[i]);
    s += d * d;
    ++count;
  }
  return count ? s / double(count) : std::numeric_limits<double>::quiet_NaN();
}

// 10 log10(peak^2 / mse); +inf for identical images.
inline double psnr_from_mse(double mse, double peak = 1.0) {
  if (mse <= 0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(peak * peak / mse);
}

inline double masked_mean(const float* v, const uint8_t* mask, int64_t n) {
  double s = 0;
  int64_t count = 0;
  for (int64_t i = 0; i < n; ++i)
    if (!mask || mask[i]) s += v[i], ++count;
  return count ? s / double(count) : std::numeric_limits<double>::quiet_NaN();
}

// Mean SSIM over the selected pixels: core/kernels/ssim.h's per-pixel map (11x11
// Gaussian window, sigma 1.5, C1 = (0.01 L)^2, C2 = (0.03 L)^2 with L = 1; the window
// truncated and renormalised at the border so border pixels use the pixels that exist).
inline double masked_ssim(const float* a, const float* b, const uint8_t* mask, int w, int h) {
  auto map = ssim_map_renormalised(a, b, h, w);
  return masked_mean(map.data(), mask, int64_t(w) * h);
}

// Gradient-domain error: the mean over forward differences, horizontal and vertical, whose
// two pixels are both selected, of |(a[j] - a[i]) - (b[j] - b[i])|. A uniform offset
// scores 0 and a moved, lost or invented edge scores its step: it sees the detail
// (contact shadows, creases) that MSE, dominated by broad offsets, averages away. The
// absolute value rather than the square keeps many small missing steps (a soft contact
// shadow) from being swamped by the few large ones at silhouettes, and keeps the unit
// that of the image per pixel. NaN when no pair is selected.
inline double masked_gradient_error(const float* a, const float* b, const uint8_t* mask, int w, int h) {
  double s = 0;
  int64_t count = 0;
  auto add = [&](int64_t i, int64_t j) {
    if (mask && (!mask[i] || !mask[j])) return;
    s += std::abs((double(a[j]) - a[i]) - (double(b[j]) - b[i]));
    ++count;
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int64_t i = int64_t(y) * w + x;
      if (x + 1 < w) add(i, i + 1);
      if (y + 1 < h) add(i, i + w);
    }
  return count ? s / double(count) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace nns::report
