#pragma once
// Sequential: children "0", "1", ... applied in order (PyTorch's nn.Sequential naming,
// so parameter names read "0.weight", "2.bias").
//   auto net = std::make_shared<Sequential<float>>();
//   net->add(std::make_shared<Linear<float>>(...)); net->add(std::make_shared<ReLU<float>>());
#include <memory>
#include <string>
#include <vector>

#include "nn/module.h"

namespace nns {

template <class T = float>
class Sequential : public Module<T> {
 public:
  Sequential() = default;
  explicit Sequential(std::vector<std::shared_ptr<Module<T>>> layers) {
    for (auto& l : layers) add(std::move(l));
  }

  // Returns the layer, typed, so a caller can keep a handle to it.
  template <class M>
  std::shared_ptr<M> add(std::shared_ptr<M> layer) {
    layers_.push_back(layer);
    return this->register_module(std::to_string(layers_.size() - 1), std::move(layer));
  }

  Var<T> forward(const Var<T>& x) override {
    Var<T> h = x;
    for (auto& l : layers_) h = l->forward(h);
    return h;
  }

  size_t size() const { return layers_.size(); }
  Module<T>& operator[](size_t i) { return *layers_.at(i); }

 private:
  std::vector<std::shared_ptr<Module<T>>> layers_;
};

}  // namespace nns
