#pragma once
// Data augmentation for train-gan (docs/gan.md, "Augmentation"), off unless asked for:
// each training sample may be replaced by another physically valid frame built from it.
//
//  * mirror (--aug-mirror), with probability 1/2: the frame seen in a mirror, camera x
//    -> -x. A single view is flipped left-right. A surround frame becomes the mirrored
//    cube: every face flipped left-right, left and right swapped; for an even face size
//    the global view of that cube is exactly the global view flipped left-right (the
//    layout is symmetric about the front face's centre, data/global_view.h; tested for
//    every even size), so both modes flip the input. Camera-space normals' x changes
//    sign; albedo, depth and light move with their pixels; the coordinate channels
//    stay (they say where a pixel is, not what it shows). The target moves the same way.
//  * exposure (--aug-exposure F): all light times one factor, log-uniform in [1/F, F];
//  * light colour (--aug-tint T): each channel of all light times t_c, log-uniform in
//    [1/T, T], the three rescaled to Rec. 709 luminance 1 (so a tint does not expose).
//    The renderer is linear in its light sources, and direct, env, emission and
//    indirect each scale by the light's factor: lights, sky and emitters scaled by s_c
//    give exactly these channels times s_c. So the lumination input (channels 7-9,
//    direct + emission + env) and the target (direct + env + indirect) are scaled in
//    linear light — through the HDR mapping, which is not linear — while albedo, normals
//    and depth, which do not depend on light, stay.
//
// What a sample gets is drawn from a stream of (seed, epoch, position in the epoch's
// order), as the order itself is: the same numbers with any thread count or rank count,
// and a resumed run replays it with no state in the checkpoint. Five numbers are drawn
// for every sample whatever is on, so turning jitter on does not move the mirrors.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/rng.h"
#include "models/gi/generator.h"
#include "models/gi/gi_inputs.h"

namespace nns::runs {

struct GiAugment {
  bool mirror = false;
  double exposure = 1;  // F >= 1; 1: off
  double tint = 1;      // T >= 1; 1: off
  bool any() const { return mirror || exposure > 1 || tint > 1; }
};

// What one sample gets.
struct AugmentDraw {
  bool mirror = false;
  float scale[3] = {1, 1, 1};  // per channel, applied to all light
};

inline AugmentDraw draw_augment(const GiAugment& a, Rng& rng) {
  AugmentDraw d;
  const double u_mirror = rng.uniform(), u_exposure = rng.uniform();
  double t[3];
  for (double& x : t) x = rng.uniform();
  d.mirror = a.mirror && u_mirror < 0.5;
  const double e = std::exp(std::log(a.exposure) * (2 * u_exposure - 1));
  for (double& x : t) x = std::exp(std::log(a.tint) * (2 * x - 1));
  const double lum = 0.2126 * t[0] + 0.7152 * t[1] + 0.0722 * t[2];
  for (int c = 0; c < 3; ++c) d.scale[c] = float(e * t[c] / lum);
  return d;
}

// The stream of sample `position` of epoch `epoch` of a run seeded `seed`.
inline Rng augment_rng(uint64_t seed, int epoch, int64_t position) {
  return Rng(seed ^ 0xA5A5'0000'6175'676Dull).fork(uint64_t(epoch)).fork(uint64_t(position));
}

namespace detail {
// Reverses every row of `planes` planes of h x w floats.
inline void flip_rows(float* p, int64_t planes, int64_t h, int64_t w) {
  for (int64_t r = 0; r < planes * h; ++r) std::reverse(p + r * w, p + (r + 1) * w);
}
inline Tensor<float> flipped(const Tensor<float>& t) {
  Tensor<float> o = t.clone();
  const int64_t w = o.size(o.dim() - 1), h = o.size(o.dim() - 2);
  flip_rows(o.data(), o.numel() / (w * h), h, w);
  return o;
}
}  // namespace detail

// The network input of the sample in a mirror (see above); throws for a global view of
// odd face size, whose layout is not symmetric (the front face is not centred).
inline Tensor<float> mirrored_input(const gi::GiSample& s) {
  const int64_t C = s.input.size(1), H = s.input.size(2), W = s.input.size(3);
  if (s.front.x0 + s.front.w + s.front.x0 != W)
    throw std::invalid_argument(
        s.name +
        ": mirroring (--aug-mirror, --mirror-average) needs the front view centred in the input (a global view of "
        "even face size), got face size " +
        std::to_string(s.front.w));
  Tensor<float> in = s.input.clone();
  // Albedo, normals, depth, lumination; not the coordinate channels (10-11) after them.
  detail::flip_rows(in.data(), std::min<int64_t>(C, 10), H, W);
  for (int64_t i = 0; i < H * W; ++i) in[3 * H * W + i] = -in[3 * H * W + i];
  return in;
}

// The sample in a mirror (see above): its input, targets, shading planes and geometry.
inline gi::GiSample mirrored(const gi::GiSample& s) {
  gi::GiSample o = s;
  o.input = mirrored_input(s);
  for (Tensor<float>* t : {&o.target, &o.albedo, &o.emission, &o.direct_env, &o.target_linear})
    if (t->defined()) *t = detail::flipped(*t);
  const int64_t w = s.front.w, h = s.front.h;
  for (int64_t r = 0; r < h && !o.geometry.empty(); ++r)
    std::reverse(o.geometry.begin() + r * w, o.geometry.begin() + (r + 1) * w);
  // The front view's geometry: the same world through a mirrored camera (x_cam -> -x_cam).
  data::View& g = o.front_geometry;
  for (auto& [name, plane] : g.channels) {
    for (int r = 0; r < g.height; ++r) std::reverse(plane.begin() + r * g.width, plane.begin() + (r + 1) * g.width);
    if (name == "N.X")
      for (float& x : plane) x = -x;
  }
  if (g.world_to_camera)
    for (int k = 0; k < 4; ++k) (*g.world_to_camera)[size_t(k)] = -(*g.world_to_camera)[size_t(k)];
  return o;
}

// All light of the sample times scale[c] per channel (see above); `hdr_scale` is the
// HDR mapping's k the sample was assembled with.
inline gi::GiSample light_scaled(const gi::GiSample& s, const float scale[3], float hdr_scale) {
  const gi::HdrMapping hdr(hdr_scale);
  const int64_t H = s.input.size(2), W = s.input.size(3), n = H * W;
  gi::GiSample o = s;
  o.input = s.input.clone();
  for (int c = 0; c < 3; ++c) {
    float* lum = o.input.data() + (gi::kLuminationChannel + c) * n;
    for (int64_t i = 0; i < n; ++i) lum[i] = hdr.to_tanh(scale[c] * hdr.from_tanh(lum[i]));
  }
  for (Tensor<float>* t : {&o.emission, &o.direct_env, &o.target_linear}) {
    if (!t->defined()) continue;
    *t = t->clone();
    const int64_t m = t->numel() / 3;
    for (int c = 0; c < 3; ++c)
      for (int64_t i = 0; i < m; ++i) (*t)[c * m + i] *= scale[c];
  }
  if (s.target.defined()) {
    o.target = s.target.clone();
    for (int64_t i = 0; i < o.target.numel(); ++i) o.target[i] = hdr.to_tanh(o.target_linear[i]);
  }
  return o;
}

// The sample as `d` says: mirrored, then its light scaled (the two commute).
inline gi::GiSample augmented(const gi::GiSample& s, const AugmentDraw& d, float hdr_scale) {
  gi::GiSample o = d.mirror ? mirrored(s) : s;
  if (d.scale[0] != 1 || d.scale[1] != 1 || d.scale[2] != 1) o = light_scaled(o, d.scale, hdr_scale);
  return o;
}

}  // namespace nns::runs
