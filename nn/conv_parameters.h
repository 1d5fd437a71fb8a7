#pragma once
// What Conv2d and ConvTranspose2d share: the groups check, and the weight and optional
// bias with PyTorch's default initialisation U(-1/sqrt(fan_in), 1/sqrt(fan_in)).
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/rng.h"
#include "nn/linear.h"  // fan_in_uniform_init
#include "nn/module.h"

namespace nns {

template <class T>
class ConvLayerBase : public Module<T> {
 public:
  Var<T> weight;
  Var<T> bias;  // undefined when built without bias

 protected:
  static void check_groups(const char* layer, int64_t in_channels, int64_t out_channels, int groups) {
    if (groups <= 0 || in_channels % groups || out_channels % groups)
      throw std::invalid_argument(std::string(layer) + ": groups=" + std::to_string(groups) + " must divide in (" +
                                  std::to_string(in_channels) + ") and out (" + std::to_string(out_channels) +
                                  ") channels");
  }

  // Weight first, then bias, from the same Rng: the order fixes the numbers a seed gives.
  void init_parameters(const Shape& weight_shape, int64_t bias_size, int64_t fan_in, bool with_bias, Rng& rng) {
    Tensor<T> w(weight_shape);
    fan_in_uniform_init(w, fan_in, rng);
    weight = this->register_parameter("weight", std::move(w));
    if (with_bias) {
      Tensor<T> b({bias_size});
      fan_in_uniform_init(b, fan_in, rng);
      bias = this->register_parameter("bias", std::move(b));
    }
  }
};

}  // namespace nns
