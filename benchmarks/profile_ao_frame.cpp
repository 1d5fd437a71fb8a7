// Per-frame time of AO methods on the same frames, the methods interleaved round by
// round, so that a machine shared with other jobs slows them alike (a plain program, not
// a Google Benchmark: `valgrind --tool=callgrind` can run one method alone, and it takes
// dataset views as they are).
//   profile_ao_frame [threads=2] [rounds=20] [methods=all] [view=320x180] [model.blob|LADDER_DIR]
// methods: all (NNAO, HBAO-64, GTAO-32), every (NNAO and every classical setting eval-ao
// runs), or a name prefix (NNAO, HBAO, GTAO, ...). view: WxH (the synthetic box frame of
// fixtures/synthetic_gbuffer.h), FILE.exr, or FILE.exr@WxH (the view's depth and normals
// brought to WxH by nearest-pixel resampling). A ladder folder (train-nnao --ladder)
// times every rung; without a model, a random one of the default shape (16 directions x
// 8 steps, 4 bands, hidden 16, 4 blur passes; the weights do not change the work).
// Prints per method the best and median wall ms per frame, the median CPU ms of the
// pool's threads (pool_cpu_ms), their ratio (the threads the method kept busy) and the
// machine's processor.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "classical_ao/methods.h"
#include "classical_ao/params.h"
#include "core/blob.h"
#include "core/thread_pool.h"
#include "data/exr_io.h"
#include "fixtures/random_nnao_blob.h"
#include "fixtures/synthetic_gbuffer.h"
#include "models/nnao/nnao_inference.h"
#include "runs/ao/nnao_budget.h"

using namespace nns;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

struct Method {
  std::string name;
  std::function<void(const screen_space::GBuffer&, float*)> run;
  std::vector<double> ms, cpu;
};

data::View load_view(const std::string& arg) {
  int w = 0, h = 0;
  if (std::sscanf(arg.c_str(), "%dx%d", &w, &h) == 2 && w > 0 && h > 0) return fixtures::synthetic_view(w, h, 1, 1);
  const auto at = arg.rfind('@');
  if (at != std::string::npos && std::sscanf(arg.c_str() + at + 1, "%dx%d", &w, &h) == 2 && w > 0 && h > 0)
    return runs::resize_nearest(data::read_view(arg.substr(0, at)), w, h);
  return data::read_view(arg);
}

}  // namespace

int main(int argc, char** argv) {
  const int threads = argc > 1 ? std::atoi(argv[1]) : 2;
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 20;
  const std::string which = argc > 3 ? argv[3] : "all";
  const std::string view_arg = argc > 4 ? argv[4] : "320x180";
  if (threads < 1 || rounds < 1) {
    std::fprintf(stderr,
                 "usage: profile_ao_frame [threads>=1] [rounds>=1] [all|every|PREFIX] [WxH|VIEW.exr[@WxH]] "
                 "[model.blob|LADDER_DIR]\n");
    return 2;
  }
  try {
    set_num_threads(threads);
    std::vector<std::pair<std::string, nnao::NnaoWeights>> models;
    if (argc > 5 && std::filesystem::is_directory(argv[5])) {
      for (const auto& r : runs::read_ladder(argv[5]))
        models.emplace_back("NNAO " + r.name, nnao::NnaoWeights::load(r.blob));
    } else if (argc > 5) {
      models.emplace_back("NNAO", nnao::NnaoWeights::from_blob(Blob::load(argv[5])));
    } else {
      Blob b = fixtures::random_nnao_blob(0, 16, 7, false, {16, 8, 4});
      b.set_config("blur_passes", 4);
      models.emplace_back("NNAO", nnao::NnaoWeights::from_blob(b));
    }
    const data::View view = load_view(view_arg);
    const screen_space::GBuffer g = screen_space::gbuffer_from_view(view);
    std::vector<Method> methods;
    for (auto& [name, m] : models)
      methods.push_back(
          {name, [&m = m](const screen_space::GBuffer& gb, float* o) { nnao::infer_exact(m, gb, o); }, {}, {}});
    const classical_ao::ClassicalParams params;
    for (auto& c : classical_ao::classical_methods())
      for (int n : c.sample_counts) {
        const std::string name = c.name + "-" + std::to_string(n);
        if (which == "all" && name != "HBAO-64" && name != "GTAO-32") continue;
        methods.push_back({name,
                           [&c, &params, n](const screen_space::GBuffer& gb, float* o) {
                             classical_ao::run_classical(c.name, params, gb, n, o, false);
                           },
                           {},
                           {}});
      }
    std::vector<float> out(size_t(g.pixels()));
    auto selected = [&](const Method& m) { return which == "all" || which == "every" || m.name.rfind(which, 0) == 0; };
    for (int r = 0; r < rounds + 1; ++r)  // round 0 warms the caches and the pool
      for (auto& m : methods) {
        if (!selected(m)) continue;
        const double c0 = pool_cpu_ms();
        const auto t0 = std::chrono::steady_clock::now();
        m.run(g, out.data());
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (r > 0) m.ms.push_back(ms), m.cpu.push_back(pool_cpu_ms() - c0);
      }
    std::printf("%dx%d, %d thread(s), %d rounds (%s) on %s\n", g.width, g.height, threads, rounds, view_arg.c_str(),
                runs::cpu_model().c_str());
    std::printf("%-30s %9s %9s %9s %12s\n", "method", "best ms", "median ms", "CPU ms", "threads used");
    for (const auto& m : methods) {
      if (m.ms.empty()) continue;
      std::printf("%-30s %9.3f %9.3f %9.3f %12.2f\n", m.name.c_str(), *std::min_element(m.ms.begin(), m.ms.end()),
                  median(m.ms), median(m.cpu), median(m.cpu) / median(m.ms));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "profile_ao_frame: %s\n", e.what());
    return 1;
  }
  return 0;
}
