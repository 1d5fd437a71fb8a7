// The machine's FP32 FMA peak with 1 and 2 threads (independent FMA chains held in
// registers, see fma_peak.h): the 100% that the other benchmarks' "% of peak" refers to.
#include <benchmark/benchmark.h>

#include <chrono>
#include <thread>

#include "benchmarks/fma_peak.h"

namespace {

void BM_FmaPeak(benchmark::State& state) {
  const int threads = int(state.range(0));
  nns::set_num_threads(threads);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // let new workers start
  const int64_t iters = 1'000'000;
  float sink = 0;
  for (auto _ : state) {
    nns::ThreadPool::global().run(
        [&](int w, int) { benchmark::DoNotOptimize(nns::benchmarks::fma_chains(iters, float(w) + sink)); });
  }
  state.counters["GFLOP/s"] = benchmark::Counter(
      nns::benchmarks::fma_flops_per_iter() * double(iters) * threads * double(state.iterations()) / 1e9,
      benchmark::Counter::kIsRate);
  state.counters["threads"] = threads;
}

}  // namespace

BENCHMARK(BM_FmaPeak)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
