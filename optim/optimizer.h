#pragma once
// Optimizer: what Adam and SGD share — the parameters they update (the Vars a model's
// parameters() hands over, sharing their nodes), the learning rate, zero_grad(), and
// saving/restoring their state into a checkpoint blob.
//
// State tensors are named by the parameter's position in the list ("<prefix>3.m"), so
// a checkpoint restores into an optimizer built over the same model the same way.
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/autograd.h"
#include "core/blob.h"
#include "core/thread_pool.h"

namespace nns {

template <class T>
class Optimizer {
 public:
  virtual ~Optimizer() = default;
  Optimizer(const Optimizer&) = delete;
  Optimizer& operator=(const Optimizer&) = delete;

  // Updates every parameter that has a gradient; parameters without one are skipped
  // (their state does not move either), as in PyTorch.
  virtual void step() = 0;

  // Drops the gradients (PyTorch's set_to_none): a parameter that gets no gradient in
  // the next backward is then skipped by step() instead of updated with zeros.
  void zero_grad() {
    for (auto& p : params_) p.zero_grad();
  }

  double lr() const { return lr_; }
  void set_lr(double lr) {
    if (!(lr >= 0)) throw std::invalid_argument("learning rate must be >= 0, got " + std::to_string(lr));
    lr_ = lr;
  }
  const std::vector<Var<T>>& params() const { return params_; }

  // The learning rate of a saved state: a checkpoint is outside bytes, so a value that is
  // no learning rate is an error naming the file (fuzz_checkpoint found a negative one
  // escaping as set_lr's invalid_argument, which names nothing).
  // The ceiling is the trainers' --lr ceiling: a checkpoint holds no rate a flag could not
  // have set (a GAN checkpoint's 1e300 resumed and trained on).
  static constexpr double kMaxLearningRate = 1e9;
  void load_lr(const Blob& b, const std::string& key) {
    const double lr = b.get_f64(key);
    if (!(std::isfinite(lr) && lr >= 0 && lr <= kMaxLearningRate)) {
      char v[32];
      std::snprintf(v, sizeof v, "%g", lr);
      throw std::runtime_error("blob '" + b.source() + "': " + key + " is " + v +
                               ", not a learning rate (expected 0..1e9)");
    }
    lr_ = lr;
  }

  virtual void save_state(Blob& b, const std::string& prefix) const = 0;
  virtual void load_state(const Blob& b, const std::string& prefix) = 0;

 protected:
  Optimizer(std::vector<Var<T>> params, double lr) : params_(std::move(params)) {
    std::set<const void*> seen;
    for (size_t i = 0; i < params_.size(); ++i) {
      if (!params_[i].defined() || !params_[i].requires_grad())
        throw std::invalid_argument("optimizer: parameter " + std::to_string(i) +
                                    " is undefined or does not require grad");
      // A parameter listed twice would be stepped twice per step().
      if (!seen.insert(params_[i].node().get()).second)
        throw std::invalid_argument("optimizer: parameter " + std::to_string(i) + " appears twice in the list");
    }
    set_lr(lr);
  }

  // One zero tensor per parameter, shaped like it (moments, momentum buffers).
  std::vector<Tensor<T>> zeros_like_params() const {
    std::vector<Tensor<T>> out;
    out.reserve(params_.size());
    for (auto& p : params_) out.push_back(Tensor<T>::zeros(p.shape()));
    return out;
  }
  static std::string key(const std::string& prefix, size_t i, const char* what) {
    return prefix + std::to_string(i) + "." + what;
  }
  // Runs f(begin, end) over [0, n). The parameter tensors are small for NNAO (~15k
  // values, stepped millions of times) and large for pix2pix (~54M): small ones run
  // inline without touching the pool at all, large ones are split over the workers.
  template <class F>
  static void for_elements(int64_t n, F&& f) {
    constexpr int64_t kMinParallelWork = int64_t(1) << 15;
    if (n < 2 * kMinParallelWork) f(int64_t(0), n);
    else parallel_for(n, f, kMinParallelWork);
  }

  std::vector<Var<T>> params_;
  double lr_ = 0;
};

}  // namespace nns
