// BatchNorm2d kernels (train-mode forward, backward) on pix2pix U-Net activation shapes,
// next to a memcpy of the same traffic. bytes/s counts the minimum traffic: forward
// reads x and writes y (8 bytes per element); backward reads x, dy, dx and writes dx
// (16 bytes per element). A channel is reduced while hot in cache, so re-reads inside
// a channel are not counted. Target: within 1.5x of BM_Memcpy at the same bytes.
// Args: N, C, H*W side, threads. Before timing, the forward output is checked against
// a plain double-precision computation.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstring>

#include "core/kernels/batch_norm.h"
#include "core/rng.h"
#include "core/tensor.h"

using namespace nns;

namespace {

Tensor<float> randn(const Shape& s, uint64_t seed, double mean = 0) {
  Rng rng(seed);
  Tensor<float> t(s);
  for (auto& v : t) v = float(rng.normal(mean, 1.0));
  return t;
}

void set_bytes(benchmark::State& state, double bytes) {
  state.counters["bytes/s"] =
      benchmark::Counter(bytes, benchmark::Counter::kIsIterationInvariantRate, benchmark::Counter::kIs1024);
}

struct Case {
  int64_t N, C, HW;
  Tensor<float> x, y, dy, dx, gamma, beta, mean, var, rstd;
  explicit Case(benchmark::State& s)
      : N(s.range(0)),
        C(s.range(1)),
        HW(s.range(2) * s.range(2)),
        x(randn({N, C, HW}, 1, 0.5)),
        y(Shape{N, C, HW}),
        dy(randn({N, C, HW}, 2)),
        dx(Tensor<float>::zeros({N, C, HW})),
        gamma(randn({C}, 3, 1.0)),
        beta(randn({C}, 4)),
        mean(Shape{C}),
        var(Shape{C}),
        rstd(Shape{C}) {}
  void forward() {
    batch_norm_forward_train(y.data(), mean.data(), var.data(), rstd.data(), x.data(), gamma.data(), beta.data(), N, C,
                             HW, 1e-5);
  }
  // Worst deviation of y from (x - mean) / sqrt(var + eps) * gamma + beta in double.
  double check() {
    forward();
    double worst = 0;
    for (int64_t c = 0; c < C; c += 7) {
      double s = 0, q = 0;
      for (int64_t n = 0; n < N; ++n)
        for (int64_t i = 0; i < HW; ++i) s += x[(n * C + c) * HW + i];
      const double mu = s / double(N * HW);
      for (int64_t n = 0; n < N; ++n)
        for (int64_t i = 0; i < HW; ++i) q += std::pow(x[(n * C + c) * HW + i] - mu, 2);
      const double r = 1 / std::sqrt(q / double(N * HW) + 1e-5);
      for (int64_t i = 0; i < HW; i += 13) {
        const double want = (x[c * HW + i] - mu) * r * gamma[c] + beta[c];
        worst = std::max(worst, std::abs(want - y[c * HW + i]));
      }
    }
    return worst;
  }
};

void BM_Memcpy(benchmark::State& state) {
  const int64_t n = state.range(0) * state.range(1) * state.range(2) * state.range(2);
  Tensor<float> a = randn({n}, 1), b(Shape{n});
  for (auto _ : state) {
    std::memcpy(b.data(), a.data(), sizeof(float) * size_t(n));
    benchmark::DoNotOptimize(b.data());
    benchmark::ClobberMemory();
  }
  set_bytes(state, 8.0 * double(n));
}

void BM_BatchNormForward(benchmark::State& state) {
  set_num_threads(int(state.range(3)));
  Case k(state);
  if (k.check() > 1e-4) state.SkipWithError("batch_norm_forward_train disagrees with the definition");
  for (auto _ : state) {
    k.forward();
    benchmark::DoNotOptimize(k.y.data());
    benchmark::ClobberMemory();
  }
  set_bytes(state, 8.0 * double(k.N * k.C * k.HW));
}

void BM_BatchNormBackward(benchmark::State& state) {
  set_num_threads(int(state.range(3)));
  Case k(state);
  k.forward();
  Tensor<float> dg = Tensor<float>::zeros({k.C}), db = Tensor<float>::zeros({k.C});
  for (auto _ : state) {
    batch_norm_backward(k.dx.data(), dg.data(), db.data(), k.dy.data(), k.x.data(), k.gamma.data(), k.mean.data(),
                        k.rstd.data(), k.N, k.C, k.HW, true);
    benchmark::DoNotOptimize(k.dx.data());
    benchmark::ClobberMemory();
  }
  set_bytes(state, 16.0 * double(k.N * k.C * k.HW));
}

// pix2pix generator activations at 256x256, batch 1.
void shapes(benchmark::internal::Benchmark* b) {
  for (auto [C, S] : {std::pair{64, 128}, {128, 64}, {256, 32}, {512, 4}})
    for (int t : {1, 2}) b->Args({1, C, S, t});
  b->UseRealTime();
}
void memcpy_shapes(benchmark::internal::Benchmark* b) {
  for (auto [C, S] : {std::pair{64, 128}, {128, 64}, {256, 32}, {512, 4}}) b->Args({1, C, S});
  b->UseRealTime();
}

}  // namespace

BENCHMARK(BM_Memcpy)->Apply(memcpy_shapes);
BENCHMARK(BM_BatchNormForward)->Apply(shapes);
BENCHMARK(BM_BatchNormBackward)->Apply(shapes);
BENCHMARK_MAIN();
