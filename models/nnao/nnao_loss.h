#pragma once
// NNAO's cost (paper, eq. 2): mean squared error + gamma * |theta|, where |theta| is the
// L1 norm (sum of absolute values) of every parameter: weights, biases, alpha, beta.
#include <vector>

#include "nn/functional/elementwise.h"
#include "nn/losses/mse.h"
#include "nn/losses/penalties.h"

namespace nns::nnao {

template <class T>
Var<T> nnao_loss(const Var<T>& pred, const Var<T>& target, const std::vector<Var<T>>& params, T gamma) {
  Var<T> loss = mse_loss(pred, target);
  if (gamma == T(0)) return loss;
  return loss + l1_penalty(params) * gamma;
}

}  // namespace nns::nnao
