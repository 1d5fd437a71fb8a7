#pragma once
// Deep Shading's U-Net (Nalbach et al. 2017, Sec. 4.2), the non-adversarial baseline the
// issue names next to the pix2pix U-Net:
//
//   level 0:  x ─ Conv kxk ─ LReLU ─────────────────────────────┐ (skip)
//   level 1:      mean-pool 2x2 ─ Conv ─ LReLU ──────────┐      │
//   ...                                                   │      │
//   level L-1 (coarsest, one step): mean-pool ─ Conv ─ LReLU     │
//   up:  bilinear 2x ─ concat(skip of the same level) ─ Conv ─ LReLU ... ─ Tanh at level 0
//
// u0 = ngf kernels on level 0, doubling per level (the paper's "factor of two"); every
// convolution has the same extent (3x3 here, padding 1) and a bias; no BatchNorm, no
// dropout. Deviations from the paper, for this code base: the level-0 up step outputs
// the 3 light channels through Tanh (the paper's output is linear; ours must land in
// the HDR mapping's Tanh range like the pix2pix generator's, so the two train on the same
// targets), convolution groups (2^n on level n) are not used (our Conv2d has none; the
// grouped network is a subset of this one), and weights start from PyTorch's default
// conv initialisation (Caffe's is not given in the paper).
// The spatial size must be divisible by 2^(L-1).
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "models/gi/generator_base.h"
#include "nn/conv2d.h"
#include "nn/functional/activations.h"
#include "nn/functional/concat.h"
#include "nn/functional/resample.h"

namespace nns::gi {

struct DeepShadingConfig {
  int in_channels = 12;
  int out_channels = 3;
  int u0 = 16;     // kernels on level 0
  int levels = 5;  // resolutions, the coarsest included
  int kernel = 3;
  double slope = 0.01;  // leaky ReLU (Maas et al. 2013's 0.01)
};

template <class T = float>
class DeepShadingUnet : public GiGenerator<T> {
 public:
  DeepShadingUnet(const DeepShadingConfig& c, Rng& rng) : config_(c) {
    if (c.levels < 1 || c.u0 < 1 || c.in_channels < 1 || c.out_channels < 1 || c.kernel % 2 == 0)
      throw std::invalid_argument("DeepShadingUnet: levels, u0, channels >= 1 and an odd kernel needed");
    const int pad = c.kernel / 2;
    for (int l = 0; l < c.levels; ++l) {
      const int in = l == 0 ? c.in_channels : width(l - 1);
      down_.push_back(this->register_module("down" + std::to_string(l),
                                            std::make_shared<Conv2d<T>>(rng, in, width(l), c.kernel, 1, pad, true)));
    }
    for (int l = 0; l + 1 < c.levels; ++l) {
      const int out = l == 0 ? c.out_channels : width(l);
      up_.push_back(this->register_module(
          "up" + std::to_string(l),
          std::make_shared<Conv2d<T>>(rng, width(l + 1) + width(l), out, c.kernel, 1, pad, true)));
    }
    if (c.levels == 1)  // no up branch: a 1-level net maps level 0's features to the output
      up_.push_back(this->register_module(
          "up0", std::make_shared<Conv2d<T>>(rng, width(0), c.out_channels, c.kernel, 1, pad, true)));
  }

  Var<T> forward(const Var<T>& x) override {
    const int64_t m = int64_t(1) << (config_.levels - 1);
    if (x.shape().dim() != 4 || x.size(1) != config_.in_channels || x.size(2) % m || x.size(3) % m)
      throw std::invalid_argument("DeepShadingUnet: input " + x.shape().str() + " needs " +
                                  std::to_string(config_.in_channels) +
                                  " channels and a size divisible by 2^(levels-1) = " + std::to_string(m));
    std::vector<Var<T>> skips;
    Var<T> h = x;
    for (int l = 0; l < config_.levels; ++l) {
      if (l > 0) h = avg_pool2x2(h);
      h = leaky_relu(down_[size_t(l)]->forward(h), config_.slope);
      skips.push_back(h);
    }
    if (config_.levels == 1) return tanh_act(up_[0]->forward(h));
    for (int l = config_.levels - 2; l >= 0; --l) {
      h = concat_channels(std::vector<Var<T>>{upsample_bilinear2x(h), skips[size_t(l)]});
      h = up_[size_t(l)]->forward(h);
      h = l == 0 ? tanh_act(h) : leaky_relu(h, config_.slope);
    }
    return h;
  }

  // No BatchNorm, no dropout: every test mode is the same network.
  void set_test_modes(bool, bool) override { this->eval(); }
  int64_t size_multiple() const override { return int64_t(1) << (config_.levels - 1); }
  const DeepShadingConfig& config() const { return config_; }

 private:
  int width(int level) const { return config_.u0 << level; }

  DeepShadingConfig config_;
  std::vector<std::shared_ptr<Module<T>>> down_, up_;
};

}  // namespace nns::gi
