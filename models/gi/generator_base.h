#pragma once
// What the trainer, the checkpoint and eval-gi need of a GI generator, whichever network
// it is (the pix2pix U-Net, unet.h, or Deep Shading's U-Net, deep_shading_unet.h).
#include <cstdint>

#include "core/autograd.h"
#include "nn/module.h"

namespace nns::gi {

template <class T = float>
class GiGenerator : public Module<T> {
 public:
  // Switches to evaluation with the chosen test-time behaviour (BatchNorm batch or
  // running statistics, dropout on or off); train() undoes it.
  virtual void set_test_modes(bool bn_batch_stats, bool dropout_on) = 0;
  // Height and width of an input must be multiples of this.
  virtual int64_t size_multiple() const = 0;
  // Per-frame gains (B, 3, 1, 1) for the predicted indirect light, or undefined (none).
  virtual Var<T> level_gain(const Var<T>&) { return Var<T>(); }
};

}  // namespace nns::gi
