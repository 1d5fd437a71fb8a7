#pragma once
// A low-resolution GI prediction brought up to full resolution the way engines bring up
// their half-resolution GI: a joint bilateral upsample (Kopf et al. 2007) guided by the
// full-resolution depth and normals. Only the indirect part is upsampled; direct and
// environment light are the renderer's inputs at full resolution, so their shadow edges
// stay sharp:
//     light_full = direct_env_full + upsample(light_low - direct_env_low).
//
// The low-resolution view is the box filter of the full one by an integer factor k
// (gi_samples.h's downsample_view): its pixel (x, y) averages the full pixels
// [k x, k x + k) x [k y, k y + k), so it stands at full-resolution coordinate
// (x + 1/2) k - 1/2. A full pixel X takes its four nearest low pixels with bilinear
// weights times exp(-(dz / (depth z))^2) max(0, n.n')^normal_power, dz the depth
// difference relative to its own depth (a GI view has no AO radius to measure it in),
// so light does not bleed across a depth step or a crease. Where every neighbour is
// stopped (a thin object no low pixel saw) it takes the neighbour of nearest depth; a
// sky pixel (no light to predict) takes the plain bilinear value.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/tensor.h"
#include "data/view.h"

namespace nns::gi {

struct GuidedUpsampleEdges {
  float depth = 0.05f;   // the depth term's scale, relative to the pixel's depth
  int normal_power = 8;  // max(0, n.n')^power
};

// low: (C, h, w). low_geo, full_geo: views with Z, N.X, N.Y, N.Z of h x w and H x W,
// H = k h, W = k w. Returns (C, H, W).
inline Tensor<float> guided_upsample(const Tensor<float>& low, const data::View& low_geo, const data::View& full_geo,
                                     const GuidedUpsampleEdges& e = {}) {
  const int C = int(low.size(0)), h = int(low.size(1)), w = int(low.size(2));
  const int H = full_geo.height, W = full_geo.width;
  if (low_geo.width != w || low_geo.height != h || W % w || H % h || W / w != H / h)
    throw std::runtime_error("guided_upsample: " + std::to_string(w) + "x" + std::to_string(h) + " does not go into " +
                             std::to_string(W) + "x" + std::to_string(H) + " by one integer factor");
  const int k = W / w;
  const auto &zl = low_geo.channel("Z"), &nxl = low_geo.channel("N.X"), &nyl = low_geo.channel("N.Y"),
             &nzl = low_geo.channel("N.Z");
  const auto &zf = full_geo.channel("Z"), &nxf = full_geo.channel("N.X"), &nyf = full_geo.channel("N.Y"),
             &nzf = full_geo.channel("N.Z");
  Tensor<float> out({C, H, W});
  const int64_t n_low = int64_t(h) * w, n_full = int64_t(H) * W;
  for (int Y = 0; Y < H; ++Y)
    for (int X = 0; X < W; ++X) {
      const double u = (X + 0.5) / k - 0.5, v = (Y + 0.5) / k - 0.5;
      const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
      const double ax = u - x0, ay = v - y0;
      const int64_t i = int64_t(Y) * W + X;
      const float z = zf[size_t(i)];
      const bool sky = data::is_sky(z);
      double wt[4], w_sum = 0, nearest_dz = INFINITY;
      int64_t tap[4], nearest = -1;
      for (int t = 0; t < 4; ++t) {
        const int tx = std::clamp(x0 + (t & 1), 0, w - 1), ty = std::clamp(y0 + (t >> 1), 0, h - 1);
        const int64_t j = int64_t(ty) * w + tx;
        tap[t] = j;
        const double bw = ((t & 1) ? ax : 1 - ax) * ((t >> 1) ? ay : 1 - ay);
        const float zj = zl[size_t(j)];
        if (sky || data::is_sky(zj)) {
          wt[t] = sky ? bw : 0.0;
          w_sum += wt[t];
          continue;
        }
        const double dz = (double(zj) - z) / (double(e.depth) * z);
        const double nd =
            std::max(0.0, double(nxf[size_t(i)]) * nxl[size_t(j)] + double(nyf[size_t(i)]) * nyl[size_t(j)] +
                              double(nzf[size_t(i)]) * nzl[size_t(j)]);
        wt[t] = bw * std::exp(-dz * dz) * std::pow(nd, e.normal_power);
        w_sum += wt[t];
        if (std::abs(dz) < nearest_dz) nearest_dz = std::abs(dz), nearest = j;
      }
      for (int c = 0; c < C; ++c) {
        const float* lc = low.data() + c * n_low;
        double s = 0;
        if (w_sum > 1e-9) {
          for (int t = 0; t < 4; ++t) s += wt[t] * lc[tap[t]];
          s /= w_sum;
        } else {
          s = nearest >= 0 ? lc[nearest] : 0.0;  // every low neighbour sky: nothing to take
        }
        out[c * n_full + i] = float(s);
      }
    }
  return out;
}

}  // namespace nns::gi
