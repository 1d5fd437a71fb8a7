#pragma once
// PReLUBeta(C): NNAO's activation f = beta * max(x, 0) + alpha * min(x, 0) with
// learnable "alpha" and "beta" of shape (C), per unit for (N, C) inputs and per channel
// for (N, C, H, W). Defaults alpha = 0.25 (PyTorch's PReLU) and beta = 1, so a fresh
// layer is PyTorch's PReLU.
#include "nn/functional/prelu_beta.h"
#include "nn/module.h"

namespace nns {

template <class T = float>
class PReLUBeta : public Module<T> {
 public:
  explicit PReLUBeta(int64_t channels, double alpha0 = 0.25, double beta0 = 1.0) {
    alpha = this->register_parameter("alpha", Tensor<T>::full({channels}, T(alpha0)));
    beta = this->register_parameter("beta", Tensor<T>::full({channels}, T(beta0)));
  }
  Var<T> forward(const Var<T>& x) override { return prelu_beta(x, alpha, beta); }

  Var<T> alpha, beta;
};

}  // namespace nns
