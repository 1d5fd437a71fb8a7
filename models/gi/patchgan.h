#pragma once
// The PatchGAN discriminator (pix2pix's NLayerDiscriminator): a fully convolutional
// classifier whose every output logit judges one receptive-field patch of its input.
//
//   Conv(in, ndf, 4, s2, p1) + LeakyReLU 0.2                       (no BN on the first)
//   for n = 1 .. layers-1: Conv(ndf*min(2^(n-1),8), ndf*min(2^n,8), 4, s2, p1) + BN + LReLU
//   Conv(.., ndf*min(2^layers,8), 4, s1, p1) + BN + LReLU
//   Conv(.., 1, 4, s1, p1)                                          (logits, no sigmoid)
//
// layers = 3 gives the 70x70 receptive field. Conditioned as a cGAN: its input is the
// generator's input concatenated with the real or generated light (12 + 3 channels).
// A conv has a bias only where no BN follows (first and last). The output is logits:
// the loss applies the sigmoid itself, in the stable BCE-with-logits form.
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "models/gi/pix2pix_layers.h"

namespace nns::gi {

struct PatchGanConfig {
  int in_channels = 15;
  int ndf = 64;
  int layers = 3;
};

template <class T = float>
class PatchGan : public Module<T> {
 public:
  PatchGan(const PatchGanConfig& c, Rng& rng) : config_(c) {
    if (c.layers < 0 || c.ndf < 1 || c.in_channels < 1)
      throw std::invalid_argument("PatchGan: layers >= 0, ndf >= 1 and channels >= 1 needed");
    auto width = [&](int n) { return c.ndf * std::min(1 << std::min(n, 3), 8); };
    int ch = c.in_channels;
    for (int n = 0; n <= c.layers; ++n) {
      const bool last_strided = n < c.layers;
      const int out = width(n);
      Stage s;
      s.conv = this->register_module("conv" + std::to_string(n), make_conv<T>(ch, out, /*bias=*/n == 0, rng,
                                                                              /*stride=*/last_strided ? 2 : 1));
      if (n > 0) s.norm = this->register_module("norm" + std::to_string(n), make_bn<T>(out));
      stages_.push_back(s);
      ch = out;
    }
    head_ = this->register_module("head", make_conv<T>(ch, 1, /*bias=*/true, rng, /*stride=*/1));
    init_pix2pix(*this, rng);
  }

  // input (N, in_channels, H, W) -> logits (N, 1, H', W')
  Var<T> forward(const Var<T>& x) override {
    if (x.shape().dim() != 4 || x.size(1) != config_.in_channels)
      throw std::invalid_argument("PatchGan: input " + x.shape().str() + " needs " +
                                  std::to_string(config_.in_channels) + " channels");
    Var<T> h = x;
    for (auto& s : stages_) {
      h = s.conv->forward(h);
      if (s.norm) h = s.norm->forward(h);
      h = leaky_relu(h, T(0.2));
    }
    return head_->forward(h);
  }

  // Side of the square patch one output logit sees (70 for layers = 3).
  static int receptive_field(int layers) {
    int rf = 1;       // walk back from one output pixel: rf = rf * stride + (k - stride)
    rf = rf * 1 + 3;  // head, stride 1
    rf = rf * 1 + 3;  // last conv, stride 1
    for (int n = 0; n < layers; ++n) rf = rf * 2 + 2;  // strided convs
    return rf;
  }

  const PatchGanConfig& config() const { return config_; }

 private:
  struct Stage {
    std::shared_ptr<Module<T>> conv, norm;
  };
  PatchGanConfig config_;
  std::vector<Stage> stages_;
  std::shared_ptr<Module<T>> head_;
};

}  // namespace nns::gi
