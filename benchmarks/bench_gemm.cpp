// SGEMM throughput: square sizes and the im2col GEMM shapes of the pix2pix U-Net
// (ngf=64, 256x256), with 1 and 2 threads. Reports GFLOP/s and % of the FMA peak
// measured in this same binary (fma_peak.h). Every shape is checked before it is
// timed, with BLIS's vector probe C*t == A*(B*t) evaluated in double.
//
// Args: M, N, K, trans_a, trans_b, threads. benchmarks/compare runs the same shapes in
// OpenBLAS, oneDNN and PyTorch by reading these names back from the JSON output.
#include <benchmark/benchmark.h>

#include <cfloat>
#include <chrono>
#include <cmath>
#include <map>
#include <thread>
#include <vector>

#include "benchmarks/fma_peak.h"
#include "core/kernels/gemm.h"
#include "core/rng.h"

namespace {

void use_threads(int n) { nns::set_num_threads(n); }

double peak_gflops(int threads) {
  static std::map<int, double> cache;
  auto it = cache.find(threads);
  if (it != cache.end()) return it->second;
  use_threads(threads);
  double p = nns::benchmarks::measure_fma_peak_gflops(threads);
  cache[threads] = p;
  return p;
}

// Relative error of C*t against A*(B*t) (double), worst over the rows.
double probe_error(bool ta, bool tb, int64_t M, int64_t N, int64_t K, const float* A, int64_t lda, const float* B,
                   int64_t ldb, const float* C, int64_t ldc) {
  nns::Rng rng(5);
  std::vector<double> t(static_cast<size_t>(N)), bt(static_cast<size_t>(K), 0.0), bt_abs(static_cast<size_t>(K), 0.0);
  for (auto& x : t) x = rng.normal();
  for (int64_t k = 0; k < K; ++k)
    for (int64_t j = 0; j < N; ++j) {
      double b = tb ? B[j * ldb + k] : B[k * ldb + j];
      bt[size_t(k)] += b * t[size_t(j)];
      bt_abs[size_t(k)] += std::fabs(b * t[size_t(j)]);
    }
  double worst = 0;
  for (int64_t i = 0; i < M; ++i) {
    double lhs = 0, rhs = 0, mag = 1e-300;
    for (int64_t j = 0; j < N; ++j) lhs += double(C[i * ldc + j]) * t[size_t(j)];
    for (int64_t k = 0; k < K; ++k) {
      double a = ta ? A[k * lda + i] : A[i * lda + k];
      rhs += a * bt[size_t(k)];
      mag += std::fabs(a) * bt_abs[size_t(k)];
    }
    worst = std::max(worst, std::fabs(lhs - rhs) / mag);
  }
  return worst;
}

void run_gemm(benchmark::State& state, nns::Precision precision) {
  const int64_t M = state.range(0), N = state.range(1), K = state.range(2);
  const bool ta = state.range(3) != 0, tb = state.range(4) != 0;
  const int threads = int(state.range(5));
  const double peak = peak_gflops(threads);
  use_threads(threads);

  nns::Rng rng(1);
  std::vector<float> A(size_t(M * K)), B(size_t(K * N)), C(size_t(M * N));
  for (auto& x : A) x = float(rng.uniform(-1, 1));
  for (auto& x : B) x = float(rng.uniform(-1, 1));
  // bf16: operands that are bf16 already, so the fp32 probe's bound still applies (a
  // product of two bf16 is exact); the speed does not depend on the values.
  const nns::ScopedGemmPrecision mode(precision);
  if (precision == nns::Precision::bf16) {
    for (auto& x : A) x = nns::round_to_bf16(x);
    for (auto& x : B) x = nns::round_to_bf16(x);
    state.SetLabel(nns::bf16_isa_description());
  }
  const int64_t lda = ta ? M : K, ldb = tb ? K : N;
  auto run = [&] { nns::gemm<float>(ta, tb, M, N, K, 1.0f, A.data(), lda, B.data(), ldb, 0.0f, C.data(), N); };
  run();
  const double err = probe_error(ta, tb, M, N, K, A.data(), lda, B.data(), ldb, C.data(), N);
  if (!(err < double(K) * FLT_EPSILON)) {
    state.SkipWithError("result does not match the reference probe");
    return;
  }
  for (auto _ : state) {
    run();
    benchmark::DoNotOptimize(C.data());
    benchmark::ClobberMemory();
  }
  const double flops = 2.0 * double(M) * double(N) * double(K);
  state.counters["GFLOP/s"] = benchmark::Counter(flops * double(state.iterations()) / 1e9, benchmark::Counter::kIsRate);
  state.counters["peak_GFLOP/s"] = peak;
  state.counters["flops"] = flops;
}

// fp32 and bf16 inputs with fp32 sums (gemm_precision.h); the label says which bf16
// kernel ran (AVX512-BF16 or the generic fallback).
void BM_Sgemm(benchmark::State& state) { run_gemm(state, nns::Precision::fp32); }
void BM_GemmBf16(benchmark::State& state) { run_gemm(state, nns::Precision::bf16); }

void square_and_unet_shapes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"M", "N", "K", "ta", "tb", "threads"});
  for (int threads : {1, 2}) {
    for (int64_t s : {64, 128, 256, 512, 1024, 2048}) b->Args({s, s, s, 0, 0, threads});
    // U-Net ngf=64 at 256x256, im2col GEMMs: forward M=Cout, N=Hout*Wout, K=Cin*16.
    b->Args({64, 16384, 48, 0, 0, threads});    // down1 3->64, 128x128
    b->Args({128, 4096, 1024, 0, 0, threads});  // down2 64->128, 64x64
    b->Args({256, 1024, 2048, 0, 0, threads});  // down3 128->256, 32x32
    b->Args({512, 256, 4096, 0, 0, threads});   // down4 256->512, 16x16
    b->Args({512, 64, 8192, 0, 0, threads});    // down5 512->512, 8x8
    // Transposed conv (decoder) as W^T x: M=Cout*16, N=Hin*Win, K=Cin.
    b->Args({2048, 1024, 512, 1, 0, threads});  // up 512->128, 32x32 -> 64x64
    b->Args({1024, 4096, 256, 1, 0, threads});  // up 256->64, 64x64 -> 128x128
    // Weight gradient dW = dout col^T: M=Cout, N=Cin*16, K=Hout*Wout.
    b->Args({128, 1024, 4096, 0, 1, threads});  // down2
    b->Args({256, 2048, 1024, 0, 1, threads});  // down3
  }
}

}  // namespace

BENCHMARK(BM_Sgemm)->Apply(square_and_unet_shapes)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_GemmBf16)->Apply(square_and_unet_shapes)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
