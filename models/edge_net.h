#pragma once
// The demo's network: conv 3x3 -> batchnorm -> relu -> conv 3x3, enough to learn an
// edge detector |sobel_x * x| + |sobel_y * x| exactly (relu(a) + relu(-a) = |a|).
#include <cstdint>
#include <memory>

#include "core/rng.h"
#include "nn/batchnorm.h"
#include "nn/conv2d.h"
#include "nn/functional/activations.h"
#include "nn/module.h"

namespace nns {

struct EdgeNet : Module<float> {
  EdgeNet(uint64_t seed, int64_t width) {
    Rng init(seed);
    conv1 = register_module("conv1", std::make_shared<Conv2d<float>>(init, 1, width, 3, 1, 1));
    norm = register_module("norm", std::make_shared<BatchNorm2d<float>>(width));
    conv2 = register_module("conv2", std::make_shared<Conv2d<float>>(init, width, 1, 3, 1, 1));
  }
  Var<float> forward(const Var<float>& x) override { return conv2->forward(relu(norm->forward(conv1->forward(x)))); }
  std::shared_ptr<Conv2d<float>> conv1, conv2;
  std::shared_ptr<BatchNorm2d<float>> norm;
};

}  // namespace nns
