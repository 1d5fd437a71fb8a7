#pragma once
// Which GI generator to build (--arch) and how its output becomes the predicted light.
//
//  * pix2pix      the pix2pix U-Net (unet.h), ngf and levels as given;
//  * deepshading  Deep Shading's U-Net (deep_shading_unet.h): u0 = ngf, the same number of
//                 resolutions as the pix2pix net has (levels + 1: its input and every
//                 down conv's output), so a sweep point compares like with like.
//
// --residual (a deviation from pix2pix, docs/gan.md): the network predicts a correction
// to the light it is given instead of the light itself. lum = input channels 7-9 =
// direct + emission + env, mapped (gi_inputs.h): the target minus the indirect light.
//
//   off     prediction = G(x)                              pix2pix
//   mapped  prediction = lum + 2 G(x)                      a correction in Tanh range
//   linear  prediction = map(unmap(lum) + unmap_eps(G(x)))  G predicts the indirect light
//
// A plain generator must rebuild the sharp direct light through its bottleneck; a
// residual one gets it for free and spends its capacity on the indirect part, which is
// what `direct+env+ambient` adds as a constant. `mapped` adds in Tanh range, where a
// small error on a bright pixel is a large error in linear light (the mapping is flat
// there); `linear` adds in linear light, like the ambient reference and like physics
// (indirect light is smooth and non-negative whether or not a pixel is directly lit):
// unmap_eps(g) = k (g+1)/2 / ((1-g)/2 + eps) is the HDR mapping's inverse with its pole
// moved out of Tanh's range (eps = 1e-3: at most ~1000 k). In `mapped` the factor 2 lets
// the correction reach every target from every input (both in [-1, 1]). lum is data, a
// constant in the graph: gradients flow through G alone. The loss sees the prediction
// in Tanh range in every mode, so the trainer does not care which one is used.
#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "models/gi/deep_shading_unet.h"
#include "models/gi/unet.h"
#include "nn/functional/elementwise.h"

namespace nns::gi {

enum class GiArch { pix2pix, deepshading };
inline GiArch parse_arch(const std::string& s) {
  if (s == "pix2pix") return GiArch::pix2pix;
  if (s == "deepshading") return GiArch::deepshading;
  throw std::invalid_argument("unknown generator architecture '" + s + "' (pix2pix|deepshading)");
}
inline const char* arch_name(GiArch a) { return a == GiArch::pix2pix ? "pix2pix" : "deepshading"; }

enum class GiResidual { off, mapped, linear };
inline GiResidual parse_residual(const std::string& s) {
  if (s == "off") return GiResidual::off;
  if (s == "mapped" || s == "on") return GiResidual::mapped;
  if (s == "linear") return GiResidual::linear;
  throw std::invalid_argument("unknown residual mode '" + s + "' (off|mapped|linear)");
}
inline const char* residual_name(GiResidual r) {
  return r == GiResidual::off ? "off" : r == GiResidual::mapped ? "mapped" : "linear";
}

struct GeneratorConfig {
  GiArch arch = GiArch::pix2pix;
  UnetConfig unet;  // in/out channels, ngf, levels, dropout (dropout: pix2pix only)
  GiResidual residual = GiResidual::off;
  float hdr_scale = 1.0f;  // the HDR mapping's k (residual linear)
  static constexpr float kLinearEps = 1e-3f;

  DeepShadingConfig deep_shading() const {
    DeepShadingConfig d;
    d.in_channels = unet.in_channels;
    d.out_channels = unet.out_channels;
    d.u0 = unet.ngf;
    d.levels = unet.levels + 1;
    return d;
  }
};

template <class T = float>
std::unique_ptr<GiGenerator<T>> make_generator(const GeneratorConfig& c, Rng& rng) {
  if (c.residual != GiResidual::off && (c.unet.in_channels < kLuminationChannel + 3 || c.unet.out_channels != 3))
    throw std::invalid_argument("residual generator: needs the lumination input channels 7-9 and 3 outputs");
  if (c.arch == GiArch::pix2pix) return std::make_unique<UnetGenerator<T>>(c.unet, rng);
  return std::make_unique<DeepShadingUnet<T>>(c.deep_shading(), rng);
}

// The generator's prediction of the light (Tanh range) for the whole input.
template <class T>
Var<T> generate(GiGenerator<T>& g, const GeneratorConfig& c, const Var<T>& x) {
  Var<T> y = g.forward(x);
  if (c.residual == GiResidual::off) return y;
  const int64_t n = x.size(2) * x.size(3), ch = x.size(1);
  Tensor<T> lum({x.size(0), 3, x.size(2), x.size(3)});
  for (int64_t b = 0; b < x.size(0); ++b)
    for (int64_t k = 0; k < 3 * n; ++k) lum[b * 3 * n + k] = x.value()[(b * ch + kLuminationChannel) * n + k];
  if (c.residual == GiResidual::mapped) return y * T(2) + Var<T>(std::move(lum));
  const T k = T(c.hdr_scale), eps = T(GeneratorConfig::kLinearEps);
  for (auto& v : lum) {  // back to linear light: k u / (1 - u), u = (v + 1) / 2
    T u = std::clamp(T(0.5) * (v + T(1)), T(0), T(1) - eps);
    v = k * u / (T(1) - u);
  }
  Var<T> indirect = div(affine(y, T(0.5) * k, T(0.5) * k), affine(y, T(-0.5), T(0.5) + eps));
  if (Var<T> gain = g.level_gain(x); gain.defined()) indirect = indirect * gain;
  Var<T> light = indirect + Var<T>(std::move(lum));
  return affine(rdiv(k, affine(light, T(1), k)), T(-2), T(1));  // 2 L/(L+k) - 1
}

}  // namespace nns::gi
