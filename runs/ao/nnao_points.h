#pragma once
// NNAO's training points (paper, section 3): from every view, `per_view` random
// non-sky pixels (distinct, or all of them when fewer); each point is its input row
// (nnao_inputs.h: grid or horizon features) and the ground-truth AO of the centre
// pixel minus the inputs' base (0 for the grid kind, so its target is AO itself).
//
// The features are computed once, view by view, into rows of a file with no name
// (runs/ao/row_file.h) in the output folder, so a training step only gathers rows (no
// feature work, no allocation per step) and the memory does not grow with the number of
// views. A row is w*w*4 features in IEEE half precision (binary16, 11-bit significand:
// relative rounding error <= 2^-11, 2 bytes per feature: w = 31 needs 7.7 KB per point
// instead of 15.4 KB, the default horizon layout 0.14 KB: 70 features) followed by the float target. Rows are widened
// to float when a batch is gathered (to_float); the network, the statistics and every sum run in float or double. See
// docs/nnao.md for the measured effect of both.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "core/rng.h"
#include "core/thread_pool.h"
#include "data/view.h"
#include "models/nnao/nnao_inputs.h"
#include "screen_space/low_resolution.h"
#include "runs/ao/row_file.h"

namespace nns::runs {

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

// Bytes of one point's row: the features in binary16, then the target as a float, read
// and written with memcpy (an odd feature count puts it at a 2-byte offset).
inline int64_t point_row_bytes(int64_t features) { return features * int64_t(sizeof(Half)) + int64_t(sizeof(float)); }
inline const Half* row_features(const char* row) { return reinterpret_cast<const Half*>(row); }
inline Half* row_features(char* row) { return reinterpret_cast<Half*>(row); }
inline float row_target(const char* row, int64_t features) {
  float y;
  std::memcpy(&y, row + features * int64_t(sizeof(Half)), sizeof y);
  return y;
}
inline void set_row_target(char* row, int64_t features, float y) {
  std::memcpy(row + features * int64_t(sizeof(Half)), &y, sizeof y);
}

// A split's points: rows (point_row_bytes) in a file that lives as long as this object.
struct PointFile {
  nnao::InputSpec input;
  int64_t features = 0;
  runs::RowFile rows;
  int64_t count() const { return rows.rows(); }
};

// One view's points as rows (appended to `rows`, which is resized). `radius` <= 0 uses
// the view's aoRadius. The pixels are drawn from `rng`; the features are computed in
// parallel (each row on its own, so the rows are the same for any thread count).
// Returns the number of points.
//
// `downsample` s > 1: the points are pixels of the view's G-buffer at 1/s of its
// resolution (screen_space/low_resolution.h), as the model will see frames at inference,
// and each target is the full-resolution truth at the pixel that low pixel is.
inline int64_t view_points(const data::View& v, const nnao::InputSpec& input, int per_view, float radius, Rng& rng,
                           std::vector<char>& rows, int downsample = 1) {
  const screen_space::GBuffer full = screen_space::gbuffer_from_view(v, radius);
  if (!v.has("AO"))
    throw std::runtime_error((v.source.empty() ? std::string("view") : v.source) +
                             ": missing channel 'AO' (NNAO training needs ground-truth AO)");
  const auto& ao_full = v.channel("AO");
  screen_space::LowResGBuffer lr;
  std::vector<float> ao_low;
  if (downsample > 1) {
    lr = screen_space::downsample_gbuffer(full, downsample);
    ao_low.resize(size_t(lr.g.pixels()));
    for (int y = 0; y < lr.g.height; ++y)
      for (int x = 0; x < lr.g.width; ++x)
        ao_low[size_t(y) * size_t(lr.g.width) + size_t(x)] =
            ao_full[size_t(screen_space::LowResGBuffer::source(y, downsample, full.height)) * size_t(full.width) +
                    size_t(screen_space::LowResGBuffer::source(x, downsample, full.width))];
  }
  const screen_space::GBuffer& g = downsample > 1 ? lr.g : full;
  const std::vector<float>& ao = downsample > 1 ? ao_low : ao_full;
  std::vector<int64_t> pix = nnao::non_sky_pixels(g);
  const int64_t n = std::min<int64_t>(per_view, int64_t(pix.size()));
  // Partial Fisher-Yates: the first n entries become a uniform random subset.
  for (int64_t i = 0; i < n; ++i)
    std::swap(pix[size_t(i)], pix[size_t(i + int64_t(rng.below(pix.size() - size_t(i))))]);
  const int64_t F = input.count(), R = point_row_bytes(F);
  rows.resize(size_t(n * R));
  parallel_for(
      n,
      [&](int64_t b, int64_t e) {
        std::vector<float> row(static_cast<size_t>(F));
        for (int64_t k = b; k < e; ++k) {
          const int64_t p = pix[size_t(k)];
          input.compute(g, int(p % g.width), int(p / g.width), row.data());
          char* dst = rows.data() + k * R;
          Half* x = row_features(dst);
          for (int64_t f = 0; f < F; ++f) x[f] = to_half(row[size_t(f)]);
          set_row_target(dst, F, ao[size_t(p)] - input.base(row.data()));
        }
      },
      16);
  return n;
}

struct Standardizer {
  std::vector<float> mean, std;  // per feature
  float target_mean = 0, target_std = 1;
};

// Per-feature mean and standard deviation of the (half-precision) training points, in
// double, accumulated block by block as the points are written (one pass, no matrix in
// memory). Each feature's sum runs over the points in file order, whatever the blocks
// and the thread count, so the statistics are the same for any of them.
// A feature that never varies (the centre sample is always 0) gets std 1.
struct StandardizerSums {
  int64_t features = 0, n = 0;
  std::vector<double> sum, sq;
  double ts = 0, tq = 0;

  explicit StandardizerSums(int64_t F) : features(F), sum(size_t(F), 0), sq(size_t(F), 0) {}

  void add(const char* rows, int64_t count) {
    const int64_t F = features, R = point_row_bytes(F);
    parallel_for(
        F,
        [&](int64_t f0, int64_t f1) {
          for (int64_t i = 0; i < count; ++i) {
            const Half* x = row_features(rows + i * R);
            for (int64_t f = f0; f < f1; ++f) {
              const double v = double(x[f]);
              sum[size_t(f)] += v;
              sq[size_t(f)] += v * v;
            }
          }
        },
        64, 16);
    for (int64_t i = 0; i < count; ++i) {
      const double v = row_target(rows + i * R, F);
      ts += v, tq += v * v;
    }
    n += count;
  }

  Standardizer finish() const {
    Standardizer s;
    s.mean.assign(size_t(features), 0);
    s.std.assign(size_t(features), 1);
    for (int64_t f = 0; f < features; ++f) {
      const double m = n ? sum[size_t(f)] / double(n) : 0;
      const double var = n ? sq[size_t(f)] / double(n) - m * m : 0;
      s.mean[size_t(f)] = float(m);
      s.std[size_t(f)] = var > 1e-12 ? float(std::sqrt(var)) : 1.0f;
    }
    const double tm = n ? ts / double(n) : 0, tv = n ? tq / double(n) - tm * tm : 0;
    s.target_mean = float(tm);
    s.target_std = tv > 1e-12 ? float(std::sqrt(tv)) : 1.0f;
    return s;
  }
};

// Standardises rows in place; the features are rounded to binary16 again.
inline void standardize_rows(char* rows, int64_t count, int64_t F, const Standardizer& s) {
  const int64_t R = point_row_bytes(F);
  parallel_for(
      count,
      [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
          char* row = rows + i * R;
          Half* x = row_features(row);
          for (int64_t f = 0; f < F; ++f) x[f] = to_half((float(x[f]) - s.mean[size_t(f)]) / s.std[size_t(f)]);
          set_row_target(row, F, (row_target(row, F) - s.target_mean) / s.target_std);
        }
      },
      64);
}

// Standardises a point file in place, a bounded block of rows at a time (one read and
// one write of the file, once per run, instead of standardising every epoch).
inline void standardize_file(PointFile& pf, const Standardizer& s) {
  const int64_t R = point_row_bytes(pf.features), block = std::max<int64_t>(1, (32ll << 20) / R);
  std::vector<char> buf(size_t(std::min(block, pf.count()) * R));
  for (int64_t b = 0; b < pf.count(); b += block) {
    const int64_t n = std::min(block, pf.count() - b);
    pf.rows.read_rows(b, n, buf.data());
    standardize_rows(buf.data(), n, pf.features, s);
    pf.rows.write_rows(b, n, buf.data());
  }
}

}  // namespace nns::runs
