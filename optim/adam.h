#pragma once
// Adam (Kingma & Ba 2015) with PyTorch's exact update rule and defaults: lr 1e-3,
// betas (0.9, 0.999), eps 1e-8, weight decay 0 (off; L2 through the gradient, not
// AdamW). pix2pix uses lr 2e-4 and betas (0.5, 0.999): pass them explicitly.
#include <cmath>

#include "optim/adam_kernel.h"
#include "optim/optimizer.h"

namespace nns {

struct AdamOptions {
  double lr = 1e-3;
  double beta1 = 0.9;
  double beta2 = 0.999;
  double eps = 1e-8;
  double weight_decay = 0;
};

template <class T>
class Adam : public Optimizer<T> {
 public:
  explicit Adam(std::vector<Var<T>> params, AdamOptions o = {}) : Optimizer<T>(std::move(params), o.lr), o_(o) {
    if (!(o.beta1 >= 0 && o.beta1 < 1 && o.beta2 >= 0 && o.beta2 < 1))
      throw std::invalid_argument("Adam: betas must be in [0, 1)");
    if (!(o.eps >= 0) || !(o.weight_decay >= 0)) throw std::invalid_argument("Adam: eps and weight_decay must be >= 0");
    m_ = this->zeros_like_params();
    v_ = this->zeros_like_params();
    steps_.assign(this->params_.size(), 0);
  }

  const AdamOptions& options() const { return o_; }
  // Steps taken by parameter i (PyTorch keeps one count per parameter, so a parameter
  // skipped for lack of a gradient keeps its own bias correction).
  int64_t steps(size_t i = 0) const { return steps_.at(i); }

  // For each parameter p with gradient g, at its step t = 1, 2, ...:
  //   g <- g + weight_decay * p
  //   m <- beta1 * m + (1 - beta1) * g       (computed as PyTorch's lerp, see adam_kernel.h)
  //   v <- beta2 * v + (1 - beta2) * g^2
  //   p <- p - (lr / (1 - beta1^t)) * m / (sqrt(v) / sqrt(1 - beta2^t) + eps)
  // eps is added to the bias-corrected sqrt(v), outside the root, as in PyTorch; the
  // corrections are computed in double, as PyTorch computes them in Python floats.
  // The loop itself is adam_update() in optim/adam_kernel.h.
  void step() override {
    for (size_t i = 0; i < this->params_.size(); ++i) {
      Var<T>& p = this->params_[i];
      if (!p.grad().defined()) continue;
      const int64_t t = ++steps_[i];
      const AdamCoeffs<T> c{T(o_.beta1),        T(1 - o_.beta1),
                            T(o_.beta2),        T(1 - o_.beta2),
                            T(o_.weight_decay), T(std::sqrt(1 - std::pow(o_.beta2, double(t)))),
                            T(o_.eps),          T(this->lr_ / (1 - std::pow(o_.beta1, double(t))))};
      T* w = p.value().data();
      const T* g = p.grad().data();
      T* m = m_[i].data();
      T* v = v_[i].data();
      this->for_elements(p.numel(), [&](int64_t begin, int64_t end) {
        adam_update(w + begin, m + begin, v + begin, g + begin, end - begin, c);
      });
    }
  }

  void save_state(Blob& b, const std::string& prefix) const override {
    b.put_f64(prefix + "lr", this->lr_);
    b.put(prefix + "steps", Shape{int64_t(steps_.size())}, steps_.data());
    for (size_t i = 0; i < m_.size(); ++i) {
      b.put(this->key(prefix, i, "m"), m_[i]);
      b.put(this->key(prefix, i, "v"), v_[i]);
    }
  }
  void load_state(const Blob& b, const std::string& prefix) override {
    this->load_lr(b, prefix + "lr");
    b.read(prefix + "steps", Shape{int64_t(steps_.size())}, steps_.data());
    for (size_t i = 0; i < m_.size(); ++i) {
      b.read(this->key(prefix, i, "m"), m_[i].shape(), m_[i].data());
      b.read(this->key(prefix, i, "v"), v_[i].shape(), v_[i].data());
    }
  }

 private:
  AdamOptions o_;
  std::vector<Tensor<T>> m_, v_;  // first and second moments, shaped like each parameter
  std::vector<int64_t> steps_;
};

}  // namespace nns
