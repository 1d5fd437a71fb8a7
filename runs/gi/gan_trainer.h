#pragma once
// One pix2pix training iteration (Isola et al. 2017; thesis pseudocode 2), its state and
// its checkpoint.
//
//   fake     = G(x)                              x: the 12 input channels (gi_inputs.h)
//   D step:  L_D = 1/2 [BCE(D(x_f, y), 1) + BCE(D(x_f, fake_f), 0)]   fake detached
//   G step:  L_G = BCE(D(x_f, fake_f), 1) + lambda * (|fake_f - y|_1 + w DSSIM(fake_f, y))
//            (w = dssim_weight; 0 is pix2pix), plus gradient_weight x gradient_l1 when > 0
//
// `_f` is the front region: in surround mode G sees and predicts the whole global view
// but only the front view has a ground truth, so the L1 term and the discriminator look
// at the front rectangle of input and output (the discriminator is conditioned on the
// input channels there, coordinates included). BCE is computed from logits (stable);
// the D loss is halved as in pix2pix so D learns at half G's pace.
// --loss l1 / dssim train G alone on the reconstruction term / on DSSIM (no D; l1 is the
// default, runs/gi/train_gan.h says why).
//
// Every loss and every gradient is checked for NaN/Inf; the first one found throws
// NonFiniteError naming the step and the tensor, before any weight is touched, so the
// last checkpoint on disk stays the last good state.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/blob.h"
#include "core/kernels/finite.h"
#include "models/gi/crop.h"
#include "models/gi/gi_inputs.h"
#include "models/gi/gi_losses.h"
#include "models/gi/patchgan.h"
#include "models/gi/gi_model_io.h"
#include "optim/adam.h"
#include "optim/lr_schedule.h"
#include "optim/checkpoint.h"
#include "optim/weight_average.h"
#include "runs/non_finite.h"
#include "runs/training_run.h"

namespace nns::runs {

enum class GiLoss { gan, l1, dssim };
inline GiLoss parse_loss(const std::string& s) {
  if (s == "gan") return GiLoss::gan;
  if (s == "l1") return GiLoss::l1;
  if (s == "dssim") return GiLoss::dssim;
  throw std::invalid_argument("unknown loss '" + s + "' (gan|l1|dssim)");
}
inline const char* loss_name(GiLoss l) { return l == GiLoss::gan ? "gan" : l == GiLoss::l1 ? "l1" : "dssim"; }

struct GanTrainConfig {
  gi::GiInputConfig inputs;
  int ngf = 32, levels = 6;  // generator
  gi::GiArch arch = gi::GiArch::pix2pix;
  gi::GiResidual residual = gi::GiResidual::off;  // predict a correction to the input light (generator.h)
  bool g_batchnorm = true;                        // BatchNorm in the pix2pix U-Net (unet.h)
  float g_dropout = 0.5f;                         // dropout in its three innermost up blocks (0: none)
  int level_head = 0;                             // hidden width of the frame-level head (unet.h; 0: none)
  bool level_energy = false;                      // the head also reads the view's light energy (unet.h)
  int ndf = 32, d_layers = 3;                     // discriminator
  GiLoss loss = GiLoss::gan;
  double lambda = 100, lr = 2e-4, beta1 = 0.5, beta2 = 0.999;
  double lr_d = 0;  // the discriminator's learning rate; <= 0: the same as lr (pix2pix)
  double d_lr() const { return lr_d > 0 ? lr_d : lr; }
  // gan and l1 losses: reconstruction = L1 + dssim_weight * DSSIM (0: pix2pix's L1 alone).
  // SSIM is the metric L1 trains least for (docs/gan.md).
  double dssim_weight = 0;
  // Adds this times the L1 of the images' finite differences (gi_losses.h), for the
  // contact detail that per-pixel L1 leaves soft: 1 lowered the validation MSE by 18% on
  // the textured face-128 data (docs/results/2026-12-05-gi-gradient-loss.md).
  double gradient_weight = 0;
  // > 0: G.blob holds an exponential moving average of G's weights with this decay
  // (optim/weight_average.h) instead of the last step's weights.
  double ema = 0;
  int epochs = 10, epochs_decay = 10;  // constant lr, then linear decay to 0
  uint64_t seed = 1;

  gi::UnetConfig unet() const {
    gi::UnetConfig u;
    u.in_channels = inputs.channels();
    u.ngf = ngf;
    u.levels = levels;
    u.batchnorm = g_batchnorm;
    u.dropout = g_dropout;
    u.level_head = level_head;
    u.level_energy = level_energy;
    return u;
  }
  gi::GeneratorConfig generator() const { return {arch, unet(), residual, inputs.norm.hdr_scale}; }
  gi::PatchGanConfig patchgan() const { return {inputs.channels() + 3, ndf, d_layers}; }
  int total_epochs() const { return epochs + epochs_decay; }
};

using runs::check_finite;
using runs::NonFiniteError;

struct StepLosses {
  double d = 0, d_real = 0, d_fake = 0;  // discriminator (0 without one)
  double g_adv = 0, g_rec = 0, g = 0;    // rec = L1 or DSSIM term, g = total
};

// Reports a discriminator that wins outright: over a window of steps its loss stays near
// 0 while the generator's adversarial loss climbs. The generator then gets no useful
// adversarial gradient (pix2pix's known failure), only the L1 term teaches it.
class DiscriminatorWatch {
 public:
  static constexpr int kWindow = 100;
  static constexpr double kNearZero = 0.05;

  // Returns true when the window just closed is a "D wins" window.
  bool add(double d_loss, double g_adv) {
    sum_d_ += d_loss, sum_g_ += g_adv;
    if (++n_ < kWindow) return false;
    double mean_d = sum_d_ / n_, mean_g = sum_g_ / n_;
    bool wins = mean_d < kNearZero && prev_g_ >= 0 && mean_g > prev_g_;
    prev_g_ = mean_g;
    n_ = 0, sum_d_ = sum_g_ = 0;
    if (wins) ++windows_won_;
    return wins;
  }
  int64_t windows_won() const { return windows_won_; }

  void save(Blob& b) const {
    double s[4] = {sum_d_, sum_g_, prev_g_, double(n_)};
    b.put("watch.state", Shape{4}, s);
    b.put_i64("watch.windows_won", windows_won_);
  }
  void load(const Blob& b) {
    double s[4];
    b.read("watch.state", Shape{4}, s);
    sum_d_ = s[0], sum_g_ = s[1], prev_g_ = s[2], n_ = int(s[3]);
    windows_won_ = b.get_i64("watch.windows_won");
  }

 private:
  double sum_d_ = 0, sum_g_ = 0, prev_g_ = -1;
  int n_ = 0;
  int64_t windows_won_ = 0;
};

class GanTrainer {
 public:
  explicit GanTrainer(const GanTrainConfig& c)
      : config(c),
        init_rng_(c.seed),
        G_(gi::make_generator<float>(c.generator(), init_rng_)),
        G(*G_),
        schedule_(LrSchedule::linear(c.lr, c.epochs, c.epochs_decay)),
        schedule_d_(LrSchedule::linear(c.d_lr(), c.epochs, c.epochs_decay)) {
    opt_g_ = std::make_unique<Adam<float>>(G.parameters(), AdamOptions{.lr = c.lr, .beta1 = c.beta1, .beta2 = c.beta2});
    if (c.loss == GiLoss::gan) {
      D = std::make_unique<gi::PatchGan<float>>(c.patchgan(), init_rng_);
      opt_d_ = std::make_unique<Adam<float>>(D->parameters(),
                                             AdamOptions{.lr = c.d_lr(), .beta1 = c.beta1, .beta2 = c.beta2});
    }
    if (c.ema > 0) ema_ = std::make_unique<WeightAverage<float>>(G.parameters(), c.ema);
  }

  // Sets both learning rates for `epoch` (0-based); call at the start of each epoch.
  void begin_epoch(int epoch) {
    schedule_.apply(*opt_g_, epoch);
    if (opt_d_) schedule_d_.apply(*opt_d_, epoch);
  }
  double lr() const { return opt_g_->lr(); }

  StepLosses train_step(const gi::GiSample& s) {
    StepLosses out = forward_backward(s, /*checked=*/true);
    update();
    return out;
  }

  // A step accumulated over micro-batches (runs/distributed/grad_sync.h): each sample's
  // losses and gradients alone, unchecked (a rank must not stop while the others wait for
  // its gradients); then apply_accumulated() checks the mean losses and the mean
  // gradients, the same on every rank, and updates. BatchNorm keeps per-image statistics.
  StepLosses accumulate_sample(const gi::GiSample& s) { return forward_backward(s, /*checked=*/false); }
  void apply_accumulated(const StepLosses& mean) {
    const int64_t k = step_ + 1;
    if (D && !std::isfinite(mean.d)) throw NonFiniteError(k, "discriminator loss");
    if (!std::isfinite(mean.g)) throw NonFiniteError(k, "generator loss");
    if (D) check_gradients(*D, k, "D.");
    check_gradients(G, k, "G.");
    update();
  }
  // What an accumulated step averages, in a fixed order: G's parameters, then D's; and
  // the dropout generators.
  std::vector<Var<float>> trained_parameters() {
    std::vector<Var<float>> p = G.parameters();
    if (D)
      for (auto& v : D->parameters()) p.push_back(v);
    return p;
  }
  std::vector<Tensor<float>*> buffers() {
    std::vector<Tensor<float>*> b;
    for (auto& [name, t] : G.named_buffers()) b.push_back(t);
    if (D)
      for (auto& [name, t] : D->named_buffers()) b.push_back(t);
    return b;
  }
  std::vector<Rng*> rngs() {
    std::vector<Rng*> r;
    for (auto& [name, g] : G.named_rngs()) r.push_back(g);
    if (D)
      for (auto& [name, g] : D->named_rngs()) r.push_back(g);
    return r;
  }

  // The losses of one sample and their gradients (into cleared buffers); `checked`: a
  // NaN or Inf throws NonFiniteError before any gradient is used.
  StepLosses forward_backward(const gi::GiSample& s, bool checked) {
    G.train();
    if (D) D->train();
    const int64_t k = step_ + 1;  // 1-based step number in messages
    StepLosses out;
    Var<float> x(s.input);
    Var<float> y(s.target);
    Var<float> fake = gi::generate(G, config.generator(), x);
    Var<float> fake_f = gi::crop2d(fake, s.front);
    if (checked) check_finite(fake.value(), k, "generator output");

    Var<float> x_f;
    if (D) {
      x_f = Var<float>(gi::crop2d(s.input, s.front));
      // D step: real pairs towards 1, generated (detached) towards 0.
      set_requires_grad(*D, true);
      Var<float> real_logits = D->forward(pair(x_f, y));
      Var<float> fake_logits = D->forward(pair(x_f, Var<float>(fake_f.value())));
      Var<float> d_real = gi::bce_with_logits_target(real_logits, 1.0f);
      Var<float> d_fake = gi::bce_with_logits_target(fake_logits, 0.0f);
      Var<float> d_loss = (d_real + d_fake) * 0.5f;
      out.d_real = d_real.value()[0], out.d_fake = d_fake.value()[0], out.d = d_loss.value()[0];
      if (checked && !std::isfinite(out.d)) throw NonFiniteError(k, "discriminator loss");
      opt_d_->zero_grad();
      d_loss.backward();
      if (checked) check_gradients(*D, k, "D.");
    }

    // G step: fool D (its parameters frozen: no gradient is wasted on them) + lambda*L1.
    Var<float> rec = config.loss == GiLoss::dssim ? gi::dssim_tanh(fake_f, y) : l1_loss(fake_f, y);
    if (config.loss != GiLoss::dssim && config.dssim_weight > 0)
      rec = rec + gi::dssim_tanh(fake_f, y) * float(config.dssim_weight);
    if (config.loss != GiLoss::dssim && config.gradient_weight > 0)
      rec = rec + gi::gradient_l1(fake_f, y) * float(config.gradient_weight);
    Var<float> g_loss = config.loss == GiLoss::gan ? rec * float(config.lambda) : rec;
    out.g_rec = rec.value()[0];
    if (D) {
      set_requires_grad(*D, false);
      Var<float> adv = gi::bce_with_logits_target(D->forward(pair(x_f, fake_f)), 1.0f);
      out.g_adv = adv.value()[0];
      g_loss = adv + g_loss;
    }
    out.g = g_loss.value()[0];
    if (checked && !std::isfinite(out.g)) {
      if (D) set_requires_grad(*D, true);
      throw NonFiniteError(k, "generator loss");
    }
    opt_g_->zero_grad();
    // D was frozen when the adversarial term was recorded, so the graph holds no edge
    // into D's parameters (core/autograd.h fixes a node's edges when its op is
    // recorded): this backward leaves D's gradients as D's own step left them.
    g_loss.backward();
    if (D) set_requires_grad(*D, true);
    if (checked) check_gradients(G, k, "G.");
    return out;
  }

  // G's prediction of the front view, Tanh range (1, 3, h, w), in the given test mode,
  // with the weights G.blob holds (the average, with ema).
  Tensor<float> predict(const gi::GiSample& s, bool bn_batch_stats, bool dropout_on) {
    NoGradGuard ng;
    AveragedWeights averaged(ema_.get());
    auto saved = snapshot_buffers();  // batch-stat BN would move the running statistics
    G.set_test_modes(bn_batch_stats, dropout_on);
    Tensor<float> out = gi::crop2d(gi::generate(G, config.generator(), Var<float>(s.input)).value(), s.front);
    restore_buffers(saved);
    G.train();
    return out;
  }

  int64_t step() const { return step_; }
  DiscriminatorWatch& watch() { return watch_; }

  // Everything a resumed run needs to continue bitwise: weights, BN statistics, dropout
  // generators (all by name), both Adam states and the watch; the run layer adds the
  // step, the epochs done and the configuration (run_config) that a resume must match.
  void add_to(Checkpoint<float>& ck) {
    ck.add_module("G", G).add_optimizer("adam_G", *opt_g_);
    if (D) ck.add_module("D", *D).add_optimizer("adam_D", *opt_d_);
    ck.add_state([this](Blob& b) { watch_.save(b); }, [this](const Blob& b) { watch_.load(b); });
    if (ema_)
      ck.add_state([this](Blob& b) { ema_->save_state(b, "ema.G."); },
                   [this](const Blob& b) { ema_->load_state(b, "ema.G."); });
  }
  int64_t& step_counter() { return step_; }
  runs::RunConfig run_config() const {
    Blob b;
    put_config(b);
    runs::RunConfig c;
    for (auto& [k, v] : b.config()) c.emplace_back(k, v);
    return c;
  }
  // The generator alone with what rebuilds it and assembles its inputs (gi_model_io.h).
  void save_generator(const std::string& path) {
    AveragedWeights averaged(ema_.get());
    gi::save_generator_blob(path, G, config.inputs, config.generator(), loss_name(config.loss));
  }
  // G.blob, and D.blob when there is a discriminator (--loss gan).
  void save_models(const std::string& g_path, const std::string& d_path) {
    save_generator(g_path);
    if (D) gi::save_discriminator_blob(d_path, *D);
  }

  GanTrainConfig config;

 private:
  void put_config(Blob& b) const {
    gi::put_generator_config(b, config.inputs, config.generator(), loss_name(config.loss));
    b.set_config("ndf", config.ndf);
    b.set_config("d_layers", config.d_layers);
    b.set_config("lambda", config.lambda);
    if (config.dssim_weight > 0) b.set_config("dssim_weight", config.dssim_weight);
    if (config.gradient_weight > 0) b.set_config("gradient_weight", config.gradient_weight);
    b.set_config("lr", config.lr);
    // Only when it differs: a blob of a run with one rate stays as it was.
    if (config.d_lr() != config.lr) b.set_config("lr_d", config.d_lr());
    b.set_config("beta1", config.beta1);
    b.set_config("beta2", config.beta2);
    b.set_config("epochs", config.epochs);
    b.set_config("epochs_decay", config.epochs_decay);
    b.set_config("seed", int64_t(config.seed));
  }
  // Both updates only after every check passed: a failing step changes nothing.
  void update() {
    if (D) opt_d_->step();
    opt_g_->step();
    if (ema_) ema_->update();
    ++step_;
  }
  // The averaged weights in G for a scope (nothing without an average).
  struct AveragedWeights {
    WeightAverage<float>* a;
    explicit AveragedWeights(WeightAverage<float>* avg) : a(avg) {
      if (a) a->swap();
    }
    ~AveragedWeights() {
      if (a) a->swap();
    }
  };
  static Var<float> pair(const Var<float>& x, const Var<float>& y) {
    return concat_channels(std::vector<Var<float>>{x, y});
  }
  static void set_requires_grad(Module<float>& m, bool on) {
    for (auto p : m.parameters()) p.set_requires_grad(on);
  }
  static void check_gradients(Module<float>& m, int64_t step, const std::string& prefix) {
    for (auto& [name, p] : m.named_parameters())
      if (p.grad().defined()) check_finite(p.grad(), step, "gradient of " + prefix + name);
  }
  std::vector<Tensor<float>> snapshot_buffers() {
    std::vector<Tensor<float>> out;
    for (auto& [name, b] : G.named_buffers()) out.push_back(b->clone());
    return out;
  }
  void restore_buffers(const std::vector<Tensor<float>>& saved) {
    size_t i = 0;
    for (auto& [name, b] : G.named_buffers()) *b = saved[i++].clone();
  }

  Rng init_rng_;
  std::unique_ptr<gi::GiGenerator<float>> G_;

 public:
  gi::GiGenerator<float>& G;
  std::unique_ptr<gi::PatchGan<float>> D;

 private:
  std::unique_ptr<Adam<float>> opt_g_, opt_d_;
  std::unique_ptr<WeightAverage<float>> ema_;  // config.ema > 0
  LrSchedule schedule_, schedule_d_;           // G's and D's (the same unless lr_d is set)
  int64_t step_ = 0;
  DiscriminatorWatch watch_;
};

}  // namespace nns::runs
