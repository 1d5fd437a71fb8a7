#pragma once
// What the generator's frame-level head (unet.h, UnetGenerator::level_gain) reads of the
// whole input view: per input channel its mean and mean square, and, with `energy`, per
// colour channel the log of the mean linear lumination and of the mean albedo x
// lumination, the light the view's surfaces send on (the first bounce's source).
//
// Why the energy: the lumination channels are Reinhard-mapped (hdr_mapping.h), so their
// mean says little about the light's total: a sun-lit wall 50x brighter than the shadow
// maps below 1. Undone per pixel, in units of k (u / (1 - u), scale-free), and averaged,
// it is what the bounced light's level follows; the log makes a factor an offset for the
// MLP, and exp of its output a gain. With these six features the validation MSE fell
// 15% (docs/results/2026-12-06-gi-frame-energy.md).
//
// Features of sample b, in this order (C input channels, F = 2C or 2C + 6):
//   mean_hw(x_c)                                     c = 0 .. C-1
//   mean_hw(x_c^2)                                   c = 0 .. C-1
//   log(mean_hw(L_c) + 1e-3)                         c = 0 .. 2   (energy)
//   log(mean_hw(a_c L_c) + 1e-3)                     c = 0 .. 2   (energy)
// with a_c = (x_{albedo+c} + 1) / 2, u = clamp((x_{lumination+c} + 1) / 2, 0, 1 - 2^-20),
// L_c = u / (1 - u) (gi_inputs.h's channel layout). Sums in double, in four lanes.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "core/tensor.h"
#include "models/gi/gi_inputs.h"
#include "models/gi/hdr_mapping.h"

namespace nns::gi {

// Sums over a view in four interleaved partial sums, added in a fixed order at the end:
// one running double sum waits for the adder's latency at every pixel (0.52 ms against
// 0.23 ms per default frame, benchmarks/bench_frame_level_features.cpp).
constexpr int kLanes = 4;
template <class F>
void for_lanes(int64_t n, F&& f) {
  int64_t i = 0;
  for (; i + kLanes <= n; i += kLanes)
    for (int k = 0; k < kLanes; ++k) f(i + k, k);
  for (; i < n; ++i) f(i, 0);
}
inline double lane_total(const double (&s)[kLanes]) { return (s[0] + s[1]) + (s[2] + s[3]); }

inline int64_t frame_level_feature_count(int64_t channels, bool energy) { return 2 * channels + (energy ? 6 : 0); }

// x: (B, C, H, W) in gi_inputs.h's layout; returns (B, F).
template <class T>
Tensor<T> frame_level_features(const Tensor<T>& x, bool energy) {
  const int64_t B = x.size(0), C = x.size(1), n = x.size(2) * x.size(3), F = frame_level_feature_count(C, energy);
  if (energy && C < kLuminationChannel + 3)
    throw std::invalid_argument("frame_level_features: the energy needs the lumination channels 7-9");
  Tensor<T> f({B, F});
  for (int64_t b = 0; b < B; ++b) {
    const T* xb = x.data() + b * C * n;
    T* fb = f.data() + b * F;
    for (int64_t c = 0; c < C; ++c) {
      const T* p = xb + c * n;
      double m[kLanes] = {}, q[kLanes] = {};
      for_lanes(n, [&](int64_t i, int k) { m[k] += double(p[i]), q[k] += double(p[i]) * double(p[i]); });
      fb[c] = T(lane_total(m) / double(n));
      fb[C + c] = T(lane_total(q) / double(n));
    }
    if (!energy) continue;
    for (int64_t c = 0; c < 3; ++c) {
      const T *a = xb + (kAlbedoChannel + c) * n, *l = xb + (kLuminationChannel + c) * n;
      double sum_l[kLanes] = {}, sum_al[kLanes] = {};
      for_lanes(n, [&](int64_t i, int k) {
        const double u = std::clamp(0.5 * (double(l[i]) + 1), 0.0, double(HdrMapping::kMaxUnit));
        const double light = u / (1 - u);
        sum_l[k] += light, sum_al[k] += 0.5 * (double(a[i]) + 1) * light;
      });
      fb[2 * C + c] = T(std::log(lane_total(sum_l) / double(n) + 1e-3));
      fb[2 * C + 3 + c] = T(std::log(lane_total(sum_al) / double(n) + 1e-3));
    }
  }
  return f;
}

}  // namespace nns::gi
