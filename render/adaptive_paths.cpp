#include "render/adaptive_paths.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nns::data {

std::vector<int> allot_paths(int width, int height, const std::vector<double>& variance,
                             const std::vector<uint8_t>& geometry, int first, int mean, int most) {
  const size_t n = size_t(width) * size_t(height);
  if (variance.size() != n || geometry.size() != n) throw std::invalid_argument("allot_paths: plane sizes");
  most = std::max(most, first);
  std::vector<int> paths(n, 0);
  // sigma per geometry pixel from its neighbours; < 0: none to ask.
  std::vector<double> sigma(n, -1.0);
  size_t pixels = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      if (!geometry[i]) continue;
      ++pixels;
      double sum = 0;
      int count = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if ((dx == 0 && dy == 0) || qx < 0 || qy < 0 || qx >= width || qy >= height) continue;
          const size_t q = size_t(qy) * size_t(width) + size_t(qx);
          if (geometry[q]) sum += variance[q], ++count;
        }
      if (count > 0) sigma[i] = std::sqrt(sum / count);
    }
  if (pixels == 0) return paths;
  auto count_for = [&](size_t i, double k) {
    if (sigma[i] < 0) return std::clamp(mean, first, most);
    const double want = std::min(double(most), k * sigma[i]);  // min first: k * sigma may be inf
    return std::clamp(int(std::lround(std::max(want, double(first)))), first, most);
  };
  auto total_for = [&](double k) {
    double t = 0;
    for (size_t i = 0; i < n; ++i)
      if (geometry[i]) t += count_for(i, k);
    return t;
  };
  // The total grows with k from pixels * first to pixels * most: bisection on log k
  // for the largest k whose total stays within the budget.
  const double budget = double(mean) * double(pixels);
  double k = 0;
  if (mean > first) {
    double max_sigma = 0, min_sigma = INFINITY;
    for (size_t i = 0; i < n; ++i)
      if (geometry[i] && sigma[i] > 0) max_sigma = std::max(max_sigma, sigma[i]), min_sigma = std::min(min_sigma, sigma[i]);
    if (max_sigma > 0) {
      double lo = std::log(double(first) / max_sigma) - 1, hi = std::log(double(most) / min_sigma) + 1;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (total_for(std::exp(mid)) <= budget ? lo : hi) = mid;
      }
      k = std::exp(lo);
    }
  }
  for (size_t i = 0; i < n; ++i)
    if (geometry[i]) paths[i] = count_for(i, k);
  return paths;
}

}  // namespace nns::data
