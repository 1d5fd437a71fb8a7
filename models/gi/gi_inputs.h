#pragma once
// Assembling the generator's 12 input channels and its target from G-buffer views
// (docs/dataset-format.md), for one front view (--mode front, Deep Illumination) or a
// surround frame merged into the global view (--mode surround, the thesis).
//
// Input channels, in this order, all in about [-1, 1] as pix2pix expects:
//   0-2  albedo                       2a - 1
//   3-5  camera-space normal          as stored (front camera's space for every face)
//   6    depth                        2 min(z / depth_max, 1) - 1; sky = 1 (thesis 4.3.1)
//   7-9  lumination = direct + emission + env   HDR-mapped (hdr_mapping.h), thesis eq. 4.2
//   10-11 coordinates (CoordConv)     2c - 1 of (x, y) for a single view, of (phi, theta)
//                                     for the global view (data/coord_maps.h); absent when
//                                     CoordConv is off (10 channels)
// Target (front view only): direct + env + indirect, HDR-mapped into Tanh's range. The
// shaded image is albedo * target + emission (the emission is not the network's job).
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/tensor.h"
#include "data/view.h"
#include "models/gi/crop.h"
#include "models/gi/hdr_mapping.h"

namespace nns::gi {

// The first channel of each three-channel group above.
constexpr int kAlbedoChannel = 0, kNormalChannel = 3, kLuminationChannel = 7;

enum class GiMode { front, surround };

inline GiMode parse_mode(const std::string& s) {
  if (s == "front") return GiMode::front;
  if (s == "surround") return GiMode::surround;
  throw std::invalid_argument("unknown GI mode '" + s + "' (front|surround)");
}
inline const char* mode_name(GiMode m) { return m == GiMode::front ? "front" : "surround"; }

// Data-set constants every sample of a model is assembled with; stored in the model blob.
struct GiNormalisation {
  float depth_max = 1.0f;  // depth mapped to 1 at and beyond this distance
  float hdr_scale = 1.0f;  // HdrMapping's k
  // The brightest target light of the training split: predictions are capped there when
  // mapped back to linear light. Near Tanh's end the inverse mapping x = k u / (1 - u)
  // turns a tiny output error into an unbounded one (u = 1 - 2^-20 is 1e6 k); light
  // brighter than anything in training is never a good answer. Infinity: no cap.
  float light_max = INFINITY;
};

struct GiInputConfig {
  GiMode mode = GiMode::surround;
  bool coordconv = true;
  int size = 0;  // face size the views are reduced to (0: as stored), gi_samples.h
  GiNormalisation norm;
  // Share of train/'s scenes carved out as the validation split (data/validation_split.h)
  // before anything was fitted; stored in G.blob so eval-gi carves the same scenes.
  double validation_fraction = 0;
  int channels() const { return coordconv ? 12 : 10; }
};

// One training or test example.
struct GiSample {
  std::string name;  // the view file or the frame folder
  std::string scene;
  Tensor<float> input;   // (1, C, H, W)      the generator's input
  Tensor<float> target;  // (1, 3, h, w)      Tanh range, the front view; undefined without ground truth
  Rect front;            // the front view inside the input (all of it in front mode)
  // The front view, linear HDR, (3, h, w): for shading, references and metrics.
  Tensor<float> albedo, emission, direct_env, target_linear;  // target_linear: as target
  std::vector<uint8_t> geometry;                              // h * w, 1 where there is geometry (not sky)
  // Share of the frame's direct light on the front face (gi_samples.h); NaN for a single
  // view, where the surroundings are unknown.
  float front_direct_share = NAN;
  // The front view's Z and N.X/Y/Z with its fovY and worldToCamera (no lighting): what
  // reprojects one frame of a camera path onto the previous one for eval-gi's flicker.
  data::View front_geometry;
};

// The geometry part of a view (see GiSample::front_geometry).
inline data::View geometry_of(const data::View& v) {
  data::View g;
  g.source = v.source, g.scene = v.scene, g.width = v.width, g.height = v.height;
  g.fov_y_deg = v.fov_y_deg, g.world_to_camera = v.world_to_camera;
  for (const char* c : {"Z", "N.X", "N.Y", "N.Z"})
    if (v.has(c)) g.add_channel(c) = v.channel(c);
  return g;
}

// Rejects NaN/Inf in a light or material channel with a message naming file and channel.
inline const std::vector<float>& finite_channel(const data::View& v, const std::string& name) {
  const auto& c = v.channel(name);
  for (size_t i = 0; i < c.size(); ++i)
    if (!std::isfinite(c[i]))
      throw std::runtime_error(v.source + ": channel '" + name + "' has a non-finite value at pixel " +
                               std::to_string(i % size_t(v.width)) + "," + std::to_string(i / size_t(v.width)));
  return c;
}

// Optional light channels (emission, env) are zero when absent, as the spec says.
inline std::vector<float> rgb_or_zero(const data::View& v, const std::string& base, int c) {
  std::string name = base + "." + "RGB"[c];
  if (!v.has(name)) return std::vector<float>(size_t(v.width) * size_t(v.height), 0.0f);
  return finite_channel(v, name);
}

// The 10 per-view planes (coordinates excluded) of one view, (10, h, w), mapped as above.
inline Tensor<float> view_planes(const data::View& v, const GiNormalisation& norm) {
  const int64_t n = int64_t(v.width) * v.height;
  Tensor<float> t({10, v.height, v.width});
  float* p = t.data();
  HdrMapping hdr(norm.hdr_scale);
  for (int c = 0; c < 3; ++c) {
    const auto& a = finite_channel(v, std::string("albedo.") + "RGB"[c]);
    for (int64_t i = 0; i < n; ++i) p[(kAlbedoChannel + c) * n + i] = 2.0f * a[size_t(i)] - 1.0f;
  }
  const char* normals[3] = {"N.X", "N.Y", "N.Z"};
  for (int c = 0; c < 3; ++c) {
    const auto& nc = finite_channel(v, normals[c]);
    for (int64_t i = 0; i < n; ++i) p[(kNormalChannel + c) * n + i] = nc[size_t(i)];
  }
  data::check_depth(v);
  const auto& z = v.channel("Z");
  for (int64_t i = 0; i < n; ++i) {
    float d = data::is_sky(z[size_t(i)]) ? 1.0f : std::min(z[size_t(i)] / norm.depth_max, 1.0f);
    p[6 * n + i] = 2.0f * d - 1.0f;
  }
  for (int c = 0; c < 3; ++c) {
    const auto& dir = finite_channel(v, std::string("direct.") + "RGB"[c]);
    auto em = rgb_or_zero(v, "emission", c), env = rgb_or_zero(v, "env", c);
    for (int64_t i = 0; i < n; ++i)
      p[(kLuminationChannel + c) * n + i] = hdr.to_tanh(dir[size_t(i)] + em[size_t(i)] + env[size_t(i)]);
  }
  return t;
}

// Fills the linear front-view planes that shade a prediction (albedo, emission,
// direct + env, the geometry mask) from the front view; needs no ground truth, so
// gi-infer assembles a user's frame with this alone.
inline void fill_front_shading(GiSample& s, const data::View& v) {
  const int64_t n = int64_t(v.width) * v.height;
  s.albedo = Tensor<float>({3, v.height, v.width});
  s.emission = Tensor<float>({3, v.height, v.width});
  s.direct_env = Tensor<float>({3, v.height, v.width});
  for (int c = 0; c < 3; ++c) {
    const auto& a = finite_channel(v, std::string("albedo.") + "RGB"[c]);
    const auto& dir = finite_channel(v, std::string("direct.") + "RGB"[c]);
    auto em = rgb_or_zero(v, "emission", c), env = rgb_or_zero(v, "env", c);
    for (int64_t i = 0; i < n; ++i) {
      size_t k = size_t(i);
      s.albedo[c * n + i] = a[k];
      s.emission[c * n + i] = em[k];
      s.direct_env[c * n + i] = dir[k] + env[k];
    }
  }
  data::check_depth(v);
  const auto& z = v.channel("Z");
  s.geometry.resize(size_t(n));
  for (int64_t i = 0; i < n; ++i) s.geometry[size_t(i)] = data::is_sky(z[size_t(i)]) ? 0 : 1;
}

// Fills the shading planes and the target of `s` from the front view (needs indirect.*).
// The target sums dir + env + ind in this order, as it always has: training numbers
// stay bitwise the same.
inline void fill_front_targets(GiSample& s, const data::View& v, const GiNormalisation& norm) {
  fill_front_shading(s, v);
  const int64_t n = int64_t(v.width) * v.height;
  HdrMapping hdr(norm.hdr_scale);
  s.target_linear = Tensor<float>({3, v.height, v.width});
  s.target = Tensor<float>({1, 3, v.height, v.width});
  for (int c = 0; c < 3; ++c) {
    const auto& dir = finite_channel(v, std::string("direct.") + "RGB"[c]);
    const auto& ind = finite_channel(v, std::string("indirect.") + "RGB"[c]);
    auto env = rgb_or_zero(v, "env", c);
    for (int64_t i = 0; i < n; ++i) {
      size_t k = size_t(i);
      float t = dir[k] + env[k] + ind[k];
      s.target_linear[c * n + i] = t;
      s.target[c * n + i] = hdr.to_tanh(t);
    }
  }
}

}  // namespace nns::gi
