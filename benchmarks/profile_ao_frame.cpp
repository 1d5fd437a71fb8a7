// Per-frame time of the default NNAO (horizon features, exact, with its blur) against
// HBAO-64 and GTAO-32 on the same frames, the methods interleaved round by round, so
// that a machine shared with other jobs slows them alike (a plain program, not a
// Google Benchmark: `valgrind --tool=callgrind` can run one method alone, and it takes
// dataset views as they are).
//   profile_ao_frame [threads=2] [rounds=20] [methods=all|NNAO|HBAO|GTAO] [view=320x180|FILE.exr] [model.blob]
// Without a model: a random one of the default shape (16 directions x 8 steps, 4
// bands, hidden 16; the weights do not change the work). Without a view file: the
// synthetic box frame of fixtures/synthetic_gbuffer.h at that size. Prints per method
// the best and median wall ms per frame, ms per depth sample, and the median over
// rounds of the per-round ratio to HBAO-64 per sample.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "classical_ao/gtao.h"
#include "classical_ao/hbao.h"
#include "core/blob.h"
#include "core/thread_pool.h"
#include "data/exr_io.h"
#include "fixtures/random_nnao_blob.h"
#include "fixtures/synthetic_gbuffer.h"
#include "models/nnao/nnao_inference.h"

using namespace nns;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

struct Method {
  std::string name;
  int samples;  // depth samples per pixel
  std::function<void(const ao::GBuffer&, float*)> run;
  std::vector<double> ms;
};

}  // namespace

int main(int argc, char** argv) {
  const int threads = argc > 1 ? std::atoi(argv[1]) : 2;
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 20;
  const std::string which = argc > 3 ? argv[3] : "all";
  const std::string view_arg = argc > 4 ? argv[4] : "320x180";
  if (threads < 1 || rounds < 1) {
    std::fprintf(stderr, "usage: profile_ao_frame [threads>=1] [rounds>=1] [all|NNAO|HBAO|GTAO] [WxH|VIEW.exr] [model.blob]\n");
    return 2;
  }
  try {
    set_num_threads(threads);
    const nnao::NnaoWeights model =
        argc > 5 ? nnao::NnaoWeights::from_blob(Blob::load(argv[5]))
                 : nnao::NnaoWeights::from_blob(fixtures::random_nnao_blob(0, 16, 7, false, {16, 8, 4}));
    data::View view;
    int w = 0, h = 0;
    if (std::sscanf(view_arg.c_str(), "%dx%d", &w, &h) == 2 && w > 0 && h > 0) view = fixtures::synthetic_view(w, h, 1, 1);
    else view = data::read_view(view_arg);
    const ao::GBuffer g = ao::gbuffer_from_view(view);
    std::vector<Method> methods = {
        {"NNAO", int(model.input.samples()), [&](const ao::GBuffer& gb, float* o) { nnao::infer_exact(model, gb, o); }, {}},
        {"HBAO-64", 64, [](const ao::GBuffer& gb, float* o) { ao::hbao(gb, 64, o); }, {}},
        {"GTAO-32", 32, [](const ao::GBuffer& gb, float* o) { ao::gtao(gb, 32, o); }, {}},
    };
    std::vector<float> out(size_t(g.pixels()));
    for (int r = 0; r < rounds + 1; ++r)  // round 0 warms the caches and the pool
      for (auto& m : methods) {
        if (which != "all" && m.name.rfind(which, 0) != 0) continue;
        const auto t0 = std::chrono::steady_clock::now();
        m.run(g, out.data());
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (r > 0) m.ms.push_back(ms);
      }
    std::printf("%dx%d, %d thread(s), %d rounds (%s)\n", g.width, g.height, threads, rounds, view_arg.c_str());
    std::printf("%-8s %8s %9s %9s %16s %22s\n", "method", "samples", "best ms", "median ms", "median ms/sample",
                "per-sample vs HBAO-64");
    const Method& hbao = methods[1];
    for (const auto& m : methods) {
      if (m.ms.empty()) continue;
      std::string ratio = "-";
      if (!hbao.ms.empty()) {
        std::vector<double> q;
        for (size_t r = 0; r < m.ms.size(); ++r) q.push_back((m.ms[r] / m.samples) / (hbao.ms[r] / hbao.samples));
        ratio = std::to_string(median(q)).substr(0, 5) + "x";
      }
      std::printf("%-8s %8d %9.3f %9.3f %16.5f %22s\n", m.name.c_str(), m.samples, *std::min_element(m.ms.begin(), m.ms.end()),
                  median(m.ms), median(m.ms) / m.samples, ratio.c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "profile_ao_frame: %s\n", e.what());
    return 1;
  }
  return 0;
}
