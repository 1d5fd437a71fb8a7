#pragma once
// NNAO's training points (paper, section 3): from every view, `per_view` random
// non-sky pixels (distinct, or all of them when fewer); each point is its feature
// vector (nnao_features.h) and the ground-truth AO of the centre pixel. The target is
// AO itself (1 = unoccluded), as the dataset stores it.
//
// The features are computed once into one matrix (points x w*w*4), so a training step
// only gathers rows: no feature work and no allocation per step. The matrix is stored in
// IEEE half precision (binary16, 11-bit significand: relative rounding error <= 2^-11),
// 2 bytes per feature: w = 31 needs 7.7 KB per point instead of 15.4 KB. Rows are
// widened to float when a batch is gathered (to_float); the network, the statistics
// and every sum run in float or double. See docs/nnao.md for the measured effect.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/rng.h"
#include "core/thread_pool.h"
#include "data/view.h"
#include "models/nnao/nnao_features.h"

namespace nns::nnao {

// binary16 via the compiler's _Float16 (F16C's vcvtps2ph / vcvtph2ps where the target
// has it). Conversion rounds to nearest even and saturates at +-65504, the largest
// finite half: a standardised feature never reaches it unless its std is ~0.
using Half = _Float16;
inline Half to_half(float v) {
  constexpr float kMax = 65504.0f;
  return Half(v > kMax ? kMax : (v < -kMax ? -kMax : v));
}
inline void to_float(const Half* in, float* out, int64_t n) {
  for (int64_t i = 0; i < n; ++i) out[i] = float(in[i]);
}

struct PointSet {
  int window = 31;
  int64_t count = 0, features = 0;
  std::vector<Half> x;   // (count, features), row-major, half precision
  std::vector<float> y;  // (count): AO of the centre pixel, float

  void reserve(int64_t n) {
    x.reserve(size_t(n * features));
    y.reserve(size_t(n));
  }
};

// Appends the points of one view. `radius` <= 0 uses the view's aoRadius. The pixels
// are drawn from `rng`; the features are computed in parallel (each row on its own, so
// the matrix is the same for any thread count).
inline void add_view_points(PointSet& ps, const data::View& v, int per_view, float radius, Rng& rng) {
  ao::GBuffer g = ao::gbuffer_from_view(v, radius);
  if (!v.has("AO"))
    throw std::runtime_error((v.source.empty() ? std::string("view") : v.source) +
                             ": missing channel 'AO' (NNAO training needs ground-truth AO)");
  const auto& ao = v.channel("AO");
  std::vector<int64_t> pix = non_sky_pixels(g);
  const int64_t n = std::min<int64_t>(per_view, int64_t(pix.size()));
  // Partial Fisher-Yates: the first n entries become a uniform random subset.
  for (int64_t i = 0; i < n; ++i) std::swap(pix[size_t(i)], pix[size_t(i + int64_t(rng.below(pix.size() - size_t(i))))]);
  const int64_t F = ps.features, base = ps.count;
  ps.x.resize(size_t((base + n) * F));
  ps.y.resize(size_t(base + n));
  parallel_for(n, [&](int64_t b, int64_t e) {
    std::vector<float> row(static_cast<size_t>(F));
    for (int64_t k = b; k < e; ++k) {
      const int64_t p = pix[size_t(k)];
      compute_features(g, int(p % g.width), int(p / g.width), ps.window, row.data());
      Half* dst = ps.x.data() + (base + k) * F;
      for (int64_t f = 0; f < F; ++f) dst[f] = to_half(row[size_t(f)]);
      ps.y[size_t(base + k)] = ao[size_t(p)];
    }
  }, 16);
  ps.count = base + n;
}

struct Standardizer {
  std::vector<float> mean, std;  // per feature
  float target_mean = 0, target_std = 1;
};

// Per-feature mean and standard deviation over the (half-precision) points, in double,
// feature by feature (each sum runs over the points in order: identical for any thread count).
// A feature that never varies (the centre sample is always 0) gets std 1.
inline Standardizer fit_standardizer(const PointSet& ps) {
  const int64_t F = ps.features, n = ps.count;
  Standardizer s;
  s.mean.assign(size_t(F), 0);
  s.std.assign(size_t(F), 1);
  parallel_for(F, [&](int64_t f0, int64_t f1) {
    std::vector<double> sum(size_t(f1 - f0), 0), sq(size_t(f1 - f0), 0);
    for (int64_t i = 0; i < n; ++i) {
      const Half* row = ps.x.data() + i * F;
      for (int64_t f = f0; f < f1; ++f) {
        const double v = double(row[f]);
        sum[size_t(f - f0)] += v;
        sq[size_t(f - f0)] += v * v;
      }
    }
    for (int64_t f = f0; f < f1; ++f) {
      const double m = n ? sum[size_t(f - f0)] / double(n) : 0;
      const double var = n ? sq[size_t(f - f0)] / double(n) - m * m : 0;
      s.mean[size_t(f)] = float(m);
      s.std[size_t(f)] = var > 1e-12 ? float(std::sqrt(var)) : 1.0f;
    }
  }, 64, 16);
  double ts = 0, tq = 0;
  for (float v : ps.y) ts += v, tq += double(v) * v;
  const double tm = n ? ts / double(n) : 0, tv = n ? tq / double(n) - tm * tm : 0;
  s.target_mean = float(tm);
  s.target_std = tv > 1e-12 ? float(std::sqrt(tv)) : 1.0f;
  return s;
}

inline void apply_standardizer(PointSet& ps, const Standardizer& s) {
  const int64_t F = ps.features;
  parallel_for(ps.count, [&](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i) {
      Half* row = ps.x.data() + i * F;
      for (int64_t f = 0; f < F; ++f) row[f] = to_half((float(row[f]) - s.mean[size_t(f)]) / s.std[size_t(f)]);
      ps.y[size_t(i)] = (ps.y[size_t(i)] - s.target_mean) / s.target_std;
    }
  }, 64);
}

}  // namespace nns::nnao
