// Memory-bound elementwise kernels next to a memcpy of the same traffic. Each reports
// bytes/s counting every byte read and written (memcpy of B bytes: 2B), so the ratio to
// BM_Memcpy at the same size is the kernel's efficiency (target: within 1.5x).
// Sizes: 1<<16 floats (cache-resident) and 1<<22 floats (16 MiB, from memory); the
// second argument is the thread count. BM_Dropout times NNAO's input dropout
// (16 x 3844 elements, p = 0.5) per call.
// Before timing, each benchmark checks its kernel against a plain loop.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstring>

#include "core/kernels/activations.h"
#include "core/kernels/binary.h"
#include "core/kernels/dropout.h"
#include "core/rng.h"
#include "core/tensor.h"

using namespace nns;

namespace {

Tensor<float> randn(const Shape& s, uint64_t seed) {
  Rng rng(seed);
  Tensor<float> t(s);
  for (auto& v : t) v = float(rng.normal());
  return t;
}

void set_bytes(benchmark::State& state, double bytes_per_iter) {
  state.counters["bytes/s"] =
      benchmark::Counter(bytes_per_iter, benchmark::Counter::kIsIterationInvariantRate, benchmark::Counter::kIs1024);
}

void BM_Memcpy(benchmark::State& state) {
  const int64_t n = state.range(0);
  Tensor<float> a = randn({n}, 1), b(Shape{n});
  for (auto _ : state) {
    std::memcpy(b.data(), a.data(), sizeof(float) * size_t(n));
    benchmark::DoNotOptimize(b.data());
    benchmark::ClobberMemory();
  }
  set_bytes(state, 2.0 * 4 * double(n));
}

void BM_AddSameShape(benchmark::State& state) {
  const int64_t n = state.range(0);
  set_num_threads(int(state.range(1)));
  Tensor<float> a = randn({n}, 1), b = randn({n}, 2), c(Shape{n});
  BroadcastPlan p = make_broadcast_plan({n}, {n}, "bench");
  add_forward(c.data(), a.data(), b.data(), p);
  for (int64_t i = 0; i < n; i += 997)
    if (c[i] != a[i] + b[i]) state.SkipWithError("add_forward disagrees with a + b");
  for (auto _ : state) {
    add_forward(c.data(), a.data(), b.data(), p);
    benchmark::DoNotOptimize(c.data());
    benchmark::ClobberMemory();
  }
  set_bytes(state, 3.0 * 4 * double(n));
}

// (N, C, H, W) * (C, 1, 1): a per-channel scale, the common broadcast.
void BM_MulPerChannel(benchmark::State& state) {
  const int64_t n = state.range(0), C = 64, N = 1, HW = n / C;
  set_num_threads(int(state.range(1)));
  Tensor<float> a = randn({N, C, HW}, 1), s = randn({C, 1}, 2), c(Shape{N, C, HW});
  BroadcastPlan p = make_broadcast_plan(a.shape(), s.shape(), "bench");
  mul_forward(c.data(), a.data(), s.data(), p);
  for (int64_t i = 0; i < n; i += 997)
    if (c[i] != a[i] * s[(i / HW) % C]) state.SkipWithError("mul_forward broadcast is wrong");
  for (auto _ : state) {
    mul_forward(c.data(), a.data(), s.data(), p);
    benchmark::DoNotOptimize(c.data());
    benchmark::ClobberMemory();
  }
  set_bytes(state, 2.0 * 4 * double(n));
}

void BM_LeakyReluBackward(benchmark::State& state) {
  const int64_t n = state.range(0);
  set_num_threads(int(state.range(1)));
  Tensor<float> x = randn({n}, 1), g = randn({n}, 2), dx = Tensor<float>::zeros({n});
  leaky_relu_backward(dx.data(), g.data(), x.data(), n, 0.2f);
  for (int64_t i = 0; i < n; i += 997)
    if (dx[i] != g[i] * (x[i] > 0 ? 1 : 0.2f)) state.SkipWithError("leaky_relu_backward is wrong");
  for (auto _ : state) {
    leaky_relu_backward(dx.data(), g.data(), x.data(), n, 0.2f);
    benchmark::DoNotOptimize(dx.data());
    benchmark::ClobberMemory();
  }
  set_bytes(state, 4.0 * 4 * double(n));  // reads x, g, dx; writes dx
}

void BM_Dropout(benchmark::State& state) {
  const int64_t n = state.range(0);
  set_num_threads(int(state.range(1)));
  Tensor<float> x = randn({n}, 1), y(Shape{n}), m(Shape{n});
  dropout_forward(y.data(), m.data(), x.data(), n, 0.5, 42);
  int64_t kept = 0;
  for (int64_t i = 0; i < n; ++i) kept += m[i] != 0;
  if (std::abs(double(kept) / double(n) - 0.5) > 0.02) state.SkipWithError("dropout keep rate is off");
  uint64_t seed = 0;
  for (auto _ : state) {
    dropout_forward(y.data(), m.data(), x.data(), n, 0.5, ++seed);
    benchmark::DoNotOptimize(y.data());
    benchmark::ClobberMemory();
  }
  set_bytes(state, 3.0 * 4 * double(n));
  state.counters["elements/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int64_t n : {int64_t(1) << 16, int64_t(1) << 22})
    for (int t : {1, 2}) b->Args({n, t});
}

}  // namespace

BENCHMARK(BM_Memcpy)->Arg(1 << 16)->Arg(1 << 22)->UseRealTime();
BENCHMARK(BM_AddSameShape)->Apply(sizes)->UseRealTime();
BENCHMARK(BM_MulPerChannel)->Apply(sizes)->UseRealTime();
BENCHMARK(BM_LeakyReluBackward)->Apply(sizes)->UseRealTime();
BENCHMARK(BM_Dropout)->Args({16 * 3844, 1})->Args({16 * 3844, 2})->Args({1 << 22, 2})->UseRealTime();
BENCHMARK_MAIN();
