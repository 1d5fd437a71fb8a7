// bf16 against fp32 in one process, interleaved: what `--precision bf16` buys on this
// machine, measured fairly on a shared one (not a Google Benchmark: GB runs one
// benchmark to completion before the next, so a change of load between the fp32 and the
// bf16 rows would show up as a speed ratio).
//   bf16_speedup [threads=2] [rounds=5] [what=all|gemm|conv|gan]
// Each round times every item once in fp32 and once in bf16 (the order alternating
// between rounds); an item's time is the median of its rounds, and the ratio's spread is
// the range of the per-round ratios fp32 / bf16. Items: the square and U-Net GEMM shapes
// of bench_gemm, the conv2d fwd+bwd shapes of bench_conv that go through GEMM, and the
// pix2pix 256 ngf64 iteration of bench_gan_iteration. Timing of a GEMM or conv item
// repeats the call for at least 0.2 s. Times are CPU time (summed over the
// pool's threads, pool_cpu_ms): on a machine shared with other jobs, wall time measures the scheduler (with
// 1 thread, CPU time is the time the work took); wall-time ratios are printed beside.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <utility>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/kernels/conv2d.h"
#include "core/kernels/gemm.h"
#include "core/kernels/gemm_precision.h"
#include "core/rng.h"
#include "core/thread_pool.h"
#include "runs/gi/gan_trainer.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::runs;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

struct Item {
  std::string name;
  double flops;  // per call (0: report time only)
  std::function<void()> call;
  bool repeat;                  // repeat for >= 0.2 s (cheap calls) or time one call
  std::vector<double> t[2];     // CPU seconds per call, [fp32, bf16], one per round
  std::vector<double> wall[2];  // wall seconds per call
};

double cpu_now() { return pool_cpu_ms() * 1e-3; }

// {CPU seconds, wall seconds} per call.
std::pair<double, double> time_call(Item& it) {
  int n = 0;
  const double t0 = now(), c0 = cpu_now();
  double t = t0;
  do {
    it.call();
    ++n;
    t = now();
  } while (it.repeat && t - t0 < 0.2);
  return {(cpu_now() - c0) / n, (t - t0) / n};
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::vector<float> randn(size_t n, Rng& rng) {
  std::vector<float> v(n);
  for (auto& x : v) x = float(rng.normal());
  return v;
}

// Random operands that outlive the items' lambdas.
struct Buffers {
  Rng rng{1};
  std::vector<std::vector<float>> keep;
  float* operator()(size_t n) {
    keep.push_back(randn(n, rng));
    return keep.back().data();
  }
};

void add_gemm_items(std::vector<Item>& items, Buffers& buf) {
  const std::vector<std::array<int64_t, 5>> shapes = {
      {256, 256, 256, 0, 0},  {512, 512, 512, 0, 0},   {1024, 1024, 1024, 0, 0}, {2048, 2048, 2048, 0, 0},
      {64, 16384, 48, 0, 0},  {128, 4096, 1024, 0, 0}, {256, 1024, 2048, 0, 0},  {512, 256, 4096, 0, 0},
      {512, 64, 8192, 0, 0},  {2048, 1024, 512, 1, 0}, {1024, 4096, 256, 1, 0},  {128, 1024, 4096, 0, 1},
      {256, 2048, 1024, 0, 1}};
  for (auto [M, N, K, ta, tb] : shapes) {
    const float* A = buf(size_t(M * K));
    const float* B = buf(size_t(K * N));
    float* C = buf(size_t(M * N));
    items.push_back({"sgemm " + std::to_string(M) + "," + std::to_string(N) + "," + std::to_string(K) + "," +
                         std::to_string(ta) + "," + std::to_string(tb),
                     2.0 * double(M * N * K),
                     [=] { gemm<float>(ta, tb, M, N, K, 1.0f, A, ta ? M : K, B, tb ? K : N, 0.0f, C, N); }, true});
  }
}

void add_conv_items(std::vector<Item>& items, Buffers& buf) {
  // {Cin, Cout, k, stride, pad, HW} of bench_conv (the rows with more than one output channel).
  const std::vector<std::array<int64_t, 6>> shapes = {
      {64, 128, 4, 2, 1, 128}, {16, 16, 3, 1, 1, 256},  {64, 64, 3, 1, 1, 128},
      {256, 256, 3, 1, 1, 32}, {12, 64, 4, 2, 1, 256},  {128, 256, 4, 2, 1, 64},
      {256, 512, 4, 2, 1, 32}, {512, 512, 4, 2, 1, 16}, {256, 512, 4, 1, 1, 32}};
  for (auto [ci, co, k, s, p, hw] : shapes) {
    const ConvGeometry g = conv2d_geometry(1, ci, hw, hw, co, k, k, s, s, p, p, 1, 1, 1);
    const float* x = buf(size_t(g.N * g.C_in * g.H * g.W));
    const float* w = buf(size_t(g.C_out * g.cin_g() * k * k));
    const float* b = buf(size_t(g.C_out));
    const float* dy = buf(size_t(g.N * g.C_out * g.H_out * g.W_out));
    float* y = buf(size_t(g.N * g.C_out * g.H_out * g.W_out));
    float* dx = buf(size_t(g.N * g.C_in * g.H * g.W));
    float* dw = buf(size_t(g.C_out * g.cin_g() * k * k));
    float* db = buf(size_t(g.C_out));
    items.push_back({"conv2d " + std::to_string(ci) + "," + std::to_string(co) + "," + std::to_string(k) + "," +
                         std::to_string(s) + "," + std::to_string(p) + "," + std::to_string(hw),
                     6.0 * double(g.macs()),
                     [=] {
                       conv2d_forward(y, x, w, b, g);
                       conv2d_backward(dx, dw, db, dy, x, w, g);
                     },
                     true});
  }
}

// The thesis configuration of bench_gan_iteration: a pix2pix 256, ngf 64 step.
struct GanItem {
  std::unique_ptr<GanTrainer> trainer;
  GiSample sample;
};
void add_gan_item(std::vector<Item>& items, GanItem& gan, Rng& rng) {
  const int64_t S = 256;
  GanTrainConfig c;
  c.inputs.mode = GiMode::front;
  c.inputs.size = int(S);
  c.ngf = 64, c.levels = 8, c.ndf = 64, c.d_layers = 3;
  gan.trainer = std::make_unique<GanTrainer>(c);
  gan.sample.input = Tensor<float>({1, 12, S, S});
  for (auto& v : gan.sample.input) v = float(rng.uniform(-1, 1));
  gan.sample.target = Tensor<float>({1, 3, S, S});
  for (auto& v : gan.sample.target) v = float(rng.uniform(-1, 1));
  gan.sample.front = {0, 0, S, S};
  items.push_back({"pix2pix 256,64,8", 0, [&gan] { gan.trainer->train_step(gan.sample); }, false});
}

// Every item once in each precision per round, the order alternating between rounds.
void time_rounds(std::vector<Item>& items, int rounds) {
  for (auto& it : items)  // warm-up: caches, allocator, pool, packing buffers
    for (Precision p : {Precision::fp32, Precision::bf16}) {
      const ScopedGemmPrecision mode(p);
      it.call();
    }
  for (int r = 0; r < rounds; ++r)
    for (auto& it : items)
      for (int k = 0; k < 2; ++k) {
        const int m = (r + k) % 2;  // fp32 first on even rounds, bf16 first on odd ones
        const ScopedGemmPrecision mode(m ? Precision::bf16 : Precision::fp32);
        const auto [cpu, wall] = time_call(it);
        it.t[m].push_back(cpu);
        it.wall[m].push_back(wall);
      }
}

void print_table(const std::vector<Item>& items, int threads, int rounds) {
  std::printf("CPU time (all threads); wall-time ratio of the medians in the last column\n");
  std::printf(
      "| row | threads | fp32 | bf16 | fp32 / bf16 (median) | per-round range | wall fp32 / bf16 |\n"
      "|---|---:|---:|---:|---:|---:|---:|\n");
  for (auto& it : items) {
    std::vector<double> ratio;
    for (int r = 0; r < rounds; ++r) ratio.push_back(it.t[0][size_t(r)] / it.t[1][size_t(r)]);
    const double f = median(it.t[0]), b = median(it.t[1]);
    auto cell = [&](double s) {
      char c[64];
      if (it.flops > 0) std::snprintf(c, sizeof c, "%.1f GFLOP/s", it.flops / s * 1e-9);
      else std::snprintf(c, sizeof c, "%.3f s", s);
      return std::string(c);
    };
    std::printf("| %s | %d | %s | %s | %.2fx | %.2f-%.2fx | %.2fx |\n", it.name.c_str(), threads, cell(f).c_str(),
                cell(b).c_str(), f / b, *std::min_element(ratio.begin(), ratio.end()),
                *std::max_element(ratio.begin(), ratio.end()), median(it.wall[0]) / median(it.wall[1]));
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int threads = argc > 1 ? std::atoi(argv[1]) : 2;
  const int rounds = std::max(1, argc > 2 ? std::atoi(argv[2]) : 5);
  const std::string what = argc > 3 ? argv[3] : "all";
  set_num_threads(threads);
  Buffers buf;
  std::vector<Item> items;
  if (what == "all" || what == "gemm") add_gemm_items(items, buf);
  if (what == "all" || what == "conv") add_conv_items(items, buf);
  GanItem gan;
  if (what == "all" || what == "gan") add_gan_item(items, gan, buf.rng);
  std::printf("bf16_speedup: %d thread(s), %d rounds; bf16 GEMM on %s\n", threads, rounds,
              bf16_isa_description().c_str());
  time_rounds(items, rounds);
  print_table(items, threads, rounds);
  return 0;
}
