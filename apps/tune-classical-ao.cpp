// tune-classical-ao: fit every classical AO method's free parameters to the ray-traced AO
// of a dataset's training split (classical_ao/tune.h), so that eval-ao compares
// NNAO against the classical methods at their best, as XeGTAO fits its presets.
//
//   tune-classical-ao [--data DIR] --out params.txt [--methods SSAO,...] [--rounds 3]
//   eval-ao --classical-params params.txt ...
#include <chrono>
#include <cstdio>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "apps/args.h"
#include "core/atomic_file.h"
#include "core/thread_pool.h"
#include "report/chart.h"
#include "data/dataset.h"
#include "render/default_dataset.h"
#include "data/exr_io.h"
#include "classical_ao/tune.h"

using namespace nns;

int main(int argc, char** argv) {
  return apps::run_main("tune-classical-ao", [&]() -> int {
    apps::Args args(argc, argv, "tune-classical-ao",
                    "Fit the classical AO methods' parameters for minimum MSE on a dataset's training split.");
    std::string data_dir =
        args.get_string("--data", "", "dataset root with train/ (default: the built-in default nnao dataset)");
    std::string out =
        args.get_path("--out", "classical-params.txt", "parameter file to write (eval-ao --classical-params)");
    std::vector<std::string> methods = args.get_names("--methods", "SSAO,SSAO+,HBAO,Alchemy,GTAO", "methods to tune");
    std::string start = args.get_string("--start", "", "parameter file to start from (default: the built-in values)");
    // Past ~30 rounds the halved steps are below a float's resolution of the parameters.
    int rounds = args.get_int("--rounds", 3, "coordinate-descent rounds (the steps halve after each)", 1, 100);
    int max_views =
        args.get_int("--max-views", 0, "use at most this many training views, evenly spread (0 = all)", 0, INT_MAX);
    int threads = args.get_int("--threads", 2, "worker threads", 1, 256);
    args.done();
    set_num_threads(threads);
    if (data_dir.empty()) data_dir = render::ensure_default_dataset("nnao", threads);
    const data::DatasetListing d = data::list_dataset(data_dir);
    // Never the test split: a flat folder has no split to keep apart, so it is refused.
    if (d.flat) throw std::invalid_argument(data_dir + ": no train/ split (tuning must not see the test views)");
    std::vector<std::string> paths = d.train.views;
    if (paths.empty()) throw std::runtime_error(d.train.dir + ": no views (*.exr)");
    if (max_views > 0 && int(paths.size()) > max_views) {
      std::vector<std::string> every;
      for (int k = 0; k < max_views; ++k) every.push_back(paths[size_t(k) * paths.size() / size_t(max_views)]);
      paths = every;
    }
    data::ReadOptions ro;
    ro.only_channels = {"Z", "N.X", "N.Y", "N.Z", "AO"};
    std::vector<data::View> views;
    for (auto& p : paths) {
      views.push_back(data::read_view(p, ro));
      if (!views.back().has("AO")) throw std::runtime_error(p + ": missing channel 'AO' (the tuning target)");
      screen_space::gbuffer_from_view(views.back());  // the G-buffer checks, before any time is spent
    }

    classical_ao::ClassicalParams params =
        start.empty() ? classical_ao::ClassicalParams{} : classical_ao::read_classical_params(start);
    std::ostringstream summary;
    std::set<std::string> seen;
    for (const std::string& name : methods) {
      if (!seen.insert(name).second) continue;
      const classical_ao::ClassicalMethod& m = classical_ao::classical_method(name);  // throws on an unknown name
      std::printf("tuning %s at samples", name.c_str());
      for (int n : m.sample_counts) std::printf(" %d", n);
      std::printf(" on %zu training views\n", views.size());
      const auto t0 = std::chrono::steady_clock::now();
      auto r = classical_ao::tune_classical(name, m.sample_counts, views, params, rounds, [](const std::string& s) {
        std::printf("  %s\n", s.c_str());
        std::fflush(stdout);
      });
      char line[256];
      std::snprintf(line, sizeof line, "%s: train MSE %.6g -> %.6g (%d parameter sets, %.0f s)", name.c_str(),
                    r.mse_before, r.mse_after, r.evaluations,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      std::printf("%s\n", line);
      summary << "# " << line << "\n";
    }
    std::string header = "tune-classical-ao on " + d.train.dir + " (" + std::to_string(views.size()) + " views, " +
                         std::to_string(rounds) + " rounds); MSE averaged over each method's sample counts";
    remove_stale_temporaries_of(out);  // a killed earlier run's
    write_file_atomic(out, classical_ao::format_classical_params(params, header) + summary.str());
    std::printf("wrote %s\n", out.c_str());
    return 0;
  });
}
