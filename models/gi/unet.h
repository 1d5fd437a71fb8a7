#pragma once
// The pix2pix U-Net generator (Isola et al. 2017, as the surround-aware thesis uses it),
// built from one recursive skip block like pix2pix's UnetSkipConnectionBlock:
//
//   x ─ [LeakyReLU 0.2] ─ Conv 4x4 s2 p1 ─ [BN] ─ (inner block) ─ ReLU ─ ConvT 4x4 s2 p1
//     ─ [BN] ─ [Dropout 0.5] ─┬─ concat(x, ·)      (every block but the outermost)
//                             └─ Tanh              (outermost)
//
// Level i = 0 (outermost) .. L-1 (innermost) has ngf * min(2^i, 8) channels inside.
// Choices, following the pix2pix *paper* and the thesis's
// Table 4.1/4.2 where they differ from pix2pix's code:
//  * no BatchNorm on the outermost down conv (the first layer) nor on the innermost down
//    conv (its output is 1x1 at 256x256 and batch 1: BN would zero it);
//  * a conv has a bias only where no BatchNorm follows it: the outermost and innermost
//    down convs and the outermost up conv (pix2pix's code also drops the bias of the two
//    down convs; a bias there is what a plain conv would have);
//  * Dropout 0.5 on the three innermost up blocks, the innermost included (the paper's
//    decoder "CD512-CD512-CD512-C512-..."; the code puts it on the three blocks outside
//    the innermost instead).
// The spatial size must be divisible by 2^L.
#include <memory>
#include <stdexcept>
#include <string>

#include "models/gi/generator_base.h"
#include "models/gi/frame_level_features.h"
#include "models/gi/pix2pix_layers.h"
#include "nn/functional/elementwise.h"
#include "nn/functional/reshape.h"
#include "nn/linear.h"

namespace nns::gi {

struct UnetConfig {
  int in_channels = 12;
  int out_channels = 3;
  int ngf = 64;
  int levels = 8;
  float dropout = 0.5f;
  int dropout_blocks = 3;  // the innermost up blocks with dropout
  // false: no BatchNorm anywhere (and so a bias on every conv). A measured deviation
  // (docs/gan.md): BatchNorm at batch 1 normalises every image by its own statistics,
  // which hides the absolute light level from every level but the outermost skip.
  bool batchnorm = true;
  // > 0: a frame-level head of this hidden width (UnetGenerator::level_gain); 0: none.
  int level_head = 0;
  // The head also reads the view's light energy (frame_level_features.h).
  bool level_energy = false;
};

template <class T = float>
class UnetBlock : public Module<T> {
 public:
  // `outer` channels in and out of this block (in = `input` for the outermost),
  // `inner` channels after its down conv.
  UnetBlock(const UnetConfig& c, int level, Rng& rng) : level_(level), levels_(c.levels) {
    const bool outermost = level == 0, innermost = level == c.levels - 1;
    const int inner = c.ngf * std::min(1 << std::min(level, 3), 8);
    const int outer = outermost ? c.out_channels : c.ngf * std::min(1 << std::min(level - 1, 3), 8);
    const int input = outermost ? c.in_channels : outer;
    const bool down_bn = !outermost && !innermost && c.batchnorm;
    down_ = this->register_module("down", make_conv<T>(input, inner, /*bias=*/!down_bn, rng));
    if (down_bn) down_norm_ = this->register_module("down_norm", make_bn<T>(inner));
    if (!innermost) sub_ = this->register_module("sub", std::make_shared<UnetBlock<T>>(c, level + 1, rng));
    const int up_in = innermost ? inner : 2 * inner;
    const bool up_bn = !outermost && c.batchnorm;
    up_ = this->register_module("up", make_conv_transpose<T>(up_in, outer, /*bias=*/!up_bn, rng));
    if (up_bn) up_norm_ = this->register_module("up_norm", make_bn<T>(outer));
    if (!outermost && level >= c.levels - c.dropout_blocks && c.dropout > 0)
      dropout_ = this->register_module("dropout", make_dropout<T>(c.dropout, rng.next_u64()));
  }

  Var<T> forward(const Var<T>& x) override {
    Var<T> h = level_ == 0 ? x : leaky_relu(x, T(0.2));
    h = down_->forward(h);
    if (down_norm_) h = down_norm_->forward(h);
    if (sub_) h = sub_->forward(h);
    h = up_->forward(relu(h));
    if (up_norm_) h = up_norm_->forward(h);
    if (dropout_) h = dropout_->forward(h);
    if (level_ == 0) return tanh_act(h);
    return concat_channels(std::vector<Var<T>>{x, h});
  }

  // Test-time behaviour, independently of Module::train(): batch or running BN
  // statistics, dropout on or off (pix2pix tests with both as in training).
  void set_test_modes(bool bn_batch_stats, bool dropout_on) {
    for (auto* bn : {down_norm_.get(), up_norm_.get()})
      if (bn) bn->train(bn_batch_stats);
    if (dropout_) dropout_->train(dropout_on);
    if (sub_) sub_->set_test_modes(bn_batch_stats, dropout_on);
  }

 private:
  int level_, levels_;
  std::shared_ptr<Module<T>> down_, down_norm_, up_, up_norm_, dropout_;
  std::shared_ptr<UnetBlock<T>> sub_;
};

template <class T = float>
class UnetGenerator : public GiGenerator<T> {
 public:
  UnetGenerator(const UnetConfig& c, Rng& rng) : config_(c) {
    if (c.levels < 1 || c.ngf < 1 || c.in_channels < 1 || c.out_channels < 1)
      throw std::invalid_argument("UnetGenerator: levels, ngf and channels must be >= 1");
    root_ = this->register_module("model", std::make_shared<UnetBlock<T>>(c, 0, rng));
    init_pix2pix(*this, rng);
    if (c.level_energy && c.in_channels < kLuminationChannel + 3)
      throw std::invalid_argument("UnetGenerator: the level head's energy needs the lumination channels 7-9");
    if (c.level_head > 0) {  // after the U-Net's draws: without the head nothing changes
      head_in_ = this->register_module(
          "level_head_in",
          std::make_shared<Linear<T>>(rng, frame_level_feature_count(c.in_channels, c.level_energy), c.level_head));
      head_out_ =
          this->register_module("level_head_out", std::make_shared<Linear<T>>(rng, c.level_head, c.out_channels));
      for (auto* t : {&head_out_->weight.value(), &head_out_->bias.value()})
        for (auto& v : *t) v = T(0);  // gain 1 at the start: the U-Net trains as without the head
    }
  }

  // The frame's level: one gain per output channel, exp(MLP(frame_level_features(x))),
  // for the predicted indirect light. The U-Net's
  // BatchNorm at batch 1 normalises every feature map by its own statistics, so a
  // frame-wide level reaches the output only through the outermost skip; this path
  // carries it past the normalisation. Undefined without the head.
  Var<T> level_gain(const Var<T>& x) override {
    if (!head_in_) return Var<T>();
    const int64_t B = x.size(0);
    Tensor<T> f = frame_level_features(x.value(), config_.level_energy);
    Var<T> h = leaky_relu(head_in_->forward(Var<T>(std::move(f))), 0.2);
    return reshape(exp(head_out_->forward(h)), Shape{B, config_.out_channels, 1, 1});
  }

  Var<T> forward(const Var<T>& x) override {
    const int64_t m = int64_t(1) << config_.levels;
    if (x.shape().dim() != 4 || x.size(1) != config_.in_channels || x.size(2) % m || x.size(3) % m)
      throw std::invalid_argument("UnetGenerator: input " + x.shape().str() + " needs " +
                                  std::to_string(config_.in_channels) +
                                  " channels and a size divisible by 2^levels = " + std::to_string(m));
    return root_->forward(x);
  }

  // Switches to evaluation with the chosen test-time behaviour; train() undoes it.
  void set_test_modes(bool bn_batch_stats, bool dropout_on) override {
    this->eval();
    root_->set_test_modes(bn_batch_stats, dropout_on);
  }
  int64_t size_multiple() const override { return int64_t(1) << config_.levels; }

  const UnetConfig& config() const { return config_; }

 private:
  UnetConfig config_;
  std::shared_ptr<UnetBlock<T>> root_;
  std::shared_ptr<Linear<T>> head_in_, head_out_;
};

}  // namespace nns::gi
