#pragma once
// NNAO's second input kind: horizon profiles instead of the paper's w x w grid.
//
// Why: the grid features (nnao_features.h) reach the network's first layer, a linear
// map, as raw normal and depth differences; but AO is a *maximum* along each direction
// (the highest occluder hides everything below it; Jimenez et al. 2016, eq. 3), which
// a linear layer over a fixed grid only approximates for the geometry it has seen.
// Trained on the 16 training families, the grid model scores 1.7x the MSE of tuned
// HBAO on the families it never saw (docs/nnao.md). Here the maxima are taken before
// the network, and the network learns what classical methods hard-code.
//
// For a non-sky centre pixel with view-space position P, unit normal N and AO radius r
// covering R_px pixels on screen at its depth:
//   * D directions on the screen, evenly spaced, the first along the normal's screen
//     projection (the features do not change when the image rotates about the view
//     axis); each marched `steps` samples out to R_px, sample s at
//     t_s = 1 + ((s + 0.5) / steps)^2 R_px pixels (denser near the pixel, as GTAO);
//   * a sample: d = its position - P; sky, off-screen (the march stops) and |d| > r
//     (beyond the ground truth's ray length) add nothing; else its elevation above the
//     tangent plane, sin e = N.d / |d|;
//   * features: for direction k and band b (the steps cut into `bands` equal runs), the
//     highest elevation reached up to the end of band b (a running maximum from 0: the
//     horizon as a function of distance); then N.V (how much the surface faces the
//     camera) and log2(1 + R_px) / 8 (how many pixels the radius spans; at inference
//     held at most at radius_term_max, below); then, per
//     band, the horizons' own cosine-weighted visibility 1 - mean_k sin^2 e_k (an
//     occluder at elevation e hides the fraction sin^2 e of its azimuth's
//     cosine-weighted rays).
// The network predicts AO minus the last band's visibility (horizon_base): where it
// has learned nothing, it falls back on the physics rather than on the training
// families' mean. Choosing between variants on validation families (docs/nnao.md):
// the residual target took validation MSE from 0.0048 to 0.0040; a 4x4 rotation noise
// with a blur, a march in the tangent plane, and a reach beyond r did not help.
// Layout: out[k * bands + b], then N.V, the radius term, then the bands' visibilities.
#include <cmath>
#include <cstdint>
#include <string>

#include "screen_space/gbuffer.h"

namespace nns::nnao {

struct HorizonLayout {
  int directions = 16, steps = 8, bands = 4;  // the default preset's (runs/ao/nnao_train_options.h)
  // The radius term's ceiling (blob key radius_term_max; absent or 0: none). Training
  // sees the term unclamped; a trained model's inference holds it at 0.6 (R_px ~ 27 px).
  // Why: where the radius spans more pixels than that, the training views were mostly
  // close-ups inside rooms, and the network learned to darken there whatever the
  // horizons say; on a close convex shape it painted a lit sphere grey (docs/nnao.md).
  // Held at 0.6, it trusts the horizons: validation families, 3 seeds, MSE -13%, flicker
  // 0.75x -> 0.69x the truth's. Clamping in training too made it worse (+15%).
  float radius_term_max = INFINITY;
  int samples() const { return directions * steps; }
  int64_t features() const { return int64_t(directions) * bands + 2 + bands; }
  // What is wrong with the layout, or "" if it is usable.
  std::string problem() const {
    const std::string d = std::to_string(directions), st = std::to_string(steps), b = std::to_string(bands);
    if (directions < 1 || directions > 64) return "directions " + d + " is out of range 1..64";
    if (steps < 1 || steps > 64) return "steps " + st + " is out of range 1..64";
    if (bands < 1 || bands > steps || steps % bands != 0) return "bands " + b + " must divide steps " + st;
    if (!(radius_term_max > 0)) return "radius_term_max " + std::to_string(radius_term_max) + " must be above 0";
    return "";
  }
};

// The feature index of the last band's visibility: what the network's output is added to.
inline int64_t horizon_base_index(const HorizonLayout& L) { return L.features() - 1; }

// Writes L.features() floats for centre pixel (px, py), which must not be sky.
inline void compute_horizon_features(const screen_space::GBuffer& g, int px, int py, const HorizonLayout& L,
                                     float* out) {
  const int64_t c = int64_t(py) * g.width + px;
  const Vec3 P = g.position(px, py), N = screen_space::normalize_or_facing(g.normal(c));
  const float r = g.radius, r2 = r * r;
  const float R_px = r * 0.5f * float(g.width) / (g.sx * g.z[c]);
  // The normal's direction on the screen (y down); facing the camera, any start will do.
  const float sxn = N.x, syn = -N.y, sl = std::sqrt(sxn * sxn + syn * syn);
  const float c0 = sl > 1e-4f ? sxn / sl : 1.0f, s0 = sl > 1e-4f ? syn / sl : 0.0f;
  const int per_band = L.steps / L.bands;
  for (int k = 0; k < L.directions; ++k) {
    const float a = 6.2831853f * float(k) / float(L.directions);
    const float ca = std::cos(a), sa = std::sin(a);
    const float ox = c0 * ca - s0 * sa, oy = s0 * ca + c0 * sa;
    float horizon = 0;
    bool on_screen = true;
    for (int s = 0; s < L.steps; ++s) {
      if (on_screen) {
        const float f = (float(s) + 0.5f) / float(L.steps);
        const float t = 1.0f + f * f * R_px;
        const float qx = float(px) + ox * t, qy = float(py) + oy * t;
        on_screen = g.on_screen(qx, qy);
        if (on_screen) {
          int jx, jy;
          g.clamped_pixel(qx, qy, jx, jy);
          const int64_t j = int64_t(jy) * g.width + jx;
          if (!g.sky(j)) {
            const Vec3 d = g.position(jx, jy) - P;
            const float d2 = dot(d, d);
            if (d2 > 0 && d2 <= r2) horizon = std::fmax(horizon, dot(N, d) / std::sqrt(d2));
          }
        }
      }
      if ((s + 1) % per_band == 0) out[k * L.bands + (s + 1) / per_band - 1] = horizon;
    }
  }
  const int64_t extra = int64_t(L.directions) * L.bands;
  out[extra] = dot(N, screen_space::normalize_or_facing(-1.0f * P));
  out[extra + 1] = std::fmin(L.radius_term_max, std::log2(1.0f + R_px) / 8.0f);
  for (int b = 0; b < L.bands; ++b) {
    float occluded = 0;
    for (int k = 0; k < L.directions; ++k) occluded += out[k * L.bands + b] * out[k * L.bands + b];
    out[extra + 2 + b] = 1.0f - occluded / float(L.directions);
  }
}

}  // namespace nns::nnao
