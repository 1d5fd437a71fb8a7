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

#include "core/progress.h"
#include "core/kernels/gemm_precision.h"
#include "runs/distributed/grad_sync.h"
#include "runs/gi/gan_trainer.h"
#include "runs/gi/gi_augment.h"
#include "runs/gi/gi_previews.h"
#include "runs/gi/gi_train_data.h"

namespace nns::gi {

struct GanRunOptions {
  GanTrainConfig train;
  std::string out;
  bool resume = false;
  int log_every = 10;
  int sample_every = 250;
  int64_t poison_step = -1;     // test hook: make this step's input NaN (the NaN-stop test)
  int stop_after_epochs = -1;   // test hook: stop (as if killed) after this many epochs
  bool quiet = false;
  int accumulate = 1;        // samples (micro-batches of one image) per optimizer step
  double bucket_mb = 25;     // MiB per gradient bucket of the MPI exchange (<= 0: one)
  std::string data_identity;    // the data's folder and frame counts: a resume must match
  // bf16: every GEMM and convolution of the training takes bf16 inputs (fp32 sums); the
  // weights, Adam's moments, BatchNorm statistics and the losses stay fp32.
  Precision precision = Precision::fp32;
  // Mirror, exposure and light-colour jitter of the training samples (gi_augment.h).
  GiAugment augment;
};

// The augmentation's part of a run's configuration (a resume must match it); checkpoints
// from before augmentation existed were made without it (RunSpec::unrecorded_means).
inline void add_augment_config(runs::RunSpec& spec, const GiAugment& a) {
  auto num = [](double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", x);
    return std::string(b);
  };
  spec.config.emplace_back("aug_mirror", a.mirror ? "on" : "off");
  spec.config.emplace_back("aug_exposure", num(a.exposure));
  spec.config.emplace_back("aug_tint", num(a.tint));
  for (auto [k, v] : {std::pair<const char*, const char*>{"aug_mirror", "off"}, {"aug_exposure", "1"}, {"aug_tint", "1"}})
    spec.unrecorded_means.emplace_back(k, v);
}

struct GanRunResult {
  bool finished = false;        // false: stopped on a non-finite value
  std::string stop_message;
  int epochs_done = 0;
  int64_t steps = 0;
  double seconds = 0;           // training time of this process (excludes loading)
  int64_t d_wins_windows = 0;
  int64_t first_d_wins_step = -1;
};

inline GanRunResult run_gan_training(const GanRunOptions& o, GiTrainData& train) {
  if (train.empty()) throw std::runtime_error("train-gan: no training samples");
  const ScopedGemmPrecision precision(o.precision);
  GanTrainer t(o.train);
  Checkpoint<float> ck;
  t.add_to(ck);
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
  runs::TrainingRun run(spec, ck, t.step_counter());
  if (run.writes_files()) std::filesystem::create_directories(o.out + "/samples");
  dist::GradSync sync(t.trained_parameters(), t.rngs(), o.accumulate, o.bucket_mb);
  sync.set_buffers(t.buffers());
  const int K = o.accumulate;
  const int start_epoch = int(run.epochs_done());
  if (o.resume && !o.quiet)
    std::fprintf(stderr, "train-gan: resuming from %s at epoch %d, step %lld\n", run.path("checkpoint.blob").c_str(),
                 start_epoch, (long long)t.step());

  GanRunResult r;
  r.epochs_done = start_epoch;
  const int total = o.train.total_epochs();
  const int64_t n = int64_t(train.size());
  const int64_t steps_per_epoch = n / K;
  if (steps_per_epoch == 0) throw std::runtime_error("train-gan: fewer training samples than --accumulate");
  Progress bar("train-gan " + std::string(loss_name(o.train.loss)), int64_t(total - start_epoch) * steps_per_epoch);
  StepLosses acc;
  int acc_n = 0;
  auto flush_log = [&](int epoch) {
    const double k = 1.0 / acc_n;
    run.log({t.step(), epoch, {{"lr", t.lr()}, {"d", acc.d * k}, {"d_real", acc.d_real * k}, {"d_fake", acc.d_fake * k},
                               {"g_adv", acc.g_adv * k}, {"g_rec", acc.g_rec * k}, {"g", acc.g * k}}});
    acc = {};
    acc_n = 0;
  };
  const std::string g_blob = run.path("G.blob"), d_blob = run.path("D.blob");
  try {
    for (int epoch = start_epoch; epoch < total; ++epoch) {
      t.begin_epoch(epoch);
      // The order of an epoch depends on (seed, epoch) only, so a resumed run replays it.
      Rng order_rng = Rng(o.train.seed).fork(1000 + uint64_t(epoch));
      std::vector<int64_t> order(static_cast<size_t>(n));
      for (int64_t i = 0; i < n; ++i) order[size_t(i)] = i;
      for (int64_t i = n - 1; i > 0; --i) std::swap(order[size_t(i)], order[order_rng.below(uint64_t(i + 1))]);
      // Sample q of the epoch's order (q: a position in it), reading `next` ahead.
      auto sample = [&](int64_t q, int64_t next) -> const GiSample& {
        return train.get(size_t(order[size_t(q)]),
                         next >= 0 && next < n ? std::optional<size_t>(size_t(order[size_t(next)])) : std::nullopt);
      };
      // Sample q as trained on: augmented when asked (gi_augment.h), from its own stream.
      GiSample augmented_sample;
      auto prepared = [&](int64_t q, const GiSample& s) -> const GiSample& {
        if (!o.augment.any()) return s;
        Rng rng = augment_rng(o.train.seed, epoch, q);
        augmented_sample = augmented(s, draw_augment(o.augment, rng), o.train.inputs.norm.hdr_scale);
        return augmented_sample;
      };
      GiSample poisoned;
      auto maybe_poisoned = [&](const GiSample& s, bool poison) -> const GiSample& {
        if (!poison) return s;
        poisoned = s;
        poisoned.input = s.input.clone();
        poisoned.input[0] = NAN;
        return poisoned;
      };
      for (int64_t j = 0; j < steps_per_epoch; ++j) {
        const bool poison = t.step() + 1 == o.poison_step;  // micro-batch 0's input, with --accumulate
        StepLosses l;
        const GiSample* shown = nullptr;  // K = 1: the step's sample, for the PNGs
        if (!sync.active()) {
          shown = &prepared(j, sample(j, j + 1));
          l = t.train_step(maybe_poisoned(*shown, poison));
        } else {
          const dist::MicroRange mine = sync.mine();
          std::vector<std::vector<double>> per;
          for (int m = mine.begin; m < mine.end; ++m) {
            const int64_t q = j * K + m, next = m + 1 < mine.end ? q + 1 : (j + 1 < steps_per_epoch ? (j + 1) * K + mine.begin : -1);
            const GiSample& s = prepared(q, sample(q, next));
            sync.begin_micro(m);
            const StepLosses lm = t.accumulate_sample(maybe_poisoned(s, poison && m == 0));
            sync.end_micro(m);
            per.push_back({lm.d, lm.d_real, lm.d_fake, lm.g_adv, lm.g_rec, lm.g});
          }
          sync.finish_step();
          const std::vector<double> mean = sync.mean_over_micro(per);
          l = {mean[0], mean[1], mean[2], mean[3], mean[4], mean[5]};
          t.apply_accumulated(l);
        }
        if (o.train.loss == GiLoss::gan && t.watch().add(l.d, l.g_adv)) {
          ++r.d_wins_windows;
          if (r.first_d_wins_step < 0) r.first_d_wins_step = t.step();
          if (!o.quiet)
            std::fprintf(stderr, "\ntrain-gan: warning: the discriminator wins outright at step %lld "
                         "(D loss < %.2f over %d steps while G's adversarial loss climbs)\n",
                         (long long)t.step(), DiscriminatorWatch::kNearZero, DiscriminatorWatch::kWindow);
        }
        acc.d += l.d, acc.d_real += l.d_real, acc.d_fake += l.d_fake;
        acc.g_adv += l.g_adv, acc.g_rec += l.g_rec, acc.g += l.g;
        ++acc_n;
        if (t.step() % o.log_every == 0) flush_log(epoch);
        if (run.writes_files() && o.sample_every > 0 && t.step() % o.sample_every == 0) {
          // The step's first sample (read again when the step read others after it).
          const GiSample& s = shown ? *shown : prepared(j * K, sample(j * K, -1));
          write_sample_pngs(o.out + "/samples/step" + std::to_string(t.step()), s,
                            t.predict(s, /*bn_batch_stats=*/true, /*dropout_on=*/false),
                            HdrMapping(o.train.inputs.norm.hdr_scale));
        }
        if (!o.quiet) {
          char status[96];
          std::snprintf(status, sizeof status, "D %.3f G_adv %.3f rec %.4f", l.d, l.g_adv, l.g_rec);
          bar.update(int64_t(epoch - start_epoch) * steps_per_epoch + j + 1, status);
        }
      }
      // The epoch's last partial window: a resumed run starts afresh at this step.
      if (acc_n > 0) flush_log(epoch);
      if (run.writes_files()) write_loss_chart(run.metrics(), run.path("loss.svg"));
      run.end_epoch(epoch + 1, [&] { t.save_models(g_blob, d_blob); });
      r.epochs_done = epoch + 1;
      if (epoch + 1 == o.stop_after_epochs) break;
    }
    // Also after a resume that found every epoch done: G.blob always matches the
    // checkpoint, even if a run was killed between writing the two.
    if (run.writes_files()) t.save_models(g_blob, d_blob);
    r.finished = true;
  } catch (const NonFiniteError& e) {
    r.stop_message = run.stop_message(e);
    if (!o.quiet) std::fprintf(stderr, "\ntrain-gan: stopped: %s\n", r.stop_message.c_str());
  }
  if (!o.quiet) bar.finish();
  r.steps = t.step();
  r.d_wins_windows = t.watch().windows_won();
  r.seconds = bar.elapsed_seconds();
  std::vector<std::pair<std::string, double>> figures = {{"seconds", r.seconds}, {"d_wins_windows", double(r.d_wins_windows)},
                                                         {"first_d_wins_step", double(r.first_d_wins_step)},
                                                         {"g_parameters", double(t.G.parameter_count())}};
  dist::add_sync_figures(sync, figures);
  run.finish(r.stop_message, figures,
             [&](data::Report& report) {
               if (std::filesystem::exists(run.path("loss.svg"))) report.chart("loss.svg", "D and G losses per step");
               add_sample_comparisons(report, o.out, o.sample_every, t.step());
             });
  return r;
}

}  // namespace nns::gi
