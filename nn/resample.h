#pragma once
// AvgPool2x2 and UpsampleBilinear2x modules (Deep Shading's U-Net), for Sequential.
#include "nn/functional/resample.h"
#include "nn/module.h"

namespace nns {

template <class T = float>
class AvgPool2x2 : public Module<T> {
 public:
  Var<T> forward(const Var<T>& x) override { return avg_pool2x2(x); }
};

template <class T = float>
class UpsampleBilinear2x : public Module<T> {
 public:
  Var<T> forward(const Var<T>& x) override { return upsample_bilinear2x(x); }
};

}  // namespace nns
