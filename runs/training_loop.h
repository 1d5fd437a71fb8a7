#pragma once
// The one training loop. A trainer supplies what is its own (its model's step, its data,
// its evaluation, its files) as a TrainingTask; the loop owns the sequence every trainer
// shares, as dlib's dnn_trainer owns its loop:
//
//   precision scope -> TrainingRun (folder, log, checkpoint, --resume) -> gradient
//   exchange -> progress bar -> epochs { steps { micro-batches } -> evaluation ->
//   outputs, then checkpoint } -> final outputs -> non-finite stop -> summary, report
//
//   runs::TrainingLoop loop(spec, ck, step, precision);  // the run; ck restored on --resume
//   ... build the data (in the run's folder, after a refused --resume has cost nothing) ...
//   runs::LoopResult r = loop.train(task, settings);
//   return loop.finish(r.stop_message, figures, add_to_report);
//
// A step is task.step() in one process with --accumulate 1. Otherwise it is K
// micro-batches (runs/distributed/grad_sync.h): each rank computes its block of them,
// each gradient alone and unchecked (a rank must not stop while the others wait for its
// gradients), then the exchange leaves the mean gradient in every rank's buffers and
// task.apply() checks the mean values and updates, identically on every rank.
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/kernels/gemm_precision.h"
#include "core/progress.h"
#include "runs/distributed/grad_sync.h"
#include "runs/training_run.h"

namespace nns::runs {

// One step's values (its losses), in the trainer's own order; an accumulated step's are
// the mean over its micro-batches, in micro-batch order.
using StepValues = std::vector<double>;

// What a trainer gives the loop. Epochs count from 0 while they run; `epochs_done`
// counts the completed ones (1 after the first).
class TrainingTask {
 public:
  virtual ~TrainingTask() = default;

  // What the gradient exchange averages: the trained parameters, the generators a
  // micro-batch forks, the buffers a forward pass moves (running statistics).
  virtual std::vector<Var<float>> trained_parameters() = 0;
  virtual std::vector<Rng*> rngs() = 0;
  virtual std::vector<Tensor<float>*> buffers() { return {}; }

  // Its learning rate, its data order.
  virtual void begin_epoch(int64_t epoch) { (void)epoch; }
  // The data every micro-batch of step j reads.
  virtual void begin_step(int64_t j) { (void)j; }
  // A whole step (one process, no accumulation): gradients, checks, update.
  virtual StepValues step(int64_t j) = 0;
  // Micro-batch m of step j (mine: this rank's micro-batches): its gradient alone.
  virtual StepValues micro_batch(int64_t j, int m, const runs::MicroRange& mine) = 0;
  // After the exchange: check the mean values and gradients, then update.
  virtual void apply(const StepValues& mean) = 0;
  // After the update: running sums, log lines, samples. Returns the progress bar's
  // status ("": leave the bar as it is).
  virtual std::string end_step(int64_t epoch, int64_t j, const StepValues& values) = 0;
  // After the epoch's last step: evaluation, log, charts (before the checkpoint).
  virtual void end_epoch(int64_t epochs_done) { (void)epochs_done; }
  // The files written before each checkpoint, and once more after the last epoch.
  virtual void write_outputs() = 0;
  // A test hook: stop after this epoch as if the process had been killed.
  virtual bool interrupt_after(int64_t epochs_done) const { return (void)epochs_done, false; }
  // After a non-finite stop, before the message (e.g. a changed thread count back).
  virtual void stopped() {}
};

struct LoopSettings {
  std::string progress_label;  // the bar's label
  int64_t epochs = 0;          // in all; a resumed run does those not yet done
  int64_t steps_per_epoch = 0;
  int accumulate = 1;     // micro-batches per step
  double bucket_mb = 25;  // MiB per gradient bucket of the MPI exchange (<= 0: one)
};

struct LoopResult {
  std::string stop_message;  // empty: finished; else why it stopped (non-finite value)
  int64_t epochs_run = 0;    // by this process
  double epoch_seconds = 0;  // summed over them (steps, evaluation, writes)
  double seconds = 0;        // the whole loop, this process
  bool finished() const { return stop_message.empty(); }
};

class TrainingLoop {
 public:
  // `step` is the trainer's step counter (the checkpoint keeps it). Refuses a --resume
  // whose configuration differs (TrainingRun) before anything is built.
  TrainingLoop(RunSpec spec, Checkpoint<float>& ck, int64_t& step, Precision precision, bool quiet)
      : precision_(precision),
        app_(spec.app),
        checkpoint_name_(spec.checkpoint_name),
        resume_(spec.resume),
        run_(std::move(spec), ck, step),
        step_(step),
        quiet_(quiet) {
    if (resume_ && !quiet_)
      std::fprintf(stderr, "%s: resuming from %s at epoch %lld, step %lld\n", app_.c_str(),
                   run_.path(checkpoint_name_).c_str(), (long long)run_.epochs_done(), (long long)step_);
  }

  TrainingRun& run() { return run_; }

  LoopResult train(TrainingTask& task, const LoopSettings& s) {
    sync_ = std::make_unique<runs::GradSync>(task.trained_parameters(), task.rngs(), s.accumulate, s.bucket_mb);
    sync_->set_buffers(task.buffers());
    const int64_t first = run_.epochs_done();
    Progress bar(s.progress_label, (s.epochs - first) * s.steps_per_epoch);
    LoopResult r;
    try {
      for (int64_t epoch = first; epoch < s.epochs; ++epoch) {
        const auto t_epoch = std::chrono::steady_clock::now();
        task.begin_epoch(epoch);
        for (int64_t j = 0; j < s.steps_per_epoch; ++j) {
          task.begin_step(j);
          const StepValues values = sync_->active() ? accumulated_step(task, j) : task.step(j);
          const std::string status = task.end_step(epoch, j, values);
          if (!quiet_ && !status.empty()) bar.update((epoch - first) * s.steps_per_epoch + j + 1, status);
        }
        task.end_epoch(epoch + 1);
        run_.end_epoch(epoch + 1, [&] { task.write_outputs(); });
        r.epoch_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_epoch).count();
        ++r.epochs_run;
        if (task.interrupt_after(epoch + 1)) break;
      }
      // Also after a resume that found every epoch done: the model always matches the
      // checkpoint, even if a run was killed between the two writes.
      if (run_.writes_files()) task.write_outputs();
    } catch (const NonFiniteError& e) {
      task.stopped();
      r.stop_message = run_.stop_message(e);
      if (!quiet_) std::fprintf(stderr, "\n%s: stopped: %s\n", app_.c_str(), r.stop_message.c_str());
    }
    if (!quiet_) bar.finish();
    r.seconds = bar.elapsed_seconds();
    return r;
  }

  // summary.json and the report, with the exchange's figures when there was one.
  // Returns the exit status: 0 finished, 3 stopped on a non-finite value.
  int finish(const std::string& stop_message, std::vector<std::pair<std::string, double>> figures,
             const std::function<void(report::Report&)>& add_to_report = {}) {
    if (sync_) runs::add_sync_figures(*sync_, figures);
    return run_.finish(stop_message, figures, add_to_report);
  }

 private:
  StepValues accumulated_step(TrainingTask& task, int64_t j) {
    const runs::MicroRange mine = sync_->mine();
    std::vector<StepValues> per_micro;
    for (int m = mine.begin; m < mine.end; ++m) {
      sync_->begin_micro(m);
      per_micro.push_back(task.micro_batch(j, m, mine));
      sync_->end_micro(m);
    }
    sync_->finish_step();
    StepValues mean = sync_->mean_over_micro(per_micro);
    task.apply(mean);
    return mean;
  }

  ScopedGemmPrecision precision_;  // first: set before the run computes anything
  std::string app_, checkpoint_name_;
  bool resume_;
  TrainingRun run_;
  int64_t& step_;
  bool quiet_;
  std::unique_ptr<runs::GradSync> sync_;
};

}  // namespace nns::runs
