// The cost of pix2pix training on the CPU: one full iteration (G forward, D step on a
// real and a generated pair, G step through the frozen D, both Adam updates) at the
// thesis-like size — 256x256, ngf 64, 8 levels, PatchGAN n=3 ndf 64, batch 1 — plus the
// U-Net step and the PatchGAN step alone. Counters: seconds/iteration, GFLOP/s of the
// convolutions (counted analytically, below), % of the machine's FP32 peak, peak RSS.
//
// Multithreaded: every rate is per wall-clock second (UseRealTime).
// FLOPs: a conv or transposed conv costs 2*Cin*Cout*k*k per output (input) pixel
// forward; its backward costs the same for the input gradient and again for the weight
// gradient. Per iteration: G forward + backward (3 F_G, less the first layer's unneeded
// input gradient, ignored), D forward 3 times (real, fake, fake for G), D backward for
// weights on the 2 passes of the D step (2 F_D) and for the input on all 3 (3 F_D: the
// D step needs its inner layers' input gradients to reach the earlier weights; the
// first layer's is again ignored): 3 F_G + 8 F_D, 90.8 GFLOP at the thesis size.
// Peak: the measured FP32 FMA peak of the same number of threads (benchmarks/fma_peak.h).
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <string>

#include "benchmarks/fma_peak.h"
#include "core/kernels/gemm_precision.h"
#include "core/thread_pool.h"
#include "runs/gi/gan_trainer.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::runs;

namespace {

double conv_flops(int64_t cin, int64_t cout, int64_t pixels) { return 2.0 * double(cin * cout * 16) * double(pixels); }

// Forward FLOPs of the U-Net on an S x S input.
double unet_flops(const UnetConfig& c, int64_t S) {
  double f = 0;
  for (int l = 0; l < c.levels; ++l) {
    const int64_t inner = c.ngf * std::min(1 << std::min(l, 3), 8);
    const int64_t outer = l == 0 ? c.out_channels : c.ngf * std::min(1 << std::min(l - 1, 3), 8);
    const int64_t input = l == 0 ? c.in_channels : outer;
    const int64_t out_side = S >> (l + 1);  // down conv output side
    f += conv_flops(input, inner, out_side * out_side);
    f += conv_flops(l == c.levels - 1 ? inner : 2 * inner, outer, out_side * out_side);  // up: per input pixel
  }
  return f;
}

double patchgan_flops(const PatchGanConfig& c, int64_t S) {
  double f = 0;
  int64_t ch = c.in_channels, side = S;
  for (int n = 0; n <= c.layers; ++n) {
    const int64_t out = c.ndf * std::min(1 << std::min(n, 3), 8);
    side = n < c.layers ? side / 2 : side - 1;
    f += conv_flops(ch, out, side * side);
    ch = out;
  }
  side -= 1;
  return f + conv_flops(ch, 1, side * side);
}

double peak_flops(int threads) {
  static double cached[3] = {0, 0, 0};  // measured once per thread count
  if (threads > 2) return threads * peak_flops(1);
  if (cached[threads] == 0) cached[threads] = benchmarks::measure_fma_peak_gflops(threads) * 1e9;
  return cached[threads];
}

double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

GiSample synthetic_sample(int64_t S, int channels, Rng& rng) {
  GiSample s;
  s.input = Tensor<float>({1, channels, S, S});
  for (auto& v : s.input) v = float(rng.uniform(-1, 1));
  s.target = Tensor<float>({1, 3, S, S});
  for (auto& v : s.target) v = float(rng.uniform(-1, 1));
  s.front = {0, 0, S, S};
  return s;
}

GanTrainConfig thesis_config(int64_t S, int ngf, int levels) {
  GanTrainConfig c;
  c.inputs.mode = GiMode::front;
  c.inputs.size = int(S);
  c.ngf = ngf, c.levels = levels, c.ndf = 64, c.d_layers = 3;
  return c;
}

void set_counters(benchmark::State& state, double flops, int threads) {
  state.counters["s_per_iter"] =
      benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["GFLOP/s"] = benchmark::Counter(flops * double(state.iterations()) / 1e9, benchmark::Counter::kIsRate);
  state.counters["GFLOP_per_iter"] = flops / 1e9;
  const double peak = peak_flops(threads);
  state.counters["peak_GFLOP/s"] = peak / 1e9;
  // A rate counter divides by the elapsed time: 100 * achieved / peak.
  state.counters["pct_of_peak"] =
      benchmark::Counter(100.0 * flops * double(state.iterations()) / peak, benchmark::Counter::kIsRate);
  state.counters["peak_RSS_MiB"] = peak_rss_mib();
}

// Times full iterations of a trainer built from `c` on one synthetic sample (drawn with
// `seed`) after a warm-up step that also checks the losses are finite.
void time_gan_iterations(benchmark::State& state, const GanTrainConfig& c, int threads, uint64_t seed) {
  set_num_threads(threads);
  const int64_t S = c.inputs.size;
  GanTrainer t(c);
  Rng rng(seed);
  GiSample s = synthetic_sample(S, 12, rng);
  StepLosses l = t.train_step(s);
  if (!std::isfinite(l.g) || !std::isfinite(l.d)) state.SkipWithError("non-finite loss");
  for (auto _ : state) benchmark::DoNotOptimize(t.train_step(s));
  set_counters(state, 3 * unet_flops(c.unet(), S) + 8 * patchgan_flops(c.patchgan(), S), threads);
}

// args: size, ngf, levels, threads
void gan_iteration(benchmark::State& state, Precision precision) {
  const ScopedGemmPrecision mode(precision);
  if (precision == Precision::bf16) state.SetLabel(bf16_isa_description());
  time_gan_iterations(state, thesis_config(state.range(0), int(state.range(1)), int(state.range(2))),
                      int(state.range(3)), 1);
}

void BM_GanIteration(benchmark::State& state) { gan_iteration(state, Precision::fp32); }
// Mixed precision (train-gan --precision bf16): bf16 GEMM/conv inputs, the rest fp32.
void BM_GanIterationBf16(benchmark::State& state) { gan_iteration(state, Precision::bf16); }

// What the reconstruction terms cost at the default's size (face 64, ngf and ndf 16, 5
// levels, front mode): args size, gradient weight (0: L1 + DSSIM alone; else + that times
// gradient_l1), threads. Run with --benchmark_enable_random_interleaving and repetitions
// so that both see the same machine.
void BM_GanIterationLosses(benchmark::State& state) {
  GanTrainConfig c = thesis_config(state.range(0), 16, 5);
  c.ndf = 16, c.dssim_weight = 1, c.gradient_weight = double(state.range(1));
  time_gan_iterations(state, c, int(state.range(2)), 4);
}

// The generator alone: forward, L1 backward, Adam (the --loss l1 baseline's iteration).
void BM_UnetStep(benchmark::State& state) {
  const int64_t S = state.range(0);
  const int threads = int(state.range(3));
  set_num_threads(threads);
  GanTrainConfig c = thesis_config(S, int(state.range(1)), int(state.range(2)));
  c.loss = GiLoss::l1;
  GanTrainer t(c);
  Rng rng(2);
  GiSample s = synthetic_sample(S, 12, rng);
  t.train_step(s);
  for (auto _ : state) benchmark::DoNotOptimize(t.train_step(s));
  set_counters(state, 3 * unet_flops(c.unet(), S), threads);
}

// The discriminator alone: forward + backward (weights and input) + Adam on one pair.
void BM_PatchGanStep(benchmark::State& state) {
  const int64_t S = state.range(0);
  const int threads = int(state.range(1));
  set_num_threads(threads);
  Rng rng(3);
  PatchGan<float> d({15, 64, 3}, rng);
  Adam<float> opt(d.parameters(), AdamOptions{.lr = 2e-4, .beta1 = 0.5});
  Var<float> x(synthetic_sample(S, 15, rng).input, true);
  for (auto _ : state) {
    opt.zero_grad();
    x.zero_grad();
    Var<float> loss = bce_with_logits_target(d.forward(x), 1.0f);
    loss.backward();
    opt.step();
    benchmark::DoNotOptimize(loss.value().data());
  }
  set_counters(state, 3 * patchgan_flops({15, 64, 3}, S), threads);
}

}  // namespace

BENCHMARK(BM_GanIteration)
    ->Args({256, 64, 8, 2})
    ->Args({256, 64, 8, 1})
    ->Args({128, 16, 5, 2})
    ->Unit(benchmark::kSecond)
    ->MinTime(1.0)
    ->UseRealTime();
BENCHMARK(BM_GanIterationLosses)
    ->Args({64, 0, 2})
    ->Args({64, 1, 2})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(1.0)
    ->UseRealTime();
BENCHMARK(BM_GanIterationBf16)
    ->Args({256, 64, 8, 2})
    ->Args({256, 64, 8, 1})
    ->Args({128, 16, 5, 2})
    ->Unit(benchmark::kSecond)
    ->MinTime(1.0)
    ->UseRealTime();
BENCHMARK(BM_UnetStep)
    ->Args({256, 64, 8, 2})
    ->Args({256, 64, 8, 1})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(1.0)
    ->UseRealTime();
BENCHMARK(BM_PatchGanStep)->Args({256, 2})->Args({256, 1})->Unit(benchmark::kMillisecond)->MinTime(1.0)->UseRealTime();
BENCHMARK_MAIN();
