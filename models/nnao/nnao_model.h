#pragma once
// The NNAO network (Holden et al. 2016, section 4), as a Module tree:
//   dropout(p) -> fc0 (F -> H) -> PReLU-beta -> fc1 (H -> H) -> PReLU-beta
//              -> fc2 (H -> H) -> PReLU-beta -> fc3 (H -> 1) -> PReLU-beta
// PReLU-beta(x) = beta max(x, 0) + alpha min(x, 0) on every layer (eq. 1); the paper's
// H is 4. Input: standardised features (F of them, nnao_inputs.h: the paper's grid or
// horizon profiles); output: the standardised AO of the centre pixel (minus the
// horizon kind's base). The standardisation statistics are buffers, so they travel
// with the weights in the blob (names in nnao_weights.h).
#include <memory>
#include <string>

#include "core/rng.h"
#include "models/nnao/nnao_inputs.h"
#include "nn/dropout.h"
#include "nn/linear.h"
#include "nn/module.h"
#include "nn/prelu.h"

namespace nns::nnao {

struct NnaoNetConfig {
  int window = 31;
  int hidden = 4;
  double dropout = 0.5;
  // "grid": the paper's w x w grid of normal and depth differences (nnao_features.h,
  // `window`); "horizon": horizon profiles (horizon_features.h, `horizon`).
  std::string features = "grid";
  HorizonLayout horizon;
  InputSpec input() const { return {features, window, horizon}; }
  int64_t inputs() const { return input().count(); }
};

template <class T = float>
class NnaoNet : public Module<T> {
 public:
  NnaoNet(Rng& rng, const NnaoNetConfig& c) : config(c) {
    const int64_t F = c.inputs(), H = c.hidden;
    drop = this->register_module("drop", std::make_shared<Dropout<T>>(c.dropout, rng.next_u64()));
    const int64_t in[4] = {F, H, H, H}, out[4] = {H, H, H, 1};
    for (int l = 0; l < 4; ++l) {
      fc[l] = this->register_module("fc" + std::to_string(l), std::make_shared<Linear<T>>(rng, in[l], out[l]));
      act[l] = this->register_module("act" + std::to_string(l), std::make_shared<PReLUBeta<T>>(out[l]));
    }
    feature_mean = &this->register_buffer("feature_mean", Tensor<T>::zeros({F}));
    feature_std = &this->register_buffer("feature_std", Tensor<T>::ones({F}));
    target_stats = &this->register_buffer("target_stats", Tensor<T>::from({2}, {T(0), T(1)}));
  }

  Var<T> forward(const Var<T>& x) override {
    Var<T> h = drop->forward(x);
    for (int l = 0; l < 4; ++l) h = act[l]->forward(fc[l]->forward(h));
    return h;
  }

  NnaoNetConfig config;
  std::shared_ptr<Dropout<T>> drop;
  std::shared_ptr<Linear<T>> fc[4];
  std::shared_ptr<PReLUBeta<T>> act[4];
  Tensor<T>* feature_mean;  // (F)
  Tensor<T>* feature_std;   // (F)
  Tensor<T>* target_stats;  // (2): mean, std of the AO target
};

}  // namespace nns::nnao
