#pragma once
// l1_loss(pred, target) = mean(|pred - target|)  (PyTorch's L1Loss, reduction mean;
// pix2pix's reconstruction term)
#include "core/kernels/pointwise_losses.h"
#include "nn/losses/pointwise_loss.h"

namespace nns {

template <class T>
Var<T> l1_loss(const Var<T>& pred, const Var<T>& target) {
  return pointwise_loss(pred, target, "l1_loss", l1_loss_forward<T>, l1_loss_backward<T>);
}

}  // namespace nns
