#pragma once
// Learning-rate schedules, as a pure function of the (0-based) epoch so a resumed run
// gets the same rate from its restored epoch counter.
//  - constant: base.
//  - linear (pix2pix's lr_policy "linear"): base for n_epochs, then a linear decay
//    towards 0 over n_epochs_decay, with pix2pix's lambda rule
//      factor(epoch) = 1 - max(0, epoch + 1 - n_epochs) / (n_epochs_decay + 1).
#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace nns {

class LrSchedule {
 public:
  enum class Kind { Constant, Linear };

  static LrSchedule constant(double base) { return LrSchedule(Kind::Constant, base, 0, 0); }
  static LrSchedule linear(double base, int64_t n_epochs, int64_t n_epochs_decay) {
    if (n_epochs < 0 || n_epochs_decay < 0)
      throw std::invalid_argument("linear LR schedule: epoch counts must be >= 0");
    return LrSchedule(Kind::Linear, base, n_epochs, n_epochs_decay);
  }

  double at(int64_t epoch) const {
    if (kind_ == Kind::Constant) return base_;
    double decayed = double(std::max<int64_t>(0, epoch + 1 - n_epochs_));
    return base_ * (1.0 - decayed / double(n_epochs_decay_ + 1));
  }
  // Sets the optimizer's rate for `epoch` (call at the start of each epoch).
  template <class Opt>
  void apply(Opt& opt, int64_t epoch) const {
    opt.set_lr(std::max(0.0, at(epoch)));
  }
  Kind kind() const { return kind_; }

 private:
  LrSchedule(Kind k, double base, int64_t n, int64_t nd) : kind_(k), base_(base), n_epochs_(n), n_epochs_decay_(nd) {
    if (!(base >= 0)) throw std::invalid_argument("LR schedule: base rate must be >= 0");
  }
  Kind kind_;
  double base_;
  int64_t n_epochs_, n_epochs_decay_;
};

}  // namespace nns
