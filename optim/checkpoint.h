#pragma once
// Checkpoint: everything a training run needs to continue bitwise as if it had never
// stopped — module(s) (parameters, buffers, their Rngs), optimizer state(s), counters
// such as step and epoch, free-standing Rngs (data shuffling), and the run's config.
// It is a Blob (core/blob.h) like a weights file, with names grouped by prefix:
//   module.<name>.<dotted tensor name>   optim.<name>.<state>
//   rng.<name> (u64[4])                   counter.<name> (i64[1])
//
// The trainer registers what to save once, then saves and loads as often as it likes:
//   Checkpoint<float> ck;
//   ck.add_module("generator", G).add_optimizer("generator", opt_G)
//     .add_rng("data", data_rng).add_counter("epoch", epoch).add_counter("step", step);
//   Blob meta("pix2pix"); meta.set_config("lr", 2e-4);
//   ck.save("run/latest.ckpt", meta);
//   Blob restored = ck.load("run/latest.ckpt");   // restores all of it in place
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/blob.h"
#include "nn/serialize.h"
#include "optim/optimizer.h"

namespace nns {

template <class T = float>
class Checkpoint {
 public:
  Checkpoint& add_module(const std::string& name, Module<T>& m) {
    modules_.emplace_back(name, &m);
    return *this;
  }
  Checkpoint& add_optimizer(const std::string& name, Optimizer<T>& o) {
    optimizers_.emplace_back(name, &o);
    return *this;
  }
  Checkpoint& add_rng(const std::string& name, Rng& r) {
    rngs_.emplace_back(name, &r);
    return *this;
  }
  // Registering a counter name again replaces the earlier one: a run object that
  // registers its own counters (runs/training_run.h) may be made anew for the same
  // checkpoint, and the old registration must not point into the old object
  // (AddressSanitizer found exactly that: a stack-use-after-scope on restore).
  //
  // A counter read back must lie in [lo, hi] (a checkpoint is outside bytes: an
  // epochs_done of 2^62 resumed "at epoch 4611686018427387904", -1 ran an extra epoch).
  // The default ceiling, 2^53, is the largest count the metrics log writes exactly.
  static constexpr int64_t kMaxCounter = int64_t(1) << 53;
  Checkpoint& add_counter(const std::string& name, int64_t& c, int64_t lo = 0, int64_t hi = kMaxCounter) {
    for (auto& counter : counters_)
      if (counter.name == name) return counter = {name, &c, lo, hi}, *this;
    counters_.push_back({name, &c, lo, hi});
    return *this;
  }
  // Any other state that writes and reads its own blob entries (a trainer's running sums).
  Checkpoint& add_state(std::function<void(Blob&)> save, std::function<void(const Blob&)> load) {
    states_.emplace_back(std::move(save), std::move(load));
    return *this;
  }

  // Adds everything registered to `meta` (its kind and config are kept) and writes it.
  void save(const std::string& path, Blob meta = Blob("checkpoint")) const {
    fill(meta);
    meta.save(path);
  }
  void fill(Blob& b) const {
    for (auto& [name, m] : modules_) put_module(b, *m, "module." + name + ".");
    for (auto& [name, o] : optimizers_) o->save_state(b, "optim." + name + ".");
    for (auto& [name, r] : rngs_) b.put("rng." + name, Shape{4}, r->state().data());
    for (auto& c : counters_) b.put_i64("counter." + c.name, *c.value);
    for (auto& st : states_) st.first(b);
  }

  // Restores everything registered from the file and returns the blob (its config).
  // A missing or mis-shaped entry throws naming it; objects restored before the
  // failure keep their new values, so do not train on after a failed load.
  Blob load(const std::string& path) {
    Blob b = Blob::load(path);
    restore(b);
    return b;
  }
  void restore(const Blob& b) {
    for (auto& [name, m] : modules_) get_module(b, *m, "module." + name + ".");
    for (auto& [name, o] : optimizers_) o->load_state(b, "optim." + name + ".");
    for (auto& [name, r] : rngs_) {
      Rng::State s;
      b.read("rng." + name, Shape{4}, s.data());
      r->set_state(s);
    }
    for (auto& c : counters_) {
      const int64_t v = b.get_i64("counter." + c.name);
      if (v < c.lo || v > c.hi)
        throw b.error("counter '" + c.name + "' is " + std::to_string(v) + ", out of range " + std::to_string(c.lo) +
                      ".." + std::to_string(c.hi));
      *c.value = v;
    }
    for (auto& st : states_) st.second(b);
  }

 private:
  std::vector<std::pair<std::string, Module<T>*>> modules_;
  std::vector<std::pair<std::string, Optimizer<T>*>> optimizers_;
  std::vector<std::pair<std::string, Rng*>> rngs_;
  struct Counter {
    std::string name;
    int64_t* value;
    int64_t lo, hi;
  };
  std::vector<Counter> counters_;
  std::vector<std::pair<std::function<void(Blob&)>, std::function<void(const Blob&)>>> states_;
};

}  // namespace nns
