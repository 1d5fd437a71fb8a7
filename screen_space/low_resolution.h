#pragma once
// Screen-space AO at a fraction of the frame's resolution, the way engines run GTAO and
// HBAO+ at half resolution: a G-buffer with one pixel of every s x s block, the effect
// computed on it, then brought back to full resolution by an upsample guided by the
// full-resolution depth and normals (a joint bilateral upsample: Kopf et al. 2007).
//
// The low-resolution pixel (x, y) is the full-resolution pixel (s x + s/2, s y + s/2)
// (clamped to the frame): a real surface point, never an average of depths across an
// edge. Its plane is read as a frame of ceil(W/s) x ceil(H/s) pixels of the same camera;
// that places it within half a full-resolution pixel of where it is, the same for every
// pixel (a shift of the principal point, not a distortion).
//
// The upsample: a full-resolution pixel X lies at u = (X - s/2) / s in low-resolution
// coordinates (the low pixels' own positions); its four neighbours get their bilinear
// weights times exp(-(dz / (depth r))^2) max(0, n.n')^normal_power, the edge terms of the
// bilateral blur, so light does not bleed across a depth step or a crease. Where every
// neighbour is stopped (a thin object seen at no low-resolution pixel) the pixel takes
// the neighbour of nearest depth. Sky stays 1.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "screen_space/gbuffer.h"
#include "screen_space/pow_by_squaring.h"
#include "screen_space/simd16.h"

namespace nns::screen_space {

struct LowResGBuffer {
  int scale = 1;
  std::vector<float> z, nx, ny, nz;
  GBuffer g;  // views the planes above
  // The full-resolution pixel that low-resolution pixel (x, y) is.
  static int source(int x, int scale, int full) { return std::min(full - 1, x * scale + scale / 2); }
};

inline LowResGBuffer downsample_gbuffer(const GBuffer& full, int scale) {
  LowResGBuffer lr;
  lr.scale = scale;
  const int w = (full.width + scale - 1) / scale, h = (full.height + scale - 1) / scale;
  const size_t n = size_t(w) * size_t(h);
  lr.z.resize(n), lr.nx.resize(n), lr.ny.resize(n), lr.nz.resize(n);
  parallel_for(h, [&](int64_t y0, int64_t y1) {  // at 1280x720 a serial copy held the second thread back
    for (int64_t y = y0; y < y1; ++y) {
      const int64_t row = int64_t(LowResGBuffer::source(int(y), scale, full.height)) * full.width;
      for (int x = 0; x < w; ++x) {
        const int64_t j = row + LowResGBuffer::source(x, scale, full.width);
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        lr.z[i] = full.z[j], lr.nx[i] = full.nx[j], lr.ny[i] = full.ny[j], lr.nz[i] = full.nz[j];
      }
    }
  });
  const float fov_y_deg = 2.0f * std::atan(full.sy) * 180.0f / 3.14159265358979f;
  lr.g = make_gbuffer(w, h, fov_y_deg, full.radius, lr.z.data(), lr.nx.data(), lr.ny.data(), lr.nz.data());
  // The same tangents as the full frame's (make_gbuffer recomputes them from the angle
  // and the rounded size, which would scale the image by up to one pixel in W).
  lr.g.sx = full.sx, lr.g.sy = full.sy;
  return lr;
}

struct UpsampleEdges {
  float depth = 0.3f;    // the depth term's scale, in AO radii
  int normal_power = 2;  // max(0, n.n')^power
};

// The scalar loop the vectorised upsample must match: one full-resolution pixel.
inline float upsample_pixel(const GBuffer& full, const LowResGBuffer& lr, const float* low, int X, int Y,
                            const UpsampleEdges& e) {
  const int64_t i = int64_t(Y) * full.width + X;
  if (full.sky(i)) return 1.0f;
  const int s = lr.scale, w = lr.g.width, h = lr.g.height;
  const float u = (float(X) - float(s / 2)) / float(s), v = (float(Y) - float(s / 2)) / float(s);
  const float fu = std::floor(u), fv = std::floor(v);
  const float ax = u - fu, ay = v - fv;
  const int x0 = int(fu), y0 = int(fv);
  const float z = full.z[i], nxc = full.nx[i], nyc = full.ny[i], nzc = full.nz[i];
  const float inv_dz = 1.0f / (e.depth * full.radius);
  float s_sum = 0, w_sum = 0, nearest = 1, nearest_dz = INFINITY;
  for (int t = 0; t < 4; ++t) {
    const int tx = std::clamp(x0 + (t & 1), 0, w - 1), ty = std::clamp(y0 + (t >> 1), 0, h - 1);
    const int64_t j = int64_t(ty) * w + tx;
    const float zj = lr.z[size_t(j)];
    if (data::is_sky(zj)) continue;
    const float bw = ((t & 1) ? ax : 1 - ax) * ((t >> 1) ? ay : 1 - ay);
    const float dz = (zj - z) * inv_dz;
    const float nd = std::max(0.0f, nxc * lr.nx[size_t(j)] + nyc * lr.ny[size_t(j)] + nzc * lr.nz[size_t(j)]);
    const float wt = bw * std::exp(-(dz * dz)) * pow_by_squaring(nd, e.normal_power, 1.0f);
    s_sum += wt * low[j], w_sum += wt;
    if (std::fabs(dz) < nearest_dz) nearest_dz = std::fabs(dz), nearest = low[j];
  }
  return w_sum > 1e-6f ? s_sum / w_sum : nearest;
}

inline void upsample_reference(const GBuffer& full, const LowResGBuffer& lr, const float* low, float* out,
                               const UpsampleEdges& e = {}) {
  for (int y = 0; y < full.height; ++y)
    for (int x = 0; x < full.width; ++x) out[int64_t(y) * full.width + x] = upsample_pixel(full, lr, low, x, y, e);
}

// The two low-resolution rows a band of full-resolution rows reads, laid out by
// full-resolution column: row r (0: upper, 1: lower) holds E_r[X] = plane[ty_r * w + tx],
// tx = clamp(left_tap(X), 0, w - 1), for X in [0, W + s). Tap c (0: left, 1: right) of
// column X is E_r[X + c s], since left_tap(X + s) = left_tap(X) + 1 (exact for s = 2, 4).
// The upsample's four gathers per plane become contiguous loads of the same values (a
// 1/4 rung's upsample spent most of its time in those gathers). Each worker builds the
// rows of the bands it upsamples in its own buffer, keeping a row the next band reuses:
// built once per frame for the whole frame, they were a serial 0.2 ms of page faults for
// a 1/4 rung at 320x180, and the upsample as a whole did not get faster on 2 threads.
struct TapRows {
  int width = 0, scale = 1;               // full-resolution columns; a row's stride is width + scale
  int low_row[2] = {-1, -1};              // the low-resolution row each of the two holds (-1: none)
  std::vector<float> z, low, nx, ny, nz;  // [r * (width + scale) + X]
  const float* row(const std::vector<float>& plane, int r, int c) const {
    return plane.data() + int64_t(r) * (width + scale) + c * scale;
  }
};

// The left neighbour of full-resolution column X: floor((X - s/2) / s), computed as the
// vector loop computes u (a multiplication by 1/s, exact for s = 2 and 4).
inline int left_tap(int X, int s) {
  const float u = (float(X) - float(s / 2)) * (1.0f / float(s));
  return int(std::floor(u));
}

// Makes `t` hold low rows ty0 (r = 0) and ty1 (r = 1) of `low` and the G-buffer planes;
// column[X] = clamp(left_tap(X), 0, w - 1) for X in [0, W + s). The caller sets
// t.low_row to -1 before the first band of a frame; after that, a lower row that is the
// next band's upper row moves up instead of being read again.
inline void fill_tap_rows(const LowResGBuffer& lr, const float* low, const int* column, int W, int ty0, int ty1,
                          bool normals, TapRows& t) {
  const int stride = W + lr.scale, w = lr.g.width;
  const size_t n = size_t(2) * size_t(stride);
  t.width = W, t.scale = lr.scale;
  t.z.resize(n), t.low.resize(n);
  if (normals) t.nx.resize(n), t.ny.resize(n), t.nz.resize(n);
  auto fill = [&](int r, int ty) {
    const size_t out = size_t(r) * size_t(stride), row = size_t(ty) * size_t(w);
    for (int X = 0; X < stride; ++X) {
      const size_t j = row + size_t(column[X]);
      t.z[out + size_t(X)] = lr.z[j], t.low[out + size_t(X)] = low[j];
      if (normals) t.nx[out + size_t(X)] = lr.nx[j], t.ny[out + size_t(X)] = lr.ny[j], t.nz[out + size_t(X)] = lr.nz[j];
    }
    t.low_row[r] = ty;
  };
  auto move_lower_up = [&](std::vector<float>& plane) {
    std::copy(plane.begin() + stride, plane.begin() + 2 * stride, plane.begin());
  };
  if (t.low_row[1] == ty0 && ty0 >= 0) {  // the previous band's lower row is this band's upper one
    move_lower_up(t.z), move_lower_up(t.low);
    if (normals) move_lower_up(t.nx), move_lower_up(t.ny), move_lower_up(t.nz);
    t.low_row[0] = ty0;
  } else {
    fill(0, ty0);
  }
  fill(1, ty1);
}

// upsample_pixel for 16 pixels of a row at once (the same expressions; exp through
// exp_nonpositive, which the tests hold against std::exp). Two shortcuts keep the bytes
// and cut the time by a third (a 1/4 rung's upsample at 198x198: 0.33 -> 0.21 ms on 1
// thread): a block inside the row reads depths with plain loads, since a lane outside a
// tap's mask reaches the sums only through a weight selected to 0 and the nearest-depth
// choice only through that mask; and the nearest-depth fallback is computed only for a
// block where some pixel's weights all vanished.
struct UpsampleFrame {  // what every block of a frame shares
  int scale;
  float inv_dz, half, inv_s;  // 1 / (depth term's scale x radius), s/2 and 1/s
  bool normals;               // power 0: every weight 1, three planes a tap not read
  UpsampleFrame(const GBuffer& full, int s, const UpsampleEdges& e)
      : scale(s),
        inv_dz(1.0f / (e.depth * full.radius)),
        half(float(s / 2)),
        inv_s(1.0f / float(s)),
        normals(e.normal_power > 0) {}
};

// One block of 16 pixels of full-resolution row y, from x0, with the band's tap rows.
inline void upsample_block(const GBuffer& full, const TapRows& taps, const UpsampleEdges& e, const UpsampleFrame& f,
                           int x0, int y, float* out) {
  using namespace simd;
  const int W = full.width;
  const float inv_dz = f.inv_dz, half = f.half, inv_s = f.inv_s;
  const bool normals = f.normals;
  const Mask valid = Mask((1u << (W - x0 < kLanes ? W - x0 : kLanes)) - 1);
  const int64_t i0 = int64_t(y) * W + x0;
  const bool full_block = x0 + kLanes <= W;
  const VF z = full_block ? load(full.z + i0) : load(full.z + i0, valid, INFINITY);
  const Mask live = valid & ~sky(z);
  if (!live) {
    store(out + i0, splat(1.0f), valid);
    return;
  }
  VF nxc = splat(0.0f), nyc = splat(0.0f), nzc = splat(0.0f);
  if (normals)
    nxc = load(full.nx + i0, live, 0.0f), nyc = load(full.ny + i0, live, 0.0f), nzc = load(full.nz + i0, live, 0.0f);
  const VF u = (to_float(lane_index() + splat_i(x0)) - splat(half)) * splat(inv_s);
  const float v = (float(y) - half) * inv_s, fv = std::floor(v), ay = v - fv;
  const VF fu = floor(u), ax = u - fu;
  VF s_sum = splat(0.0f), w_sum = splat(0.0f);
  for (int t = 0; t < 4; ++t) {
    const int r = t >> 1, c = t & 1;
    const VF zj = full_block ? load(taps.row(taps.z, r, c) + x0) : load(taps.row(taps.z, r, c) + x0, live, INFINITY);
    const Mask m = live & ~sky(zj);
    if (!m) continue;
    const VF bw = (c ? ax : splat(1.0f) - ax) * splat(r ? ay : 1 - ay);
    const VF dz = (zj - z) * splat(inv_dz);
    VF p = splat(1.0f);
    if (normals) {
      const VF nd = max(splat(0.0f), nxc * load(taps.row(taps.nx, r, c) + x0, m, 0.0f) +
                                         nyc * load(taps.row(taps.ny, r, c) + x0, m, 0.0f) +
                                         nzc * load(taps.row(taps.nz, r, c) + x0, m, 0.0f));
      p = pow_by_squaring(nd, e.normal_power, splat(1.0f));
    }
    const VF lo = load(taps.row(taps.low, r, c) + x0, m, 0.0f);
    const VF wt = select(m, bw * exp_nonpositive(-(dz * dz)) * p, splat(0.0f));
    s_sum = s_sum + wt * lo, w_sum = w_sum + wt;
  }
  const Mask weighted = gt(w_sum, splat(1e-6f));
  VF nearest = splat(1.0f), nearest_dz = splat(INFINITY);
  if (live & ~weighted)
    for (int t = 0; t < 4; ++t) {
      const int r = t >> 1, c = t & 1;
      const VF zj = load(taps.row(taps.z, r, c) + x0, live, INFINITY);
      const Mask m = live & ~sky(zj);
      const VF dz = select(m, (zj - z) * splat(inv_dz), splat(0.0f));
      const VF lo = load(taps.row(taps.low, r, c) + x0, m, 0.0f);
      const Mask closer = m & lt(abs(dz), nearest_dz);
      nearest_dz = select(closer, abs(dz), nearest_dz), nearest = select(closer, lo, nearest);
    }
  const VF res = select(weighted, s_sum / w_sum, nearest);
  store(out + i0, select(live, res, splat(1.0f)), valid);
}

inline void upsample(const GBuffer& full, const LowResGBuffer& lr, const float* low, float* out,
                     const UpsampleEdges& e = {}) {
  const int s = lr.scale, h = lr.g.height, W = full.width, H = full.height;
  const UpsampleFrame frame(full, s, e);
  std::vector<int> column(size_t(W + s));
  for (int X = 0; X < W + s; ++X) column[size_t(X)] = std::clamp(left_tap(X, s), 0, lr.g.width - 1);
  // Bands: runs of full-resolution rows with the same upper low row floor(v).
  std::vector<int> band_start, band_row;
  for (int y = 0; y < H; ++y) {
    const int fv = int(std::floor((float(y) - frame.half) * frame.inv_s));
    if (band_row.empty() || fv != band_row.back()) band_start.push_back(y), band_row.push_back(fv);
  }
  band_start.push_back(H);
  // Two bands a piece: the second reuses the first's lower row.
  parallel_for_dynamic(int64_t(band_row.size()), 2, [&](int64_t b0, int64_t b1) {
    thread_local TapRows taps;
    taps.low_row[0] = taps.low_row[1] = -1;  // rows of another frame, or of another piece
    for (int64_t b = b0; b < b1; ++b) {
      const int fv = band_row[size_t(b)];
      fill_tap_rows(lr, low, column.data(), W, std::clamp(fv, 0, h - 1), std::clamp(fv + 1, 0, h - 1), frame.normals,
                    taps);
      for (int y = band_start[size_t(b)]; y < band_start[size_t(b) + 1]; ++y)
        for (int x0 = 0; x0 < W; x0 += simd::kLanes) upsample_block(full, taps, e, frame, x0, y, out);
    }
  });
}

}  // namespace nns::screen_space
