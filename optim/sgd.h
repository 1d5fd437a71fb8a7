#pragma once
// SGD with optional momentum and Nesterov momentum, PyTorch's formulation with
// dampening 0: the velocity accumulates raw gradients and the learning rate is applied
// at the update (not Sutskever's lr-inside-the-velocity form).
#include "optim/optimizer.h"

namespace nns {

struct SgdOptions {
  double lr = 1e-2;
  double momentum = 0;
  bool nesterov = false;
  double weight_decay = 0;
};

template <class T>
class Sgd : public Optimizer<T> {
 public:
  explicit Sgd(std::vector<Var<T>> params, SgdOptions o = {}) : Optimizer<T>(std::move(params), o.lr), o_(o) {
    if (!(o.momentum >= 0) || !(o.weight_decay >= 0))
      throw std::invalid_argument("SGD: momentum and weight_decay must be >= 0");
    if (o.nesterov && o.momentum == 0) throw std::invalid_argument("SGD: nesterov needs a momentum > 0");
    if (o.momentum != 0) buf_ = this->zeros_like_params();
  }

  const SgdOptions& options() const { return o_; }

  // For each parameter p with gradient g:
  //   g <- g + weight_decay * p
  //   b <- momentum * b + g                 (b starts at 0: the first step gives b = g,
  //                                          which is PyTorch's clone of the gradient)
  //   g <- nesterov ? g + momentum * b : b   (only when momentum > 0)
  //   p <- p - lr * g
  void step() override {
    const T lr = T(this->lr_), mu = T(o_.momentum), wd = T(o_.weight_decay);
    const bool use_momentum = o_.momentum != 0, nesterov = o_.nesterov;
    for (size_t i = 0; i < this->params_.size(); ++i) {
      Var<T>& p = this->params_[i];
      if (!p.grad().defined()) continue;
      T* w = p.value().data();
      const T* g = p.grad().data();
      T* b = use_momentum ? buf_[i].data() : nullptr;
      this->for_elements(p.numel(), [&](int64_t begin, int64_t end) {
        for (int64_t k = begin; k < end; ++k) {
          T gk = g[k] + wd * w[k];
          if (use_momentum) {
            b[k] = mu * b[k] + gk;
            gk = nesterov ? gk + mu * b[k] : b[k];
          }
          w[k] -= lr * gk;
        }
      });
    }
  }

  void save_state(Blob& b, const std::string& prefix) const override {
    b.put_f64(prefix + "lr", this->lr_);
    for (size_t i = 0; i < buf_.size(); ++i) b.put(this->key(prefix, i, "momentum"), buf_[i]);
  }
  void load_state(const Blob& b, const std::string& prefix) override {
    this->load_lr(b, prefix + "lr");
    for (size_t i = 0; i < buf_.size(); ++i) b.read(this->key(prefix, i, "momentum"), buf_[i].shape(), buf_[i].data());
  }

 private:
  SgdOptions o_;
  std::vector<Tensor<T>> buf_;  // momentum buffers, shaped like each parameter (if momentum)
};

}  // namespace nns
