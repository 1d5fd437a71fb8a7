#pragma once
// The GAN's losses in the form the trainer uses them.
//  * bce_with_logits_target(logits, t): BCE of every PatchGAN logit against the constant
//    label t (1 real, 0 fake), mean over patches, in the stable logits form.
//  * dssim_tanh(pred, target): Deep Shading's (1 - SSIM) / 2 for images in Tanh's range,
//    mapped to [0, 1] first because SSIM's constants assume that range.
#include "core/autograd.h"
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

}  // namespace nns::gi
