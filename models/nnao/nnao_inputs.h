#pragma once
// What the NNAO network reads for one pixel, of either kind: the paper's w x w grid
// (nnao_features.h) or horizon profiles (horizon_features.h). Training points, the
// exact inference and the weights all go through this one description, so a model
// is always fed the inputs it was trained on.
//
// The network's output is the standardised AO minus a base: 0 for the grid kind; the
// horizons' own visibility for the horizon kind (horizon_features.h says why).
#include <cstdint>
#include <stdexcept>
#include <string>

#include "models/nnao/horizon_features.h"
#include "models/nnao/nnao_features.h"

namespace nns::nnao {

struct InputSpec {
  std::string kind = "grid";  // "grid" or "horizon"
  int window = 31;            // grid: w x w samples
  HorizonLayout horizon;      // horizon: directions x steps, bands

  bool is_horizon() const { return kind == "horizon"; }
  int64_t count() const { return is_horizon() ? horizon.features() : feature_count(window); }
  // Depth samples per pixel: what the exact inference reads from the G-buffer.
  int samples() const { return is_horizon() ? horizon.samples() : window * window; }
  // What is wrong with it, or "".
  std::string problem() const {
    if (kind == "grid") return window >= 1 && window <= 63 ? "" : "window must be 1..63";
    if (kind == "horizon") return horizon.problem();
    return "features must be 'grid' or 'horizon', not '" + kind + "'";
  }
  // The raw (unstandardised) inputs of pixel (px, py), which must not be sky.
  void compute(const screen_space::GBuffer& g, int px, int py, float* out) const {
    if (is_horizon()) compute_horizon_features(g, px, py, horizon, out);
    else compute_features(g, px, py, window, out);
  }
  // What the network's output (in AO units) is added to, from the raw inputs.
  float base(const float* raw) const { return is_horizon() ? raw[horizon_base_index(horizon)] : 0.0f; }
};

}  // namespace nns::nnao
