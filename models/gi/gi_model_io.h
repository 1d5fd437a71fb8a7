#pragma once
// The generator blob (G.blob): kind "pix2pix-unet", a config that rebuilds the network
// (arch, residual, widths) and assembles its inputs exactly as in training (mode,
// CoordConv, face size, depth range, HDR scale), and the weights and BatchNorm
// statistics by name (docs/weights-format.md for the bytes). Blobs written before
// `arch` and `residual` existed load as pix2pix, not residual.
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "core/blob.h"
#include "models/gi/gi_inputs.h"
#include "models/gi/generator.h"
#include "models/gi/patchgan.h"
#include "nn/serialize.h"

namespace nns::gi {

inline constexpr const char* kGeneratorKind = "pix2pix-unet";

inline void put_generator_config(Blob& b, const GiInputConfig& in, const GeneratorConfig& gc, const std::string& loss) {
  const UnetConfig& u = gc.unet;
  b.set_config("arch", arch_name(gc.arch));
  b.set_config("residual", residual_name(gc.residual));
  b.set_config("mode", mode_name(in.mode));
  b.set_config("coordconv", in.coordconv ? "on" : "off");
  b.set_config("size", in.size);
  b.set_config("depth_max", double(in.norm.depth_max));
  b.set_config("hdr_scale", double(in.norm.hdr_scale));
  if (std::isfinite(in.norm.light_max)) b.set_config("light_max", double(in.norm.light_max));
  if (in.validation_fraction > 0) b.set_config("validation_fraction", in.validation_fraction);
  b.set_config("in_channels", u.in_channels);
  b.set_config("out_channels", u.out_channels);
  b.set_config("ngf", u.ngf);
  b.set_config("levels", u.levels);
  b.set_config("dropout", double(u.dropout));
  b.set_config("dropout_blocks", u.dropout_blocks);
  if (!u.batchnorm) b.set_config("batchnorm", "off");
  if (u.level_head > 0) b.set_config("level_head", u.level_head);
  if (u.level_head > 0 && u.level_energy) b.set_config("level_energy", "on");
  b.set_config("loss", loss);
}

inline void save_generator_blob(const std::string& path, GiGenerator<float>& g, const GiInputConfig& in,
                                const GeneratorConfig& gc, const std::string& loss) {
  Blob b(kGeneratorKind);
  put_generator_config(b, in, gc, loss);
  put_module(b, g, "G.");
  b.save(path);
}

struct LoadedGenerator {
  GiInputConfig inputs;
  GeneratorConfig config;
  std::unique_ptr<GiGenerator<float>> G;
  std::string loss;
};

inline LoadedGenerator load_generator(const std::string& path) {
  Blob b = Blob::load(path);
  if (b.kind() != kGeneratorKind)
    throw std::runtime_error(path + ": not a GI generator (kind '" + b.kind() + "', expected '" + kGeneratorKind +
                             "')");
  LoadedGenerator g;
  g.inputs.mode = parse_mode(b.config_string("mode"));
  g.inputs.coordconv = b.config_string("coordconv") == "on";
  // Integers checked as stored, then narrowed; the ranges are train-gan's flags'.
  g.inputs.size = b.config_int("size", 0, 16384);
  const auto positive = [&](const char* key) {
    const double v = b.config_double(key);  // finite as a float
    if (!(v > 0)) throw b.error("config key '" + std::string(key) + "' is " + b.config_string(key) + ", expected > 0");
    return float(v);
  };
  g.inputs.norm.depth_max = positive("depth_max");
  g.inputs.norm.hdr_scale = positive("hdr_scale");
  g.config.hdr_scale = g.inputs.norm.hdr_scale;
  if (b.has_config("light_max")) {
    double light_max = NAN;  // what is no finite float gets this key's own message
    try {
      light_max = b.config_double("light_max");
    } catch (const std::runtime_error&) {
    }
    if (!(std::isfinite(light_max) && light_max > 0))
      throw std::runtime_error(path + ": light_max " + b.config_string("light_max") +
                               " is not a positive finite number");
    g.inputs.norm.light_max = float(light_max);
  }
  if (b.has_config("validation_fraction")) {
    const double f = b.config_double("validation_fraction");
    if (!(f >= 0 && f < 1))
      throw std::runtime_error(path + ": validation_fraction " + std::to_string(f) + " is not in [0, 1)");
    g.inputs.validation_fraction = f;
  }
  UnetConfig& u = g.config.unet;
  try {
    if (b.has_config("arch")) g.config.arch = parse_arch(b.config_string("arch"));
    if (b.has_config("residual")) g.config.residual = parse_residual(b.config_string("residual"));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  u.in_channels = b.config_int("in_channels", 1, 64);
  u.out_channels = b.config_int("out_channels", 1, 64);
  u.ngf = b.config_int("ngf", 1, 1024);
  u.levels = b.config_int("levels", 1, 12);
  u.dropout = float(b.config_double("dropout"));
  if (!(u.dropout >= 0 && u.dropout < 1))
    throw b.error("config key 'dropout' is " + b.config_string("dropout") + ", expected 0 <= p < 1");
  u.dropout_blocks = b.config_int("dropout_blocks", 0, 12);
  u.batchnorm = !(b.has_config("batchnorm") && b.config_string("batchnorm") == "off");
  if (b.has_config("level_head")) u.level_head = b.config_int("level_head", 1, 4096);
  if (b.has_config("level_energy")) {
    const std::string e = b.config_string("level_energy");
    if (e != "on" && e != "off") throw b.error("config key 'level_energy' is '" + e + "', expected on or off");
    u.level_energy = e == "on";
  }
  if (u.in_channels != g.inputs.channels())
    throw std::runtime_error(path + ": in_channels " + std::to_string(u.in_channels) + " does not match coordconv " +
                             b.config_string("coordconv"));
  g.loss = b.config_string("loss");
  Rng rng(0);
  g.G = make_generator<float>(g.config, rng);
  get_module(b, *g.G, "G.");
  return g;
}

// The discriminator blob (D.blob, written beside G.blob by train-gan with the GAN loss):
// kind "patchgan", the PatchGanConfig and D's weights and BatchNorm statistics. Nothing
// in the project reads D back (the checkpoint resumes training); it is there so the
// whole pix2pix pair leaves the project (tools/nnshade_torch.py).
inline constexpr const char* kDiscriminatorKind = "patchgan";

inline void save_discriminator_blob(const std::string& path, PatchGan<float>& d) {
  Blob b(kDiscriminatorKind);
  b.set_config("in_channels", d.config().in_channels);
  b.set_config("ndf", d.config().ndf);
  b.set_config("layers", d.config().layers);
  put_module(b, d, "D.");
  b.save(path);
}

inline std::unique_ptr<PatchGan<float>> load_discriminator(const std::string& path) {
  Blob b = Blob::load(path);
  if (b.kind() != kDiscriminatorKind)
    throw b.error("holds a '" + b.kind() + "' model, expected '" + kDiscriminatorKind + "'");
  const PatchGanConfig c{b.config_int("in_channels", 1, 64), b.config_int("ndf", 1, 1024),
                         b.config_int("layers", 1, 10)};
  Rng rng(0);
  auto d = std::make_unique<PatchGan<float>>(c, rng);
  get_module(b, *d, "D.");
  return d;
}

// The generator's linear-light prediction of the front view, (3, h, w).
inline Tensor<float> predict_linear(LoadedGenerator& g, const GiSample& s, bool bn_batch_stats, bool dropout_on) {
  NoGradGuard ng;
  g.G->set_test_modes(bn_batch_stats, dropout_on);
  Tensor<float> y = crop2d(generate(*g.G, g.config, Var<float>(s.input)).value(), s.front);
  const HdrMapping hdr(g.inputs.norm.hdr_scale);
  Tensor<float> out({3, y.size(2), y.size(3)});
  const float cap = g.inputs.norm.light_max;  // inputs.h: no light beyond training's
  for (int64_t i = 0; i < out.numel(); ++i) out[i] = std::min(hdr.from_tanh(y[i]), cap);
  return out;
}

}  // namespace nns::gi
