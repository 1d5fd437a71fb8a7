#pragma once
// A random NNAO weights blob with the trainer's tensor names (nnao_weights.h), built
// by hand so inference and export tests do not depend on training.
#include <string>
#include <vector>

#include "core/blob.h"
#include "core/rng.h"

namespace nns::testing {

inline Blob random_nnao_blob(int window, int hidden, uint64_t seed, bool linear_head = false) {
  Rng rng(seed);
  const int64_t F = int64_t(window) * window * 4, H = hidden;
  Blob b("nnao");
  b.set_config("window", window);
  b.set_config("hidden", hidden);
  b.set_config("radius", 0.0);
  auto put = [&](const std::string& name, Shape s, double scale, double offset = 0) {
    std::vector<float> v(size_t(s.numel()));
    for (auto& x : v) x = float(offset + scale * rng.normal());
    b.put(name, s, v.data());
  };
  put("fc0.weight", {H, F}, 0.05);
  put("fc0.bias", {H}, 0.1);
  put("fc1.weight", {H, H}, 0.5);
  put("fc1.bias", {H}, 0.1);
  put("fc2.weight", {H, H}, 0.5);
  put("fc2.bias", {H}, 0.1);
  put("fc3.weight", {1, H}, 0.5);
  put("fc3.bias", {1}, 0.1);
  for (int l = 0; l < 4; ++l) {
    const int64_t n = l == 3 ? 1 : H;
    put("act" + std::to_string(l) + ".alpha", {n}, linear_head ? 0 : 0.1, linear_head ? 1 : 0.25);
    put("act" + std::to_string(l) + ".beta", {n}, linear_head ? 0 : 0.1, 1);
  }
  put("feature_mean", {F}, 0.01);
  std::vector<float> sd(static_cast<size_t>(F));
  for (auto& x : sd) x = float(0.5 + rng.uniform());
  b.put("feature_std", Shape{F}, sd.data());
  std::vector<float> ts = {0.7f, linear_head ? 0.01f : 0.2f};
  b.put("target_stats", Shape{2}, ts.data());
  return b;
}

}  // namespace nns::testing
