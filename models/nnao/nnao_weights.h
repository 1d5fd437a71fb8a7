#pragma once
// A trained NNAO network as plain arrays, for inference, the shader export and the
// filter images — read straight from `nnao.blob`, no autograd involved.
//
// Blob layout (kind "nnao"; written by the trainer through the module tree):
//   config: window, hidden, radius (training radius; 0 = each view's aoRadius),
//           dropout, gamma, target ("ao": 1 = unoccluded; "ao-minus-horizon-visibility":
//           the output is added to the horizons' visibility, nnao_inputs.h),
//           features ("grid" when absent, or "horizon" with directions, steps, bands,
//           blur_passes: 1 when absent, blur_depth: 0.1 and blur_normal_power: 8
//           when absent, radius_term_max: 0 = none when absent, downsample: 1, 2 or 4,
//           1 when absent)
//   fc0.weight (H, F)  fc0.bias (H)  act0.alpha (H)  act0.beta (H)   (F: nnao_inputs.h)
//   fc1.weight (H, H) ...  fc2 ...       fc3.weight (1, H) fc3.bias (1) act3.alpha/beta (1)
//   feature_mean (F)  feature_std (F)  target_stats (2: mean, std)
// The network maps standardised features to the standardised AO of the centre pixel.
//
// The feature standardisation is folded into layer 0 (W0' = W0 / std, b0' = b0 -
// W0' . mean) so inference multiplies raw features: that also makes the shader's
// subsampled dot product cheaper and leaves the mean term exact.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/blob.h"
#include "models/nnao/nnao_inputs.h"
#include "screen_space/pow_by_squaring.h"

namespace nns::nnao {

// The edge-stopping terms of NNAO's bilateral blur (nnao_inference.h): a tap weighs
// exp(-(dz / (depth r))^2) max(0, n.n')^normal_power besides its Gaussian. The first
// horizon models had depth 0.1 and power 8, which their blobs mean by leaving the keys
// out; the default's looser 0.3 and 2 blur across more of the small depth steps and
// soft creases where the raw output flickers (validation families, 3 seeds: flicker
// 0.87x -> 0.75x the ground truth's for MSE +1.7%; docs/nnao.md, "Flicker").
struct BlurEdges {
  float depth = 0.1f;
  int normal_power = 8;
};

// The blur's normal term is x^p by squaring (screen_space/pow_by_squaring.h).
using screen_space::pow_by_squaring;

struct NnaoWeights {
  int hidden = 4;
  InputSpec input;   // what layer 0 reads: the grid (input.window) or horizon profiles
  float radius = 0;  // 0: each view's own aoRadius
  // Horizon models: how many times the exact inference applies the bilateral blur
  // (nnao_inference.h), chosen on validation families (docs/nnao.md, "Flicker").
  int blur_passes = 1;
  BlurEdges blur_edges;  // horizon models; the grid keeps the defaults
  // Horizon models: the frame is marched, run through the network and blurred at 1/s of
  // its resolution in each axis, then upsampled guided by the full-resolution depth and
  // normals (screen_space/low_resolution.h); the model was trained on points of frames
  // downsampled the same way, against the full-resolution truth. 1: full resolution.
  int downsample = 1;
  std::vector<float> w0;          // (hidden, F) with the standardisation folded in
  std::vector<float> b0;          // (hidden)
  std::vector<float> w[3], b[3];  // layers 1..3: (hidden, hidden), (hidden, hidden), (1, hidden)
  std::vector<float> alpha[4], beta[4];
  float target_mean = 0, target_std = 1;

  int64_t features() const { return input.count(); }

  static float prelu(float x, float a, float bt) { return x > 0 ? bt * x : a * x; }

  // Layers 1..3 and the de-standardisation, from layer 0's pre-activations h0 (hidden);
  // `base` is the inputs' base (InputSpec::base), added before the clamp to [0, 1].
  float head(const float* h0, float base = 0) const {
    float a[64], c[64];
    for (int k = 0; k < hidden; ++k) a[k] = prelu(h0[k], alpha[0][size_t(k)], beta[0][size_t(k)]);
    int n = hidden;
    for (int l = 0; l < 3; ++l) {
      const int out = l == 2 ? 1 : hidden;
      for (int o = 0; o < out; ++o) {
        float s = b[l][size_t(o)];
        for (int i = 0; i < n; ++i) s += w[l][size_t(o) * n + i] * a[i];
        c[o] = prelu(s, alpha[l + 1][size_t(o)], beta[l + 1][size_t(o)]);
      }
      std::copy(c, c + out, a);
      n = out;
    }
    float ao = a[0] * target_std + target_mean + base;
    return ao < 0 ? 0 : (ao > 1 ? 1 : ao);
  }

  static NnaoWeights from_blob(const Blob& blob) {
    if (blob.kind() != "nnao") throw blob.error("holds a '" + blob.kind() + "' model, expected 'nnao'");
    NnaoWeights m;
    read_config(blob, m);
    if (const std::string p = m.input.problem(); !p.empty()) throw blob.error(p);
    fold_standardisation(blob, m);
    for (int l = 0; l < 3; ++l) {
      const int64_t out = l == 2 ? 1 : m.hidden;
      m.w[l] = tensor(blob, "fc" + std::to_string(l + 1) + ".weight", {out, m.hidden});
      m.b[l] = tensor(blob, "fc" + std::to_string(l + 1) + ".bias", {out});
    }
    for (int l = 0; l < 4; ++l) {
      const int64_t n = l == 3 ? 1 : m.hidden;
      m.alpha[l] = tensor(blob, "act" + std::to_string(l) + ".alpha", {n});
      m.beta[l] = tensor(blob, "act" + std::to_string(l) + ".beta", {n});
    }
    return m;
  }
  static NnaoWeights load(const std::string& path) { return from_blob(Blob::load(path)); }

 private:
  static std::vector<float> tensor(const Blob& blob, const std::string& name, Shape s) {
    std::vector<float> v(size_t(s.numel()));
    blob.read(name, s, v.data());
    return v;
  }

  // The network's size and the feature layout; every number checked as stored, then
  // narrowed (a window of 4294967303 read as 7).
  static void read_config(const Blob& blob, NnaoWeights& m) {
    m.input.window = blob.config_int("window", 0, 63);  // horizon models store 0 (unused)
    m.hidden = blob.config_int("hidden", 1, 64);
    m.radius = float(blob.config_double("radius"));
    if (!(m.radius >= 0))
      throw blob.error("radius " + blob.config_string("radius") +
                       " out of range: expected >= 0 (0: each view's aoRadius)");
    if (!blob.has_config("features")) return;
    m.input.kind = blob.config_string("features");
    auto layout_int = [&](const char* key) {  // range-checked before it becomes an int
      const int64_t v = blob.config_int(key);
      if (v < 1 || v > 64) throw blob.error(std::string(key) + " " + std::to_string(v) + " out of range 1..64");
      return int(v);
    };
    if (!m.input.is_horizon()) return;
    m.input.horizon = {layout_int("directions"), layout_int("steps"), layout_int("bands")};
    // Absent in the first horizon models' blobs: one pass, the first edge terms.
    if (blob.has_config("blur_passes")) {
      const int64_t p = blob.config_int("blur_passes");
      if (p < 1 || p > 16) throw blob.error("blur_passes " + std::to_string(p) + " out of range 1..16");
      m.blur_passes = int(p);
    }
    // A number in [lo, hi] (NaN is not), named with its range when it is not.
    auto ranged_double = [&](const char* key, double lo, double hi, const char* range) {
      double v = NAN;  // what is no finite number is out of the range too, said with it
      try {
        v = blob.config_double(key);
      } catch (const std::runtime_error&) {
      }
      if (!(v >= lo && v <= hi))
        throw blob.error(std::string(key) + " " + blob.config_string(key) + " out of range " + range);
      return float(v);
    };
    if (blob.has_config("radius_term_max"))  // 0: no ceiling
      if (const float v = ranged_double("radius_term_max", 0, 100, "0..100"); v > 0)
        m.input.horizon.radius_term_max = v;
    if (blob.has_config("blur_depth")) m.blur_edges.depth = ranged_double("blur_depth", 0.01, 100, "0.01..100");
    if (blob.has_config("downsample")) {  // absent in blobs made before it: full resolution
      const int64_t d = blob.config_int("downsample");
      if (d != 1 && d != 2 && d != 4) throw blob.error("downsample " + std::to_string(d) + " must be 1, 2 or 4");
      m.downsample = int(d);
    }
    if (blob.has_config("blur_normal_power")) {
      const int64_t p = blob.config_int("blur_normal_power");
      if (p < 0 || p > 64) throw blob.error("blur_normal_power " + std::to_string(p) + " out of range 0..64");
      m.blur_edges.normal_power = int(p);
    }
  }

  // Layer 0 with the feature standardisation folded in: w0 / std, b0 - w0 . mean / std,
  // so that inference takes the raw features.
  static void fold_standardisation(const Blob& blob, NnaoWeights& m) {
    const int64_t F = m.features(), H = m.hidden;
    std::vector<float> w0 = tensor(blob, "fc0.weight", {H, F}), b0 = tensor(blob, "fc0.bias", {H});
    std::vector<float> mean = tensor(blob, "feature_mean", {F}), stdv = tensor(blob, "feature_std", {F});
    std::vector<float> ts = tensor(blob, "target_stats", {2});
    m.target_mean = ts[0];
    m.target_std = ts[1];
    // The trainer stores a constant's std as 1 (nnao_points.h): a zero or negative one
    // is no trained model's, and dividing by it makes the weights infinite.
    if (!(m.target_std > 0))
      throw blob.error("tensor 'target_stats' holds a standard deviation of " + std::to_string(ts[1]) +
                       ", expected > 0");
    for (int64_t f = 0; f < F; ++f)
      if (!(stdv[size_t(f)] > 0))
        throw blob.error("tensor 'feature_std' holds " + std::to_string(stdv[size_t(f)]) + " at index " +
                         std::to_string(f) + ", expected > 0");
    m.w0.resize(size_t(H * F));
    m.b0.resize(size_t(H));
    for (int64_t k = 0; k < H; ++k) {
      double bias = b0[size_t(k)];
      for (int64_t f = 0; f < F; ++f) {
        float wf = w0[size_t(k * F + f)] / stdv[size_t(f)];
        m.w0[size_t(k * F + f)] = wf;
        bias -= double(wf) * mean[size_t(f)];
      }
      m.b0[size_t(k)] = float(bias);
    }
    // A tiny std can still overflow the folded layer 0.
    for (int64_t i = 0; i < H * F; ++i)
      if (!std::isfinite(m.w0[size_t(i)]))
        throw blob.error("tensor 'fc0.weight' divided by 'feature_std' overflows at index " + std::to_string(i));
    for (int64_t k = 0; k < H; ++k)
      if (!std::isfinite(m.b0[size_t(k)]))
        throw blob.error("tensor 'fc0.bias' with the standardisation folded in overflows at index " +
                         std::to_string(k));
  }
};

}  // namespace nns::nnao
