// Steady-state profile of one pix2pix iteration (not a Google Benchmark: a plain program
// that `perf` can switch on after the warm-up, which bench_gan_iteration cannot).
//   profile_gan_iteration [threads=2] [iterations=5] [size=256] [ngf=64] [levels=8]
//       [precision=fp32|bf16]
// prints the best and mean wall and CPU time per iteration (CPU time summed over
// the pool's threads: robust when other jobs share the cores) and the allocator's peak.
// With PERF_CTL set to a perf control FIFO it writes "enable" there after the warm-up:
//   mkfifo /tmp/ctl && PERF_CTL=/tmp/ctl perf record -D -1 --control fifo:/tmp/ctl -g \
//       build/benchmarks/profile_gan_iteration 1 4
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include "core/allocator.h"
#include "core/kernels/gemm_precision.h"
#include "core/thread_pool.h"
#include "runs/gi/gan_trainer.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::runs;

namespace {
double cpu_seconds() { return pool_cpu_ms() * 1e-3; }
double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

int main(int argc, char** argv) {
  auto arg = [&](int i, int fallback) { return argc > i ? std::atoi(argv[i]) : fallback; };
  const int threads = arg(1, 2), iters = std::max(1, arg(2, 5)), S = arg(3, 256);
  set_num_threads(threads);
  const ScopedGemmPrecision precision(parse_precision(argc > 6 ? argv[6] : "fp32"));
  GanTrainConfig c;  // the thesis configuration of bench_gan_iteration
  c.inputs.mode = GiMode::front;
  c.inputs.size = S;
  c.ngf = arg(4, 64), c.levels = arg(5, 8), c.ndf = 64, c.d_layers = 3;
  GanTrainer t(c);
  Rng rng(1);
  GiSample s;
  s.input = Tensor<float>({1, 12, S, S});
  for (auto& v : s.input) v = float(rng.uniform(-1, 1));
  s.target = Tensor<float>({1, 3, S, S});
  for (auto& v : s.target) v = float(rng.uniform(-1, 1));
  s.front = {0, 0, S, S};
  for (int i = 0; i < 2; ++i) t.train_step(s);  // warm-up: caches, allocator, pool
  if (const char* ctl = std::getenv("PERF_CTL")) {
    if (FILE* f = std::fopen(ctl, "w")) {
      std::fputs("enable\n", f);
      std::fclose(f);
    }
  }
  double best_wall = 1e30, best_cpu = 1e30, sum_wall = 0, sum_cpu = 0;
  for (int i = 0; i < iters; ++i) {
    const double w0 = wall_seconds(), c0 = cpu_seconds();
    t.train_step(s);
    const double w = wall_seconds() - w0, cpu = cpu_seconds() - c0;
    best_wall = std::min(best_wall, w), best_cpu = std::min(best_cpu, cpu);
    sum_wall += w, sum_cpu += cpu;
  }
  const auto& a = CachingAllocator::instance();
  std::printf(
      "threads %d, %s: wall best %.3f mean %.3f s; CPU best %.3f mean %.3f s; "
      "allocator peak %.0f MiB\n",
      threads, precision_name(gemm_precision()), best_wall, sum_wall / iters, best_cpu, sum_cpu / iters,
      double(a.peak_bytes_in_use()) / 1048576.0);
  return 0;
}
