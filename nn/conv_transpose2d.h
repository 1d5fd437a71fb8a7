#pragma once
// ConvTranspose2d layer (PyTorch's nn.ConvTranspose2d), parameters "weight"
// (in, out/groups, kh, kw) and "bias" (out), PyTorch's default initialisation drawn from
// the Rng given first:
//
//   Rng rng(1);
//   ConvTranspose2d<float> up(rng, 128, 64, /*k=*/4, /*stride=*/2, /*padding=*/1);
#include <cstdint>

#include "core/rng.h"
#include "nn/conv_parameters.h"
#include "nn/functional/conv_transpose2d.h"

namespace nns {

template <class T = float>
class ConvTranspose2d : public ConvLayerBase<T> {
 public:
  // Square kernel, same stride/padding/output padding/dilation in both directions.
  ConvTranspose2d(Rng& rng, int64_t in_channels, int64_t out_channels, int kernel_size, int stride = 1, int padding = 0,
                  int output_padding = 0, bool bias = true, int dilation = 1, int groups = 1)
      : ConvTranspose2d(rng, in_channels, out_channels, kernel_size, kernel_size,
                        ConvTranspose2dParams::square(stride, padding, output_padding, dilation, groups), bias) {}

  ConvTranspose2d(Rng& rng, int64_t in_channels, int64_t out_channels, int kernel_h, int kernel_w,
                  const ConvTranspose2dParams& params, bool bias = true)
      : in_channels(in_channels), out_channels(out_channels), params(params) {
    this->check_groups("ConvTranspose2d", in_channels, out_channels, params.groups);
    // PyTorch computes fan_in from the weight's dimension 1, which for a transposed
    // convolution is out_channels/groups: reproduce it so the scales match.
    const int64_t fan_in = out_channels / params.groups * kernel_h * kernel_w;
    this->init_parameters({in_channels, out_channels / params.groups, kernel_h, kernel_w}, out_channels, fan_in, bias,
                          rng);
  }

  Var<T> forward(const Var<T>& x) override { return conv_transpose2d(x, this->weight, this->bias, params); }

  const int64_t in_channels, out_channels;
  const ConvTranspose2dParams params;
};

}  // namespace nns
