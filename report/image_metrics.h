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

namespace nns::data {

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

// Per-pixel SSIM (Wang et al. 2004): 11x11 Gaussian window, sigma 1.5,
// C1 = (0.01 L)^2, C2 = (0.03 L)^2 with L = 1. The window is truncated at the border
// and renormalised, so border pixels use the pixels that exist.
inline std::vector<float> ssim_map(const float* a, const float* b, int w, int h) {
  const int R = 5;
  double g[2 * R + 1], gs = 0;
  for (int k = -R; k <= R; ++k) gs += g[k + R] = std::exp(-double(k * k) / (2 * 1.5 * 1.5));
  for (double& v : g) v /= gs;
  const int64_t n = int64_t(w) * h;
  // Five moments, blurred separably: horizontal pass into tmp, vertical into out.
  std::vector<double> src(size_t(n) * 5), tmp(size_t(n) * 5), out(size_t(n) * 5);
  for (int64_t i = 0; i < n; ++i) {
    double x = a[i], y = b[i];
    double* s = &src[size_t(i) * 5];
    s[0] = x, s[1] = y, s[2] = x * x, s[3] = y * y, s[4] = x * y;
  }
  auto blur = [&](const std::vector<double>& in, std::vector<double>& o, bool horizontal) {
    for (int yy = 0; yy < h; ++yy)
      for (int xx = 0; xx < w; ++xx) {
        double acc[5] = {0, 0, 0, 0, 0}, wsum = 0;
        for (int k = -R; k <= R; ++k) {
          int sx = horizontal ? xx + k : xx, sy = horizontal ? yy : yy + k;
          if (sx < 0 || sy < 0 || sx >= w || sy >= h) continue;
          const double* p = &in[(size_t(sy) * w + sx) * 5];
          for (int c = 0; c < 5; ++c) acc[c] += g[k + R] * p[c];
          wsum += g[k + R];
        }
        double* q = &o[(size_t(yy) * w + xx) * 5];
        for (int c = 0; c < 5; ++c) q[c] = acc[c] / wsum;
      }
  };
  blur(src, tmp, true);
  blur(tmp, out, false);
  const double C1 = 0.01 * 0.01, C2 = 0.03 * 0.03;
  std::vector<float> map(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) {
    const double* m = &out[size_t(i) * 5];
    double mx = m[0], my = m[1];
    double vx = m[2] - mx * mx, vy = m[3] - my * my, cxy = m[4] - mx * my;
    map[size_t(i)] = float(((2 * mx * my + C1) * (2 * cxy + C2)) /
                           ((mx * mx + my * my + C1) * (vx + vy + C2)));
  }
  return map;
}

inline double masked_mean(const float* v, const uint8_t* mask, int64_t n) {
  double s = 0;
  int64_t count = 0;
  for (int64_t i = 0; i < n; ++i)
    if (!mask || mask[i]) s += v[i], ++count;
  return count ? s / double(count) : std::numeric_limits<double>::quiet_NaN();
}

inline double masked_ssim(const float* a, const float* b, const uint8_t* mask, int w, int h) {
  auto map = ssim_map(a, b, w, h);
  return masked_mean(map.data(), mask, int64_t(w) * h);
}

}  // namespace nns::data
