// The GI generator's frame-level head reads statistics of its whole input view
// (models/gi/frame_level_features.h) once per frame: 12 channels of the default's
// 128 x 256 global view at face 64, with and without the energy features. Reported per
// call on one thread; against a 5-6 ms frame (network at 64 + guided upsample) it should
// stay a few percent. Before timing, the features are checked against one plain running
// sum per feature.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/rng.h"
#include "core/tensor.h"
#include "models/gi/frame_level_features.h"

using namespace nns;

namespace {

Tensor<float> view(uint64_t seed) {
  Rng rng(seed);
  Tensor<float> t({1, 12, 128, 256});
  for (auto& v : t) v = float(rng.uniform() * 1.8 - 0.9);
  return t;
}

// One running sum per feature: the definition, for the check.
Tensor<double> plain_features(const Tensor<float>& x) {
  const int64_t C = x.size(1), n = x.size(2) * x.size(3);
  Tensor<double> f({1, 2 * C + 6});
  for (int64_t c = 0; c < C; ++c) {
    double m = 0, q = 0;
    for (int64_t i = 0; i < n; ++i) m += x[c * n + i], q += double(x[c * n + i]) * x[c * n + i];
    f[c] = m / double(n), f[C + c] = q / double(n);
  }
  for (int64_t c = 0; c < 3; ++c) {
    double l = 0, al = 0;
    for (int64_t i = 0; i < n; ++i) {
      const double u = std::clamp(0.5 * (x[(gi::kLuminationChannel + c) * n + i] + 1.0), 0.0, 1.0 - 0x1.0p-20);
      l += u / (1 - u), al += 0.5 * (x[(gi::kAlbedoChannel + c) * n + i] + 1.0) * u / (1 - u);
    }
    f[2 * C + c] = std::log(l / double(n) + 1e-3), f[2 * C + 3 + c] = std::log(al / double(n) + 1e-3);
  }
  return f;
}

void check_once() {
  static bool done = false;
  if (done) return;
  done = true;
  const Tensor<float> x = view(1);
  const Tensor<float> f = gi::frame_level_features(x, true);
  const Tensor<double> ref = plain_features(x);
  for (int64_t i = 0; i < f.numel(); ++i)
    if (std::abs(double(f[i]) - ref[i]) > 1e-6 * std::max(1.0, std::abs(ref[i]))) {
      std::fprintf(stderr, "frame_level_features: feature %lld is %g, the plain sum gives %g\n", (long long)i,
                   double(f[i]), ref[i]);
      std::exit(1);
    }
}

void BM_FrameLevelFeatures(benchmark::State& state) {
  check_once();
  const Tensor<float> x = view(2);
  const bool energy = state.range(0) != 0;
  for (auto _ : state) {
    Tensor<float> f = gi::frame_level_features(x, energy);
    benchmark::DoNotOptimize(f.data());
  }
}
BENCHMARK(BM_FrameLevelFeatures)->Arg(0)->Arg(1)->ArgName("energy")->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
