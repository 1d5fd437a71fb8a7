// Does bf16 training need loss scaling? fp16 does because its smallest normal is 2^-14:
// small gradients flush to zero. bf16 keeps fp32's 8 exponent bits, so it should not.
// This trains the default GAN (face 64, ngf 16, 5 levels, PatchGAN ndf 16; synthetic
// front-view inputs) for some steps in fp32 and in bf16 from the same seed and counts,
// over every parameter gradient of G and D after every step, the entries that are zero,
// below fp32's smallest normal 2^-126 (vdpbf16ps flushes inputs and products there),
// and below fp16's smallest normal 2^-14 (what fp16 would lose without scaling).
//   bf16_gradient_range [steps=50]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "core/kernels/gemm_precision.h"
#include "core/thread_pool.h"
#include "runs/gi/train_gan.h"
#include "runs/gi/gan_trainer.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::runs;

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 50;
  set_num_threads(1);
  const TrainGanOptions def;
  std::printf("bf16 GEMM on %s; %d steps of the default GAN (synthetic inputs)\n", bf16_isa_description().c_str(),
              steps);
  std::printf(
      "| precision | gradient entries | zero | 0 < |g| < 2^-126 | |g| < 2^-14 (fp16 normal) | "
      "smallest nonzero |g| |\n|---|---:|---:|---:|---:|---:|\n");
  for (Precision p : {Precision::fp32, Precision::bf16}) {
    const ScopedGemmPrecision mode(p);
    GanTrainConfig c;
    c.inputs.mode = GiMode::front;
    c.inputs.size = def.size;
    c.ngf = def.ngf, c.ndf = def.ndf, c.levels = def.levels, c.d_layers = def.d_layers;
    c.dssim_weight = def.dssim_weight_used();
    c.seed = 1;
    GanTrainer t(c);
    Rng rng(7);
    const int64_t S = def.size;
    GiSample s;
    s.input = Tensor<float>({1, 12, S, S});
    s.target = Tensor<float>({1, 3, S, S});
    s.front = {0, 0, S, S};
    int64_t total = 0, zero = 0, tiny = 0, below_fp16 = 0;
    double smallest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < steps; ++i) {
      for (auto& v : s.input) v = float(rng.uniform(-1, 1));
      for (auto& v : s.target) v = float(rng.uniform(-1, 1));
      t.train_step(s);
      auto count = [&](const auto& params) {
        for (const auto& prm : params) {
          const Tensor<float>& g = prm.grad();
          for (int64_t k = 0; k < g.numel(); ++k) {
            const double a = std::fabs(double(g[k]));
            ++total;
            if (a == 0) ++zero;
            else smallest = std::min(smallest, a);
            if (a > 0 && a < std::ldexp(1.0, -126)) ++tiny;
            if (a < std::ldexp(1.0, -14)) ++below_fp16;
          }
        }
      };
      count(t.G.parameters());
      if (t.D) count(t.D->parameters());
    }
    std::printf("| %s | %lld | %lld (%.3g%%) | %lld | %lld (%.3g%%) | %.3g |\n", precision_name(p), (long long)total,
                (long long)zero, 100.0 * double(zero) / double(total), (long long)tiny, (long long)below_fp16,
                100.0 * double(below_fp16) / double(total), smallest);
  }
  return 0;
}
