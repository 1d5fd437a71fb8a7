#pragma once
// An exponential moving average of parameters (Polyak averaging; the averaged generator
// of GAN practice: Yazici et al., "The Unusual Effectiveness of Averaging in GAN
// Training", ICLR 2019). After every optimizer step
//
//   avg = d avg + (1 - d) w,   d = min(decay, (1 + t) / (10 + t)),  t = updates so far
//
// The ramp (TensorFlow's ExponentialMovingAverage with num_updates) lets the random
// initial weights fade within the first few hundred steps instead of 1/(1-decay) x more.
// A batch-1 GAN's weights wander from step to step; the average is the point they
// wander around. swap() exchanges the averages with the live weights: swap, save or
// score, swap back. Buffers (BatchNorm's running statistics) are not averaged.
//
// Elementwise in a fixed order, so the average is the same with any thread count; its
// state (the averages and t) goes into a checkpoint so a resumed run continues bitwise.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/autograd.h"
#include "core/blob.h"

namespace nns {

template <class T>
class WeightAverage {
 public:
  WeightAverage(std::vector<Var<T>> params, double decay) : params_(std::move(params)), decay_(decay) {
    if (!(decay >= 0 && decay < 1)) throw std::invalid_argument("weight average: decay must be in [0, 1)");
    for (auto& p : params_) avg_.push_back(p.value().clone());
  }

  double decay_at(int64_t t) const { return std::min(decay_, double(1 + t) / double(10 + t)); }

  void update() {
    const T d = T(decay_at(updates_)), e = T(1) - d;
    for (size_t i = 0; i < params_.size(); ++i) {
      const T* w = params_[i].value().data();
      T* a = avg_[i].data();
      for (int64_t j = 0, n = avg_[i].numel(); j < n; ++j) a[j] = d * a[j] + e * w[j];
    }
    ++updates_;
  }

  // Exchanges the live weights and the averages (twice: back as they were).
  void swap() {
    for (size_t i = 0; i < params_.size(); ++i)
      std::swap_ranges(avg_[i].data(), avg_[i].end(), params_[i].value().data());
  }

  int64_t updates() const { return updates_; }
  const Tensor<T>& average(size_t i) const { return avg_[i]; }

  void save_state(Blob& b, const std::string& prefix) const {
    b.put_i64(prefix + "updates", updates_);
    for (size_t i = 0; i < avg_.size(); ++i) b.put(prefix + std::to_string(i), avg_[i]);
  }
  void load_state(const Blob& b, const std::string& prefix) {
    const int64_t t = b.get_i64(prefix + "updates");
    if (t < 0) throw b.error(prefix + "updates is " + std::to_string(t) + ", not a count");
    for (size_t i = 0; i < avg_.size(); ++i) b.read(prefix + std::to_string(i), avg_[i].shape(), avg_[i].data());
    updates_ = t;
  }

 private:
  std::vector<Var<T>> params_;
  std::vector<Tensor<T>> avg_;
  double decay_;
  int64_t updates_ = 0;
};

}  // namespace nns
