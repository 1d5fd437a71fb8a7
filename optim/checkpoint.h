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
  Checkpoint& add_counter(const std::string& name, int64_t& c) {
    for (auto& [n, p] : counters_)
      if (n == name) return p = &c, *this;
    counters_.emplace_back(name, &c);
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
    for (auto& [name, c] : counters_) b.put_i64("counter." + name, *c);
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
    for (auto& [name, c] : counters_) *c = b.get_i64("counter." + name);
    for (auto& st : states_) st.second(b);
  }

 private:
  std::vector<std::pair<std::string, Module<T>*>> modules_;
  std::vector<std::pair<std::string, Optimizer<T>*>> optimizers_;
  std::vector<std::pair<std::string, Rng*>> rngs_;
  std::vector<std::pair<std::string, int64_t*>> counters_;
  std::vector<std::pair<std::function<void(Blob&)>, std::function<void(const Blob&)>>> states_;
};

}  // namespace nns
