#pragma once
// The few layer shapes pix2pix's networks are made of, so unet.h and patchgan.h read
// like the paper: every conv is 4x4 with padding 1 (stride 2 unless told), BatchNorm2d
// has PyTorch's defaults, LeakyReLU's slope is 0.2. Initial values are overwritten by
// init_pix2pix (N(0, 0.02) weights, BN gamma N(1, 0.02), zero biases).
#include <memory>

#include "core/rng.h"
#include "nn/batchnorm.h"
#include "nn/conv2d.h"
#include "nn/conv_transpose2d.h"
#include "nn/dropout.h"
#include "nn/functional/activations.h"
#include "nn/functional/concat.h"
#include "nn/init.h"
#include "nn/module.h"

namespace nns::gi {

template <class T>
std::shared_ptr<Module<T>> make_conv(int in, int out, bool bias, Rng& rng, int stride = 2) {
  return std::make_shared<Conv2d<T>>(rng, in, out, /*k=*/4, stride, /*padding=*/1, bias);
}

template <class T>
std::shared_ptr<Module<T>> make_conv_transpose(int in, int out, bool bias, Rng& rng) {
  return std::make_shared<ConvTranspose2d<T>>(rng, in, out, /*k=*/4, /*stride=*/2,
                                              /*padding=*/1, /*output_padding=*/0, bias);
}

template <class T>
std::shared_ptr<Module<T>> make_bn(int channels) {
  return std::make_shared<BatchNorm2d<T>>(channels);
}

template <class T>
std::shared_ptr<Module<T>> make_dropout(float p, uint64_t seed) {
  return std::make_shared<Dropout<T>>(p, seed);
}

}  // namespace nns::gi
