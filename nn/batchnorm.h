#pragma once
// BatchNorm1d (input (N, C)) and BatchNorm2d (input (N, C, H, W)) with PyTorch's names:
// parameters "weight" (gamma, 1) and "bias" (beta, 0) when affine, buffers
// "running_mean" (0) and "running_var" (1). Train/eval comes from the module's mode.
#include <stdexcept>

#include "nn/functional/batch_norm.h"
#include "nn/module.h"

namespace nns {

template <class T = float>
class BatchNorm : public Module<T> {
 public:
  BatchNorm(int64_t channels, int input_dims, double eps = 1e-5, double momentum = 0.1, bool affine = true)
      : channels_(channels), input_dims_(input_dims), eps_(eps), momentum_(momentum) {
    if (affine) {
      weight = this->register_parameter("weight", Tensor<T>::ones({channels}));
      bias = this->register_parameter("bias", Tensor<T>::zeros({channels}));
    }
    running_mean = &this->register_buffer("running_mean", Tensor<T>::zeros({channels}));
    running_var = &this->register_buffer("running_var", Tensor<T>::ones({channels}));
  }

  Var<T> forward(const Var<T>& x) override {
    if (x.shape().dim() != input_dims_)
      throw std::invalid_argument("BatchNorm" + std::to_string(input_dims_ == 2 ? 1 : 2) + "d: expected a " +
                                  std::to_string(input_dims_) + "-d input, got " + x.shape().str());
    return batch_norm(x, weight, bias, running_mean, running_var, this->is_training(), momentum_, eps_);
  }

  int64_t channels() const { return channels_; }

  Var<T> weight, bias;  // undefined when affine = false
  Tensor<T>* running_mean;
  Tensor<T>* running_var;

 private:
  int64_t channels_;
  int input_dims_;
  double eps_, momentum_;
};

template <class T = float>
class BatchNorm1d : public BatchNorm<T> {
 public:
  explicit BatchNorm1d(int64_t channels, double eps = 1e-5, double momentum = 0.1, bool affine = true)
      : BatchNorm<T>(channels, 2, eps, momentum, affine) {}
};

template <class T = float>
class BatchNorm2d : public BatchNorm<T> {
 public:
  explicit BatchNorm2d(int64_t channels, double eps = 1e-5, double momentum = 0.1, bool affine = true)
      : BatchNorm<T>(channels, 4, eps, momentum, affine) {}
};

}  // namespace nns
