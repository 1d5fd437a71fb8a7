#pragma once
// Reverse-mode, define-by-run automatic differentiation (micrograd's engine in C++).
//
// Every op returns a Var whose node records its parents and a backward function.
// backward() on a scalar sorts the graph topologically (iteratively: a deep U-Net must
// not overflow the stack) and runs the backward functions in reverse order.
//
// THE GRADIENT CONTRACT (the one place it is written down):
//  * A backward function ACCUMULATES into its parents' gradients (`dparent += ...`),
//    never assigns. An input used twice simply receives two contributions.
//  * Kernel pairs follow the same rule: `*_backward(dinp, dweight, dbias, dout, ...)`
//    adds into dinp, dweight and dbias (GEMM with beta = 1).
//  * Gradients of leaves (parameters, inputs with requires_grad) accumulate across
//    backward() calls until zero_grad(); intermediate gradients are freed as soon as
//    their backward has run, together with the tensors the op saved.
//  * A gradient buffer is created (zero-filled) the first time something adds to it.
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "core/tensor.h"

namespace nns {

// Gradient recording is on unless a NoGradGuard is alive on this thread.
inline bool& grad_mode_enabled() {
  thread_local bool enabled = true;
  return enabled;
}
class NoGradGuard {
 public:
  NoGradGuard() : prev_(grad_mode_enabled()) { grad_mode_enabled() = false; }
  ~NoGradGuard() { grad_mode_enabled() = prev_; }
  NoGradGuard(const NoGradGuard&) = delete;
  NoGradGuard& operator=(const NoGradGuard&) = delete;

 private:
  bool prev_;
};

template <class T>
struct Node {
  Tensor<T> value;
  Tensor<T> grad;  // undefined until something accumulates into it
  std::vector<std::shared_ptr<Node<T>>> parents;
  // Which parents wanted a gradient when the op was recorded (PyTorch's rule: the graph's
  // edges are fixed then). Reading parents[i]->requires_grad at backward time instead let
  // a GAN's discriminator, frozen while G's adversarial loss was recorded and unfrozen
  // before G's backward, receive G's gradient too (it was trained to call fakes real).
  std::vector<char> parent_wants_grad;
  // Reads this->grad and accumulates into parents[i]->grad_buffer(). It receives the
  // node by reference and must not capture it (a closure owning its node would leak).
  std::function<void(Node<T>&)> backward;
  bool requires_grad = false;
  const char* op = "leaf";
  // On a leaf (a parameter): called once per backward(), when every op that adds to its
  // gradient has run, i.e. the gradient is final. Data-parallel training starts sending
  // a bucket of gradients from here while backward goes on (runs/distributed/grad_sync.h).
  std::function<void()> grad_final;

  Tensor<T>& grad_buffer() {
    if (!grad.defined()) grad = Tensor<T>::zeros(value.shape());
    return grad;
  }

  Node() = default;
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;
  // Releases a long chain iteratively: the default recursive destruction of a deep
  // graph would overflow the stack.
  ~Node() {
    std::vector<std::shared_ptr<Node>> stack = std::move(parents);
    while (!stack.empty()) {
      std::shared_ptr<Node> p = std::move(stack.back());
      stack.pop_back();
      if (p && p.use_count() == 1) {
        for (auto& q : p->parents) stack.push_back(std::move(q));
        p->parents.clear();
      }
    }
  }
};

template <class T>
class Var {
 public:
  Var() = default;
  explicit Var(Tensor<T> value, bool requires_grad = false) : node_(std::make_shared<Node<T>>()) {
    node_->value = std::move(value);
    node_->requires_grad = requires_grad;
  }

  bool defined() const { return node_ != nullptr; }
  const Tensor<T>& value() const { return node_->value; }
  Tensor<T>& value() { return node_->value; }
  const Shape& shape() const { return node_->value.shape(); }
  int64_t size(int i) const { return node_->value.size(i); }
  int64_t numel() const { return node_->value.numel(); }
  // Undefined tensor if no gradient has been accumulated yet.
  const Tensor<T>& grad() const { return node_->grad; }
  Tensor<T>& grad_buffer() { return node_->grad_buffer(); }
  bool requires_grad() const { return node_ && node_->requires_grad; }
  void set_requires_grad(bool r) { node_->requires_grad = r; }
  const char* op() const { return node_->op; }
  const std::shared_ptr<Node<T>>& node() const { return node_; }
  void zero_grad() { node_->grad = Tensor<T>(); }

  // Back-propagates from this scalar (seed 1) or from any tensor with an explicit seed.
  void backward() const {
    if (value().numel() != 1)
      throw std::logic_error("backward() without a seed needs a scalar, got shape " + shape().str());
    backward(Tensor<T>::ones(shape()));
  }
  void backward(const Tensor<T>& seed) const {
    check_shape(seed, shape(), "backward seed");
    if (!node_->requires_grad) throw std::logic_error("backward(): result does not require grad");
    auto order = topological_order();
    // Leaves with a grad_final hook: how many ops still have to add to their gradient.
    std::unordered_map<Node<T>*, int> pending;
    for (auto& n : order)
      if (n->backward)
        for (auto& p : n->parents)
          if (p && p->requires_grad && !p->backward && p->grad_final) ++pending[p.get()];
    Tensor<T>& g = node_->grad_buffer();
    for (int64_t i = 0; i < g.numel(); ++i) g[i] += seed[i];
    for (auto it = order.rbegin(); it != order.rend(); ++it) {
      Node<T>& n = **it;          // `order` owns every node until the loop ends
      if (!n.backward) continue;  // a leaf: keep its gradient
      if (n.grad.defined()) n.backward(n);
      if (!pending.empty())
        for (auto& p : n.parents)
          if (auto f = p ? pending.find(p.get()) : pending.end(); f != pending.end() && --f->second == 0)
            p->grad_final();
      // Free what the op saved and its gradient: the graph is used once.
      n.backward = nullptr;
      n.parents.clear();
      n.parent_wants_grad.clear();
      n.grad = Tensor<T>();
    }
  }

 private:
  // Post-order DFS with an explicit stack: parents come before children.
  std::vector<std::shared_ptr<Node<T>>> topological_order() const {
    std::vector<std::shared_ptr<Node<T>>> order;
    std::unordered_set<Node<T>*> visited;
    std::vector<std::pair<std::shared_ptr<Node<T>>, size_t>> stack{{node_, 0}};
    visited.insert(node_.get());
    while (!stack.empty()) {
      auto& [n, next] = stack.back();
      if (next < n->parents.size()) {
        const auto& p = n->parents[next++];
        if (p && n->parent_wants_grad[next - 1] && visited.insert(p.get()).second) stack.push_back({p, 0});
      } else {
        order.push_back(std::move(n));
        stack.pop_back();
      }
    }
    return order;
  }

  std::shared_ptr<Node<T>> node_;
};

// Records the result of an op. `backward(node)` reads node.grad and accumulates into
// node.parents[i]->grad_buffer() for the parents that require grad. When no parent
// requires grad (or grad mode is off) the result is a plain constant.
template <class T, class Backward>
Var<T> make_result(Tensor<T> value, std::vector<Var<T>> parents, const char* op, Backward&& backward) {
  Var<T> out(std::move(value));
  out.node()->op = op;
  if (!grad_mode_enabled()) return out;
  bool any = false;
  for (const auto& p : parents) any |= p.requires_grad();
  if (!any) return out;
  auto& node = *out.node();
  node.requires_grad = true;
  node.parents.reserve(parents.size());
  node.parent_wants_grad.reserve(parents.size());
  for (auto& p : parents) {
    node.parents.push_back(p.node());
    node.parent_wants_grad.push_back(p.requires_grad());
  }
  node.backward = std::forward<Backward>(backward);
  return out;
}

// True if parent i of a node wants a gradient (saves work in backward functions).
template <class T>
inline bool wants_grad(const Node<T>& n, size_t i) {
  return i < n.parents.size() && n.parents[i] && n.parent_wants_grad[i];
}

}  // namespace nns
