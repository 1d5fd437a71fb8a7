#pragma once
// Binary cross-entropy, mean-reduced (PyTorch's BCEWithLogitsLoss and BCELoss):
//   bce_with_logits_loss(logits, target): numerically stable, for a GAN discriminator
//     without a final sigmoid (pix2pix's vanilla GAN loss);
//   bce_loss(prob, target): on probabilities in [0, 1], logs clamped at -100.
// A scalar target (1 for "real", 0 for "fake") stands for a constant tensor of it.
#include <type_traits>

#include "core/kernels/pointwise_losses.h"
#include "nn/losses/pointwise_loss.h"

namespace nns {

template <class T>
Var<T> bce_with_logits_loss(const Var<T>& logits, const Var<T>& target) {
  return pointwise_loss(logits, target, "bce_with_logits_loss", bce_with_logits_loss_forward<T>,
                        bce_with_logits_loss_backward<T>);
}

template <class T>
Var<T> bce_loss(const Var<T>& prob, const Var<T>& target) {
  return pointwise_loss(prob, target, "bce_loss", bce_loss_forward<T>, bce_loss_backward<T>);
}

template <class T>
Var<T> bce_with_logits_loss(const Var<T>& logits, std::type_identity_t<T> target) {
  return bce_with_logits_loss(logits, Var<T>(Tensor<T>::full(logits.shape(), target)));
}

template <class T>
Var<T> bce_loss(const Var<T>& prob, std::type_identity_t<T> target) {
  return bce_loss(prob, Var<T>(Tensor<T>::full(prob.shape(), target)));
}

}  // namespace nns
