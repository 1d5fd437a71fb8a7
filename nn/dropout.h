#pragma once
// Dropout(p, seed): inverted dropout, active only in training mode. The mask generator
// is registered as "rng", so a checkpoint saves its state and a resumed run draws the
// same masks as an uninterrupted one.
#include <cstdint>

#include "nn/functional/dropout.h"
#include "nn/module.h"

namespace nns {

template <class T = float>
class Dropout : public Module<T> {
 public:
  explicit Dropout(double p = 0.5, uint64_t seed = 0) : p_(p), rng_(&this->register_rng("rng", seed)) {}
  Var<T> forward(const Var<T>& x) override { return dropout(x, p_, this->is_training(), *rng_); }
  double p() const { return p_; }

 private:
  double p_;
  Rng* rng_;
};

}  // namespace nns
