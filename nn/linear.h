#pragma once
// Linear layer (PyTorch's nn.Linear): y = x W^T + b, x (B, in), W (out, in), b (out).
//
//   Rng rng(1);
//   Linear<float> fc(rng, 3844, 4);   // parameters "weight" (4, 3844) and "bias" (4)
//   Var<float> y = fc.forward(x);
#include <cmath>
#include <cstdint>

#include "core/rng.h"
#include "nn/functional/linear.h"
#include "nn/module.h"

namespace nns {

// PyTorch's default initialisation of Linear and Conv layers: kaiming_uniform_ with
// a = sqrt(5) gives bound = gain * sqrt(3 / fan_in) with gain = sqrt(2 / (1 + a^2)),
// i.e. exactly 1 / sqrt(fan_in); the bias uses the same bound. Weight drawn first.
template <class T>
inline void fan_in_uniform_init(Tensor<T>& t, int64_t fan_in, Rng& rng) {
  const double bound = fan_in > 0 ? 1.0 / std::sqrt(double(fan_in)) : 0.0;
  for (auto& v : t) v = T(rng.uniform(-bound, bound));
}

template <class T = float>
class Linear : public Module<T> {
 public:
  Linear(Rng& rng, int64_t in_features, int64_t out_features, bool bias = true)
      : in_features(in_features), out_features(out_features) {
    Tensor<T> w({out_features, in_features});
    fan_in_uniform_init(w, in_features, rng);
    weight = this->register_parameter("weight", std::move(w));
    if (bias) {
      Tensor<T> b({out_features});
      fan_in_uniform_init(b, in_features, rng);
      this->bias = this->register_parameter("bias", std::move(b));
    }
  }

  Var<T> forward(const Var<T>& x) override { return linear(x, weight, bias); }

  const int64_t in_features, out_features;
  Var<T> weight;
  Var<T> bias;  // undefined when built without bias
};

}  // namespace nns
