#pragma once
// A whole training run of train-gan (and of each sweep point): the loop body over the
// in-memory training samples, with progress and ETA, sample PNGs and the discriminator
// watch; the run layer (runs/training_run.h) owns the folder, metrics.jsonl, the
// checkpoint and its configuration, --resume, the NaN/Inf stop and summary.json.
//
// Files in `out`:
//   checkpoint.blob   everything to resume (written after every epoch, after G.blob)
//   G.blob            the generator alone, for eval-gi (written before each checkpoint)
//   D.blob            the discriminator alone (--loss gan), with G.blob: tools/nnshade_torch.py
//   metrics.jsonl     one line per `log_every` steps: step, epoch, lr, losses, seconds
//   loss.svg/.png     D and G losses over steps
//   samples/          step<N>_{input,prediction,truth,error,shaded}.png every `sample_every` steps
//   summary.json      how the run ended (finished | non-finite), D-wins windows, timing
//   report.md/.html   the run for people: losses, the first and last samples, figures
//
// --accumulate K: a step is K samples of the epoch's order, their gradients averaged in
// order (runs/distributed/grad_sync.h; BatchNorm keeps each image's own statistics, as
// pix2pix at batch 1); the last n mod K samples of an epoch are left out. Under mpirun
// the K samples are spread over the ranks, each rank reading only its own, and the
// weights are those of one process with --accumulate K. Rank 0 alone writes.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "runs/gi/gan_trainer.h"
#include "runs/gi/gi_augment.h"
#include "runs/gi/gi_previews.h"
#include "runs/gi/gi_training_frames.h"
#include "runs/training_loop.h"

namespace nns::runs {

// The files of a train-gan run in its output folder, named once.
struct GanRunFiles {
  std::string out;
  std::string path(const char* name) const { return (std::filesystem::path(out) / name).string(); }
  std::string generator() const { return path("G.blob"); }
  std::string discriminator() const { return path("D.blob"); }
  std::string samples() const { return path("samples"); }
  // samples/step<N>, the prefix of that step's PNGs (write_sample_pngs).
  std::string sample_prefix(int64_t step) const { return samples() + "/step" + std::to_string(step); }
  std::string eval() const { return path("eval"); }
  std::string eval_holdout() const { return path("eval/holdout"); }
};

struct GanRunOptions {
  GanTrainConfig train;
  std::string out;
  bool resume = false;
  int log_every = 10;
  int sample_every = 250;
  int64_t poison_step = -1;    // test hook: make this step's input NaN (the NaN-stop test)
  int stop_after_epochs = -1;  // test hook: stop (as if killed) after this many epochs
  bool quiet = false;
  int accumulate = 1;         // samples (micro-batches of one image) per optimizer step
  double bucket_mb = 25;      // MiB per gradient bucket of the MPI exchange (<= 0: one)
  std::string data_identity;  // the data's folder and frame counts: a resume must match
  // bf16: every GEMM and convolution of the training takes bf16 inputs (fp32 sums); the
  // weights, Adam's moments, BatchNorm statistics and the losses stay fp32.
  Precision precision = Precision::fp32;
  // Mirror, exposure and light-colour jitter of the training samples (gi_augment.h).
  GiAugment augment;
};

// A number as a run's configuration records it ("0.9", not "0.90000000000000002").
inline std::string config_number(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", x);
  return b;
}
// The augmentation's part of a run's configuration (a resume must match it); checkpoints
// from before augmentation existed were made without it (RunSpec::unrecorded_means).
inline void add_augment_config(runs::RunSpec& spec, const GiAugment& a) {
  spec.config.emplace_back("aug_mirror", a.mirror ? "on" : "off");
  spec.config.emplace_back("aug_exposure", config_number(a.exposure));
  spec.config.emplace_back("aug_tint", config_number(a.tint));
  for (auto [k, v] :
       {std::pair<const char*, const char*>{"aug_mirror", "off"}, {"aug_exposure", "1"}, {"aug_tint", "1"}})
    spec.unrecorded_means.emplace_back(k, v);
}

struct GanRunResult {
  bool finished = false;  // false: stopped on a non-finite value
  std::string stop_message;
  int epochs_done = 0;
  int64_t steps = 0;
  double seconds = 0;  // training time of this process (excludes loading)
  int64_t d_wins_windows = 0;
  int64_t first_d_wins_step = -1;
};

// What the checkpoint records and a --resume must match (runs/training_run.h).
inline runs::RunSpec run_spec(const GanRunOptions& o, const GanTrainer& t) {
  runs::RunSpec spec;
  spec.app = "train-gan";
  spec.out = o.out;
  spec.checkpoint_kind = "pix2pix-checkpoint";
  spec.resume = o.resume;
  spec.config = t.run_config();
  spec.config.emplace_back("data", o.data_identity);
  // Checkpoints made before --precision existed lack it: RunSpec::unrecorded_means.
  spec.config.emplace_back("precision", precision_name(o.precision));
  // It changes the rounding; checkpoints older than --accumulate lack it (RunSpec::unrecorded_means).
  spec.config.emplace_back("accumulate", std::to_string(o.accumulate));
  add_augment_config(spec, o.augment);
  // Recorded always, so a resume that adds or drops the average is refused; checkpoints
  // older than --ema were made without one.
  spec.config.emplace_back("ema", config_number(o.train.ema));
  spec.unrecorded_means.emplace_back("ema", "0");
  return spec;
}

// train-gan's part of the training loop (runs/training_loop.h): a step is one sample of
// the epoch's shuffled order (or K of them, accumulated) through D's and G's updates; the
// log averages every `log_every` steps; sample PNGs every `sample_every` steps; the
// outputs are G.blob and D.blob.
class GanTask : public runs::TrainingTask {
 public:
  GanTask(const GanRunOptions& o, GanTrainer& t, GiTrainData& train, runs::TrainingRun& run)
      : o_(o), t_(t), train_(train), run_(run), n_(int64_t(train.size())), K_(o.accumulate), files_{o.out} {}
  int64_t steps_per_epoch() const { return n_ / K_; }

  std::vector<Var<float>> trained_parameters() override { return t_.trained_parameters(); }
  std::vector<Rng*> rngs() override { return t_.rngs(); }
  std::vector<Tensor<float>*> buffers() override { return t_.buffers(); }

  void begin_epoch(int64_t epoch) override {
    epoch_ = int(epoch);
    t_.begin_epoch(epoch_);
    // The order of an epoch depends on (seed, epoch) only, so a resumed run replays it.
    Rng order_rng = Rng(o_.train.seed).fork(1000 + uint64_t(epoch));
    order_.resize(size_t(n_));
    for (int64_t i = 0; i < n_; ++i) order_[size_t(i)] = i;
    for (int64_t i = n_ - 1; i > 0; --i) std::swap(order_[size_t(i)], order_[order_rng.below(uint64_t(i + 1))]);
  }
  void begin_step(int64_t) override {
    poison_ = t_.step() + 1 == o_.poison_step;  // micro-batch 0's input, with --accumulate
    shown_ = nullptr;
  }
  runs::StepValues step(int64_t j) override {
    shown_ = &prepared(j, sample(j, j + 1));
    return values(t_.train_step(maybe_poisoned(*shown_, poison_)));
  }
  runs::StepValues micro_batch(int64_t j, int m, const runs::MicroRange& mine) override {
    const int64_t q = j * K_ + m;
    const int64_t next = m + 1 < mine.end ? q + 1 : (j + 1 < steps_per_epoch() ? (j + 1) * K_ + mine.begin : -1);
    const gi::GiSample& s = prepared(q, sample(q, next));
    return values(t_.accumulate_sample(maybe_poisoned(s, poison_ && m == 0)));
  }
  void apply(const runs::StepValues& mean) override { t_.apply_accumulated(losses(mean)); }
  std::string end_step(int64_t, int64_t j, const runs::StepValues& v) override {
    const StepLosses l = losses(v);
    watch(l);
    acc_.d += l.d, acc_.d_real += l.d_real, acc_.d_fake += l.d_fake;
    acc_.g_adv += l.g_adv, acc_.g_rec += l.g_rec, acc_.g += l.g;
    ++acc_n_;
    if (t_.step() % o_.log_every == 0) flush_log();
    if (run_.writes_files() && o_.sample_every > 0 && t_.step() % o_.sample_every == 0) write_samples(j);
    char status[96];
    if (o_.train.loss == GiLoss::gan)
      std::snprintf(status, sizeof status, "D %.3f G_adv %.3f rec %.4f", l.d, l.g_adv, l.g_rec);
    else std::snprintf(status, sizeof status, "rec %.4f", l.g_rec);
    return status;
  }
  void end_epoch(int64_t) override {
    // The epoch's last partial window: a resumed run starts afresh at this step.
    if (acc_n_ > 0) flush_log();
    if (run_.writes_files()) write_loss_chart(run_.metrics(), run_.path("loss.svg"));
  }
  void write_outputs() override { t_.save_models(files_.generator(), files_.discriminator()); }
  bool interrupt_after(int64_t epochs_done) const override { return epochs_done == o_.stop_after_epochs; }

  int64_t first_d_wins_step = -1;

 private:
  static runs::StepValues values(const StepLosses& l) { return {l.d, l.d_real, l.d_fake, l.g_adv, l.g_rec, l.g}; }
  static StepLosses losses(const runs::StepValues& v) { return {v[0], v[1], v[2], v[3], v[4], v[5]}; }

  // Sample q of the epoch's order (q: a position in it), reading `next` ahead.
  const gi::GiSample& sample(int64_t q, int64_t next) {
    return train_.get(size_t(order_[size_t(q)]),
                      next >= 0 && next < n_ ? std::optional<size_t>(size_t(order_[size_t(next)])) : std::nullopt);
  }
  // Sample q as trained on: augmented when asked (gi_augment.h), from its own stream.
  const gi::GiSample& prepared(int64_t q, const gi::GiSample& s) {
    if (!o_.augment.any()) return s;
    Rng rng = augment_rng(o_.train.seed, epoch_, q);
    augmented_ = augmented(s, draw_augment(o_.augment, rng), o_.train.inputs.norm.hdr_scale);
    return augmented_;
  }
  const gi::GiSample& maybe_poisoned(const gi::GiSample& s, bool poison) {
    if (!poison) return s;
    poisoned_ = s;
    poisoned_.input = s.input.clone();
    poisoned_.input[0] = NAN;
    return poisoned_;
  }
  void watch(const StepLosses& l) {
    if (o_.train.loss != GiLoss::gan || !t_.watch().add(l.d, l.g_adv)) return;
    if (first_d_wins_step < 0) first_d_wins_step = t_.step();
    if (!o_.quiet)
      std::fprintf(stderr,
                   "\ntrain-gan: warning: the discriminator wins outright at step %lld "
                   "(D loss < %.2f over %d steps while G's adversarial loss climbs)\n",
                   (long long)t_.step(), DiscriminatorWatch::kNearZero, DiscriminatorWatch::kWindow);
  }
  void flush_log() {
    const double k = 1.0 / acc_n_;
    // Epochs count from 1 in the log, as train-nnao's: the record's epoch is the one it belongs to.
    run_.log({t_.step(),
              epoch_ + 1,
              {{"lr", t_.lr()},
               {"d", acc_.d * k},
               {"d_real", acc_.d_real * k},
               {"d_fake", acc_.d_fake * k},
               {"g_adv", acc_.g_adv * k},
               {"g_rec", acc_.g_rec * k},
               {"g", acc_.g * k}}});
    acc_ = {};
    acc_n_ = 0;
  }
  // The step's first sample (read again when the step read others after it).
  void write_samples(int64_t j) {
    const gi::GiSample& s = shown_ ? *shown_ : prepared(j * K_, sample(j * K_, -1));
    write_sample_pngs(files_.sample_prefix(t_.step()), s, t_.predict(s, /*bn_batch_stats=*/true, /*dropout_on=*/false),
                      gi::HdrMapping(o_.train.inputs.norm.hdr_scale));
  }

  const GanRunOptions& o_;
  GanTrainer& t_;
  GiTrainData& train_;
  runs::TrainingRun& run_;
  const int64_t n_;
  const int K_;
  const GanRunFiles files_;
  int epoch_ = 0;
  std::vector<int64_t> order_;
  bool poison_ = false;
  const gi::GiSample* shown_ = nullptr;  // K = 1: the step's sample, for the PNGs
  gi::GiSample augmented_, poisoned_;
  StepLosses acc_;
  int acc_n_ = 0;
};

inline GanRunResult run_gan_training(const GanRunOptions& o, GiTrainData& train) {
  if (train.empty()) throw std::runtime_error("train-gan: no training samples");
  GanTrainer t(o.train);
  Checkpoint<float> ck;
  t.add_to(ck);
  runs::TrainingLoop loop(run_spec(o, t), ck, t.step_counter(), o.precision, o.quiet);
  runs::TrainingRun& run = loop.run();
  if (run.writes_files()) std::filesystem::create_directories(GanRunFiles{o.out}.samples());
  GanTask task(o, t, train, run);
  if (task.steps_per_epoch() == 0) throw std::runtime_error("train-gan: fewer training samples than --accumulate");
  const runs::LoopResult lr = loop.train(task, {.progress_label = "train-gan " + std::string(loss_name(o.train.loss)),
                                                .epochs = o.train.total_epochs(),
                                                .steps_per_epoch = task.steps_per_epoch(),
                                                .accumulate = o.accumulate,
                                                .bucket_mb = o.bucket_mb});
  GanRunResult r;
  r.finished = lr.finished();
  r.stop_message = lr.stop_message;
  r.epochs_done = int(run.epochs_done());
  r.steps = t.step();
  r.d_wins_windows = t.watch().windows_won();
  r.first_d_wins_step = task.first_d_wins_step;
  r.seconds = lr.seconds;
  loop.finish(r.stop_message,
              {{"seconds", r.seconds},
               {"d_wins_windows", double(r.d_wins_windows)},
               {"first_d_wins_step", double(r.first_d_wins_step)},
               {"g_parameters", double(t.G.parameter_count())}},
              [&](report::Report& report) {
                if (std::filesystem::exists(run.path("loss.svg"))) report.chart("loss.svg", "D and G losses per step");
                add_sample_comparisons(report, o.out, o.sample_every, t.step());
              });
  return r;
}

}  // namespace nns::runs
