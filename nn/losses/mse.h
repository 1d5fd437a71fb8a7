#pragma once
// mse_loss(pred, target) = mean((pred - target)^2)  (PyTorch's MSELoss, reduction mean)
#include <type_traits>

#include "core/kernels/pointwise_losses.h"
#include "nn/losses/pointwise_loss.h"

namespace nns {

template <class T>
Var<T> mse_loss(const Var<T>& pred, const Var<T>& target) {
  return pointwise_loss(pred, target, "mse_loss", mse_loss_forward<T>, mse_loss_backward<T>);
}

// Against a constant target value (LSGAN's real/fake labels).
template <class T>
Var<T> mse_loss(const Var<T>& pred, std::type_identity_t<T> target) {
  return mse_loss(pred, Var<T>(Tensor<T>::full(pred.shape(), target)));
}

}  // namespace nns
