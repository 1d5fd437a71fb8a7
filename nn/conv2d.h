#pragma once
// Conv2d layer (PyTorch's nn.Conv2d), parameters "weight" (out, in/groups, kh, kw) and
// "bias" (out), PyTorch's default initialisation drawn from the Rng given first:
//
//   Rng rng(1);
//   Conv2d<float> down(rng, 64, 128, /*k=*/4, /*stride=*/2, /*padding=*/1, /*bias=*/false);
//   Conv2d<float> wide(rng, 8, 8, /*kh=*/3, /*kw=*/5, Conv2dParams{.pad_h = 1, .pad_w = 2});
#include <cstdint>

#include "core/rng.h"
#include "nn/conv_parameters.h"
#include "nn/functional/conv2d.h"

namespace nns {

template <class T = float>
class Conv2d : public ConvLayerBase<T> {
 public:
  // Square kernel, same stride/padding/dilation in both directions.
  Conv2d(Rng& rng, int64_t in_channels, int64_t out_channels, int kernel_size, int stride = 1, int padding = 0,
         bool bias = true, int dilation = 1, int groups = 1)
      : Conv2d(rng, in_channels, out_channels, kernel_size, kernel_size,
               Conv2dParams::square(stride, padding, dilation, groups), bias) {}

  Conv2d(Rng& rng, int64_t in_channels, int64_t out_channels, int kernel_h, int kernel_w, const Conv2dParams& params,
         bool bias = true)
      : in_channels(in_channels), out_channels(out_channels), params(params) {
    this->check_groups("Conv2d", in_channels, out_channels, params.groups);
    const int64_t fan_in = in_channels / params.groups * kernel_h * kernel_w;
    this->init_parameters({out_channels, in_channels / params.groups, kernel_h, kernel_w}, out_channels, fan_in, bias,
                          rng);
  }

  Var<T> forward(const Var<T>& x) override { return conv2d(x, this->weight, this->bias, params); }

  const int64_t in_channels, out_channels;
  const Conv2dParams params;
};

}  // namespace nns
