#pragma once
// Which pixels of a view a float path may legitimately compute differently: those
// with a sample whose exact (double) position lies within kEdgePx of a pixel edge,
// where nearest-pixel rounding (and the march's on-screen test, also at a half pixel)
// can go either way after float rounding in another order; for a horizon model also
// a sample within rounding of the AO radius, where it stops counting as an occluder;
// for a grid model a stratum index within rounding of an integer. Everything else is
// continuous in the inputs. Used to exempt (and count) such pixels when the GLSL and
// the CPU are compared.
#include <cmath>
#include <vector>

#include "models/nnao/horizon_features.h"
#include "models/nnao/nnao_inference.h"
#include "screen_space/gbuffer.h"

namespace nns::testing {

inline constexpr double kEdgePx = 1e-4;

inline bool near_pixel_edge(double c) { return std::abs(c - std::floor(c) - 0.5) < kEdgePx; }
inline bool near_integer(double v) { return std::abs(v - std::round(v)) < 1e-5 * std::max(1.0, std::abs(v)); }

// The strata and the jitter of infer_shader_style (nnao_inference.h), in double.
inline std::vector<bool> grid_edge_pixels(const screen_space::GBuffer& g, int w, int samples, uint32_t seed) {
  int mx, my;
  nnao::sample_grid(samples, w, mx, my);
  std::vector<bool> edge(size_t(g.pixels()), false);
  const double r = g.radius, step = w == 1 ? 0.0 : 2.0 * r / (w - 1);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const int64_t c = int64_t(y) * g.width + x;
      if (g.sky(c)) continue;
      const double kx = 0.5 * g.width / (double(g.sx) * g.z[c]), ky = 0.5 * g.height / (double(g.sy) * g.z[c]);
      const uint32_t h = screen_space::pixel_hash(uint32_t(x), uint32_t(y), seed);
      const double jx = screen_space::hash_unit(h), jy = screen_space::hash_unit(screen_space::pixel_hash(h, 1, seed));
      bool near = false;
      for (int b = 0; b < my && !near; ++b) {
        const double vj = (b + jy) * w / my;
        const int j = std::min(w - 1, int(vj));
        near = near_integer(vj) || near_pixel_edge(y + (j * step - r) * ky);
        for (int a = 0; a < mx && !near; ++a) {
          const double vi = (a + jx) * w / mx;
          near = near_integer(vi) || near_pixel_edge(x + (std::min(w - 1, int(vi)) * step - r) * kx);
        }
      }
      edge[size_t(c)] = near;
    }
  return edge;
}

// The march of compute_horizon_features (horizon_features.h), in double.
inline std::vector<bool> horizon_edge_pixels(const screen_space::GBuffer& g, const nnao::HorizonLayout& L) {
  std::vector<bool> edge(size_t(g.pixels()), false);
  auto position = [&](double px, double py, double d, double p[3]) {
    p[0] = ((px + 0.5) * 2.0 / g.width - 1) * g.sx * d, p[1] = (1 - (py + 0.5) * 2.0 / g.height) * g.sy * d, p[2] = -d;
  };
  const double r2 = double(g.radius) * g.radius;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const int64_t c = int64_t(y) * g.width + x;
      if (g.sky(c)) continue;
      double P[3], N[3] = {g.nx[c], g.ny[c], g.nz[c]};
      position(x, y, g.z[c], P);
      const double len = std::sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]);
      for (double& n : N) n /= len;
      const double R_px = g.radius * 0.5 * g.width / (double(g.sx) * g.z[c]);
      const double sl = std::hypot(N[0], N[1]);
      const double c0 = sl > 1e-4 ? N[0] / sl : 1, s0 = sl > 1e-4 ? -N[1] / sl : 0;
      bool near = std::abs(sl - 1e-4) < 1e-9;
      for (int k = 0; k < L.directions && !near; ++k) {
        const double a = 2 * M_PI * k / L.directions, ox = c0 * std::cos(a) - s0 * std::sin(a),
                     oy = s0 * std::cos(a) + c0 * std::sin(a);
        for (int s = 0; s < L.steps && !near; ++s) {
          const double f = (s + 0.5) / L.steps, t = 1 + f * f * R_px, qx = x + ox * t, qy = y + oy * t;
          near = near_pixel_edge(qx) || near_pixel_edge(qy);
          if (!g.on_screen(float(qx), float(qy))) break;
          const int ix = int(std::floor(qx + 0.5)), iy = int(std::floor(qy + 0.5));
          const float zq = g.z[int64_t(iy) * g.width + ix];
          if (data::is_sky(zq)) continue;
          double Q[3];
          position(ix, iy, zq, Q);
          const double d2 =
              (Q[0] - P[0]) * (Q[0] - P[0]) + (Q[1] - P[1]) * (Q[1] - P[1]) + (Q[2] - P[2]) * (Q[2] - P[2]);
          near = near || std::abs(d2 - r2) < 1e-5 * r2;
        }
      }
      edge[size_t(c)] = near;
    }
  return edge;
}

}  // namespace nns::testing
