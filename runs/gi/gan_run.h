#pragma once
// A whole training run of train-gan (and of each sweep point): epochs over the in-memory
// training samples with progress and ETA, OUT/metrics.jsonl, a loss chart, sample PNGs,
// a checkpoint every epoch, --resume, the NaN/Inf stop and the discriminator watch.
//
// Files in `out`:
//   checkpoint.blob   everything to resume (written after every epoch, atomically)
//   G.blob            the generator alone, for eval-gi (written with each checkpoint)
//   metrics.jsonl     one line per `log_every` steps: step, epoch, lr, losses, seconds
//   loss.svg/.png     D and G losses over steps
//   samples/          step<N>_{input,prediction,truth,shaded}.png every `sample_every` steps
//   summary.json      how the run ended (finished | non-finite), D-wins windows, timing
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/progress.h"
#include "runs/gi/gan_trainer.h"
#include "runs/gi/gi_previews.h"

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
};

struct GanRunResult {
  bool finished = false;        // false: stopped on a non-finite value
  std::string stop_message;
  int epochs_done = 0;
  int64_t steps = 0;
  double seconds = 0;           // training time of this process (excludes loading)
  int64_t d_wins_windows = 0;
  int64_t first_d_wins_step = -1;
};

namespace detail {

// Keeps the first lines of metrics.jsonl up to `step` (a resumed run rewrites the rest).
inline void truncate_metrics(const std::string& path, int64_t step) {
  std::ifstream in(path);
  if (!in) return;
  std::string line, kept;
  while (std::getline(in, line)) {
    auto p = line.find("\"step\":");
    if (p == std::string::npos) continue;
    if (std::stoll(line.substr(p + 7)) <= step) kept += line + "\n";
  }
  in.close();
  std::ofstream(path, std::ios::trunc) << kept;
}

inline std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

}  // namespace detail

inline GanRunResult run_gan_training(const GanRunOptions& o, std::vector<GiSample>& train) {
  namespace fs = std::filesystem;
  if (train.empty()) throw std::runtime_error("train-gan: no training samples");
  fs::create_directories(o.out);
  fs::create_directories(o.out + "/samples");
  const std::string ckpt = o.out + "/checkpoint.blob", metrics = o.out + "/metrics.jsonl";

  GanTrainer t(o.train);
  int start_epoch = 0;
  if (o.resume && fs::exists(ckpt)) {
    start_epoch = t.load_checkpoint(ckpt);
    detail::truncate_metrics(metrics, t.step());
    if (!o.quiet)
      std::fprintf(stderr, "train-gan: resuming from %s at epoch %d, step %lld\n", ckpt.c_str(),
                   start_epoch, (long long)t.step());
  } else {
    std::ofstream(metrics, std::ios::trunc);
  }

  GanRunResult r;
  r.epochs_done = start_epoch;
  const int total = o.train.total_epochs();
  const int64_t n = int64_t(train.size());
  Progress bar("train-gan " + std::string(loss_name(o.train.loss)), int64_t(total - start_epoch) * n);
  std::ofstream log(metrics, std::ios::app);
  StepLosses acc;
  int acc_n = 0;
  auto flush_log = [&](int epoch) {
    const double k = 1.0 / acc_n;
    auto num = detail::json_number;
    log << "{\"step\":" << t.step() << ",\"epoch\":" << epoch << ",\"lr\":" << num(t.lr())
        << ",\"d\":" << num(acc.d * k) << ",\"d_real\":" << num(acc.d_real * k)
        << ",\"d_fake\":" << num(acc.d_fake * k) << ",\"g_adv\":" << num(acc.g_adv * k)
        << ",\"g_rec\":" << num(acc.g_rec * k) << ",\"g\":" << num(acc.g * k) << "}\n";
    log.flush();
    acc = {};
    acc_n = 0;
  };
  try {
    for (int epoch = start_epoch; epoch < total; ++epoch) {
      t.begin_epoch(epoch);
      // The order of an epoch depends on (seed, epoch) only, so a resumed run replays it.
      Rng order_rng = Rng(o.train.seed).fork(1000 + uint64_t(epoch));
      std::vector<int64_t> order(static_cast<size_t>(n));
      for (int64_t i = 0; i < n; ++i) order[size_t(i)] = i;
      for (int64_t i = n - 1; i > 0; --i) std::swap(order[size_t(i)], order[order_rng.below(uint64_t(i + 1))]);
      for (int64_t j = 0; j < n; ++j) {
        GiSample& s = train[size_t(order[size_t(j)])];
        GiSample poisoned;
        const GiSample* use = &s;
        if (t.step() + 1 == o.poison_step) {
          poisoned = s;
          poisoned.input = s.input.clone();
          poisoned.input[0] = NAN;
          use = &poisoned;
        }
        StepLosses l = t.train_step(*use);
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
        if (o.sample_every > 0 && t.step() % o.sample_every == 0)
          write_sample_pngs(o.out + "/samples/step" + std::to_string(t.step()), s,
                            t.predict(s, /*bn_batch_stats=*/true, /*dropout_on=*/false),
                            HdrMapping(o.train.inputs.norm.hdr_scale));
        if (!o.quiet) {
          char status[96];
          std::snprintf(status, sizeof status, "D %.3f G_adv %.3f rec %.4f", l.d, l.g_adv, l.g_rec);
          bar.update(int64_t(epoch - start_epoch) * n + j + 1, status);
        }
      }
      // The epoch's last partial window: a resumed run starts afresh at this step.
      if (acc_n > 0) flush_log(epoch);
      t.save_checkpoint(ckpt, epoch + 1);
      t.save_generator(o.out + "/G.blob");
      r.epochs_done = epoch + 1;
      write_loss_chart(metrics, o.out + "/loss");
      if (epoch + 1 == o.stop_after_epochs) break;
    }
    r.finished = true;
  } catch (const NonFiniteError& e) {
    r.stop_message = std::string(e.what()) + "; weights not updated; last good checkpoint: " +
                     (r.epochs_done > 0 ? ckpt + " (epoch " + std::to_string(r.epochs_done) + ")"
                                        : std::string("none (no epoch completed)"));
    if (!o.quiet) std::fprintf(stderr, "\ntrain-gan: stopped: %s\n", r.stop_message.c_str());
  }
  if (!o.quiet) bar.finish();
  r.steps = t.step();
  r.d_wins_windows = t.watch().windows_won();
  r.seconds = bar.elapsed_seconds();
  std::ostringstream js;
  js << "{\"finished\":" << (r.finished ? "true" : "false") << ",\"stop\":\"" << r.stop_message
     << "\",\"epochs_done\":" << r.epochs_done << ",\"steps\":" << r.steps
     << ",\"seconds\":" << detail::json_number(r.seconds) << ",\"d_wins_windows\":" << r.d_wins_windows
     << ",\"first_d_wins_step\":" << r.first_d_wins_step
     << ",\"g_parameters\":" << t.G.parameter_count() << "}\n";
  write_file_atomic(o.out + "/summary.json", js.str());
  return r;
}

}  // namespace nns::gi
