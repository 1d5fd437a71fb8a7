#pragma once
// What every training run shares, so that a trainer is only its loop body (the split of
// dlib's dnn_trainer: the network code never touches files):
//   - the output folder, locked for the run (a second run into it is refused) and with
//     temporaries of a killed run's atomic writes removed;
//   - the metrics log (runs/metrics_log.h, one format, truncated correctly on resume);
//   - the checkpoint (optim/checkpoint.h: modules, optimizer moments, RNGs, counters)
//     holding the run's configuration, so that --resume with another learning rate,
//     seed, batch, data or model is refused, naming every value that changed;
//   - the order of the end-of-epoch writes: outputs first, then the checkpoint, so a
//     run killed in between redoes the epoch on resume (never an output left behind);
//   - the non-finite stop (NonFiniteError), summary.json, and report.md / report.html
//     (runs/run_report.h) for the people who look;
//   - under MPI (runs/distributed/world.h), rank 0 alone writes: the other ranks read the
//     checkpoint on --resume and keep the log in memory (writes_files() is false).
//
//   TrainingRun run(spec, ck);               // folder, log; on resume: ck restored
//   for (int64_t e = run.epochs_done(); e < epochs; ++e) {
//     ... steps (throw NonFiniteError before touching weights) ...
//     run.log({step, e + 1, {{"train_loss", loss}}});
//     run.end_epoch(e + 1, [&] { save the model });
//   }
//   run.write_outputs(...);  // also after a resume that found every epoch done
//   return run.finish(...);
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/atomic_file.h"
#include "core/blob.h"
#include "core/folder_lock.h"
#include "optim/checkpoint.h"
#include "runs/distributed/world.h"
#include "runs/metrics_log.h"
#include "runs/non_finite.h"
#include "runs/run_report.h"

namespace nns::runs {

// The run's configuration as ordered (key, value) text: what the checkpoint records
// and a resume must match.
using RunConfig = std::vector<std::pair<std::string, std::string>>;

struct RunSpec {
  std::string app;  // "train-nnao": prefixes messages
  std::string out;  // the output folder
  std::string checkpoint_name = "checkpoint.blob";
  std::string checkpoint_kind = "checkpoint";  // the blob's kind
  bool resume = false;
  RunConfig config;
  // Keys a resume may change: more epochs extend a finished run; threads never change
  // the numbers (determinism).
  std::vector<std::string> may_change = {"epochs", "epochs_decay", "threads"};
  // Keys added after checkpoints existed, with the value a checkpoint that lacks them was
  // made with ("precision" -> "fp32"): such a checkpoint still resumes at that value, and
  // one that records another value is caught whichever way the flag changed.
  RunConfig unrecorded_means = {{"precision", "fp32"}, {"accumulate", "1"}};
};

// Every key of `now` whose value differs from the checkpoint's (or that the checkpoint
// lacks), as "key: was A, now B", joined by "; ". Empty when they agree.
inline std::string config_changes(const Blob& saved, const RunSpec& spec) {
  std::string changes;
  for (auto& [key, value] : spec.config) {
    bool free = false;
    for (auto& k : spec.may_change) free |= k == key;
    if (free) continue;
    std::string was = "(not recorded)";
    if (saved.has_config(key)) {
      was = saved.config_string(key);
    } else {
      for (auto& [k, v] : spec.unrecorded_means)
        if (k == key) was = v;
    }
    if (was != value) changes += (changes.empty() ? "" : "; ") + key + ": was " + was + ", now " + value;
  }
  return changes;
}

class TrainingRun {
 public:
  static constexpr int64_t kMaxEpochs = 100000;
  // `step` is the trainer's step counter: the checkpoint keeps it, and a resumed log
  // keeps the lines up to it.
  TrainingRun(RunSpec spec, Checkpoint<float>& ck, int64_t& step) : spec_(std::move(spec)), ck_(ck), step_(step) {
    namespace fs = std::filesystem;
    fs::create_directories(spec_.out);
    // One run per folder (core/folder_lock.h); rank 0 holds it for the whole world.
    if (writes_files()) lock_ = prepare_output_folder(spec_.out, spec_.app);
    // At most the trainers' --epochs ceiling.
    ck_.add_counter("epochs_done", epochs_done_, 0, kMaxEpochs).add_counter("step", step_);
    const std::string ck_path = path(spec_.checkpoint_name);
    if (spec_.resume) {
      if (!fs::exists(ck_path))
        throw std::runtime_error(spec_.app + ": --resume: no checkpoint " + ck_path + " to resume from");
      Blob saved = Blob::load(ck_path);
      if (saved.kind() != spec_.checkpoint_kind)
        throw std::runtime_error(ck_path + ": a '" + saved.kind() + "' blob, not a " + spec_.app + " checkpoint");
      std::string changes = config_changes(saved, spec_);
      if (!changes.empty())
        throw std::runtime_error(spec_.app + ": --resume refused: " + ck_path +
                                 " was made with another configuration (" + changes +
                                 "); resume with the same flags, or use a new --out");
      ck_.restore(saved);
    }
    if (writes_files()) log_ = MetricsLog(path("metrics.jsonl"), spec_.resume ? step_ : -1);
    // Other ranks make their scratch files in the folder only after rank 0 has cleaned it.
    runs::barrier();
  }

  // False on MPI ranks other than 0: they train in step but write nothing.
  bool writes_files() const { return runs::writer(); }

  int64_t epochs_done() const { return epochs_done_; }
  std::string path(const std::string& name) const { return (std::filesystem::path(spec_.out) / name).string(); }
  MetricsLog& metrics() { return log_; }
  void log(const MetricsRecord& r) { log_.append(r); }

  // After each epoch: the outputs, then the checkpoint that says the epoch is done.
  // Nothing is written unless every tensor the checkpoint holds is finite (weights,
  // buffers such as BatchNorm's running_var, optimizer moments): the loss check alone let
  // a run exit 0 with +inf in 20 running_var values of G.blob.
  void end_epoch(int64_t epochs_done, const std::function<void()>& write_outputs) {
    check_state_finite();
    if (writes_files() && write_outputs) write_outputs();
    epochs_done_ = epochs_done;
    if (!writes_files()) return;
    Blob meta(spec_.checkpoint_kind);
    for (auto& [k, v] : spec_.config) meta.set_config(k, v);
    ck_.save(path(spec_.checkpoint_name), meta);
  }

  // Throws NonFiniteError naming the first tensor of the checkpoint that holds a NaN or
  // an Inf. Every rank checks (they hold the same state), so all of them stop together.
  void check_state_finite() const {
    Blob state;
    ck_.fill(state);
    for (auto& [name, t] : state.tensors()) {
      const int64_t n = t.numel();
      if (t.dtype == DType::F32 && !all_finite(reinterpret_cast<const float*>(t.bytes.data()), n))
        throw NonFiniteError(step_, name);
      if (t.dtype == DType::F64 && !all_finite(reinterpret_cast<const double*>(t.bytes.data()), n))
        throw NonFiniteError(step_, name);
    }
  }

  // summary.json and the report: how the run ended, and the trainer's own figures;
  // add_to_report puts the trainer's charts and images on the page. Returns the exit
  // status: 0 finished, 3 stopped on a non-finite value.
  int finish(const std::string& stop_message, const std::vector<std::pair<std::string, double>>& figures,
             const std::function<void(report::Report&)>& add_to_report = {}) {
    const bool finished = stop_message.empty();
    if (!writes_files()) return finished ? 0 : 3;
    std::string js = "{\"finished\":" + std::string(finished ? "true" : "false") +
                     ",\"stop\":" + json_string(stop_message) + ",\"epochs_done\":" + std::to_string(epochs_done_) +
                     ",\"steps\":" + std::to_string(step_);
    for (auto& [k, v] : figures) js += ",\"" + k + "\":" + json_number(v);
    write_file_atomic(path("summary.json"), js + "}\n");
    training_report({spec_.app, stop_message, epochs_done_, step_, figures}, log_.records(), spec_.config,
                    add_to_report)
        .write(spec_.out);
    return finished ? 0 : 3;
  }

  // The message for a non-finite stop: what happened and which checkpoint is good.
  std::string stop_message(const NonFiniteError& e) const {
    // A loss stops the step before Adam moves the weights; a tensor found before the
    // epoch's writes stops them, so nothing of that epoch reaches the disk either way.
    return std::string(e.what()) + "; nothing of it written; last good checkpoint: " +
           (epochs_done_ > 0 ? path(spec_.checkpoint_name) + " (epoch " + std::to_string(epochs_done_) + ")"
                             : std::string("none (no epoch completed)"));
  }

 private:
  RunSpec spec_;
  FolderLock lock_;
  Checkpoint<float>& ck_;
  int64_t epochs_done_ = 0;
  int64_t& step_;
  MetricsLog log_;
};

}  // namespace nns::runs
