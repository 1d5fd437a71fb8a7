#pragma once
// Module: a node of a model tree that owns parameters (learnable Vars), buffers
// (non-learnable state such as batchnorm's running statistics) and child modules.
//
// Names are dotted paths ("down.0.conv.weight") so weights save and load by name.
// Train/eval is an explicit mode set on the whole tree; nothing infers it from the
// batch size (pix2pix trains batchnorm at batch size 1).
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/autograd.h"
#include "core/rng.h"

namespace nns {

template <class T = float>
class Module {
 public:
  virtual ~Module() = default;

  void train(bool on = true) {
    training_ = on;
    for (auto& [name, child] : children_) child->train(on);
  }
  void eval() { train(false); }
  bool is_training() const { return training_; }

  std::vector<std::pair<std::string, Var<T>>> named_parameters(const std::string& prefix = "") const {
    std::vector<std::pair<std::string, Var<T>>> out;
    collect_parameters(prefix, out);
    return out;
  }
  std::vector<Var<T>> parameters() const {
    std::vector<Var<T>> out;
    for (auto& [name, v] : named_parameters()) out.push_back(v);
    return out;
  }
  // Buffers are returned by reference so a loader can overwrite them in place.
  std::vector<std::pair<std::string, Tensor<T>*>> named_buffers(const std::string& prefix = "") {
    std::vector<std::pair<std::string, Tensor<T>*>> out;
    collect_buffers(prefix, out);
    return out;
  }
  // Random generators owned by modules (dropout masks); part of a checkpoint so that a
  // resumed run draws the same numbers as an uninterrupted one.
  std::vector<std::pair<std::string, Rng*>> named_rngs(const std::string& prefix = "") {
    std::vector<std::pair<std::string, Rng*>> out;
    for (auto& [name, r] : rngs_) out.emplace_back(join(prefix, name), r.get());
    for (auto& [name, c] : children_)
      for (auto& e : c->named_rngs(join(prefix, name))) out.push_back(e);
    return out;
  }

  // Layers with one input and one output override this (Sequential composes them).
  virtual Var<T> forward(const Var<T>& x) { throw std::logic_error("this module has no single-input forward()"); }

  void zero_grad() {
    for (auto& p : parameters()) p.zero_grad();
  }
  int64_t parameter_count() const {
    int64_t n = 0;
    for (auto& p : parameters()) n += p.numel();
    return n;
  }

 protected:
  // Returns a handle sharing the parameter's node: keep it as a member.
  Var<T> register_parameter(const std::string& name, Tensor<T> value) {
    params_.emplace_back(name, Var<T>(std::move(value), /*requires_grad=*/true));
    return params_.back().second;
  }
  Tensor<T>& register_buffer(const std::string& name, Tensor<T> value) {
    buffers_.emplace_back(name, std::make_unique<Tensor<T>>(std::move(value)));
    return *buffers_.back().second;
  }
  Rng& register_rng(const std::string& name, uint64_t seed) {
    rngs_.emplace_back(name, std::make_unique<Rng>(seed));
    return *rngs_.back().second;
  }
  template <class M>
  std::shared_ptr<M> register_module(const std::string& name, std::shared_ptr<M> m) {
    m->train(training_);
    children_.emplace_back(name, m);
    return m;
  }

 private:
  static std::string join(const std::string& prefix, const std::string& name) {
    return prefix.empty() ? name : prefix + "." + name;
  }
  void collect_parameters(const std::string& prefix, std::vector<std::pair<std::string, Var<T>>>& out) const {
    for (auto& [name, v] : params_) out.emplace_back(join(prefix, name), v);
    for (auto& [name, c] : children_) c->collect_parameters(join(prefix, name), out);
  }
  void collect_buffers(const std::string& prefix, std::vector<std::pair<std::string, Tensor<T>*>>& out) {
    for (auto& [name, b] : buffers_) out.emplace_back(join(prefix, name), b.get());
    for (auto& [name, c] : children_) c->collect_buffers(join(prefix, name), out);
  }

  bool training_ = true;
  std::vector<std::pair<std::string, Var<T>>> params_;
  std::vector<std::pair<std::string, std::unique_ptr<Tensor<T>>>> buffers_;
  std::vector<std::pair<std::string, std::unique_ptr<Rng>>> rngs_;
  std::vector<std::pair<std::string, std::shared_ptr<Module<T>>>> children_;
};

}  // namespace nns
