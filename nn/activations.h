#pragma once
// Parameter-free activation modules, for Sequential.
#include "nn/functional/activations.h"
#include "nn/module.h"

namespace nns {

template <class T = float>
class ReLU : public Module<T> {
 public:
  Var<T> forward(const Var<T>& x) override { return relu(x); }
};

template <class T = float>
class LeakyReLU : public Module<T> {
 public:
  explicit LeakyReLU(double slope = 0.01) : slope_(slope) {}
  Var<T> forward(const Var<T>& x) override { return leaky_relu(x, slope_); }
  double slope() const { return slope_; }

 private:
  double slope_;
};

template <class T = float>
class Tanh : public Module<T> {
 public:
  Var<T> forward(const Var<T>& x) override { return tanh_act(x); }
};

template <class T = float>
class Sigmoid : public Module<T> {
 public:
  Var<T> forward(const Var<T>& x) override { return sigmoid(x); }
};

}  // namespace nns
