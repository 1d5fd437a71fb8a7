#pragma once
// The GAN's losses in the form the trainer uses them.
//  * bce_with_logits_target(logits, t): BCE of every PatchGAN logit against the constant
//    label t (1 real, 0 fake), mean over patches, in the stable logits form.
//  * dssim_tanh(pred, target): Deep Shading's (1 - SSIM) / 2 for images in Tanh's range,
//    mapped to [0, 1] first because SSIM's constants assume that range.
//  * gradient_l1(pred, target): L1 between the images' finite differences, across and
//    down, each term a mean: it is zero for an error that is constant over a region and
//    large where an edge is soft or misplaced, so it weighs the contact detail (dark
//    creases, shadow edges) that a per-pixel L1 spends little on.
#include "core/autograd.h"
#include "models/gi/crop.h"
#include "nn/functional/elementwise.h"
#include "nn/losses/bce.h"
#include "nn/losses/dssim.h"
#include "nn/losses/l1.h"

namespace nns::gi {

template <class T>
Var<T> bce_with_logits_target(const Var<T>& logits, T label) {
  return bce_with_logits_loss(logits, Var<T>(Tensor<T>::full(logits.shape(), label)));
}

template <class T>
Var<T> dssim_tanh(const Var<T>& pred, const Var<T>& target) {
  return dssim_loss(pred * T(0.5) + T(0.5), target * T(0.5) + T(0.5));
}

// Finite differences of an NCHW image: x[:, :, :, 1:] - x[:, :, :, :-1] (across) or the
// same down the rows.
template <class T>
Var<T> finite_difference(const Var<T>& x, bool across) {
  const int64_t H = x.shape()[2], W = x.shape()[3];
  const Rect from = across ? Rect{0, 0, W - 1, H} : Rect{0, 0, W, H - 1};
  const Rect to = across ? Rect{1, 0, W - 1, H} : Rect{0, 1, W, H - 1};
  return crop2d(x, to) - crop2d(x, from);
}

template <class T>
Var<T> gradient_l1(const Var<T>& pred, const Var<T>& target) {
  if (pred.shape().dim() != 4 || pred.shape()[2] < 2 || pred.shape()[3] < 2)
    throw std::invalid_argument("gradient_l1: expects NCHW images of at least 2x2, got " + pred.shape().str());
  return l1_loss(finite_difference(pred, true), finite_difference(target, true)) +
         l1_loss(finite_difference(pred, false), finite_difference(target, false));
}

}  // namespace nns::gi
