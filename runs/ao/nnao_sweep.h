#pragma once
// "Model no more than a scene needs": train a size ladder with the same data, seed and
// epochs — for grid models w in {7, 15, 23, 31} x hidden in {4, 8, 16}, for horizon
// models directions in {8, 16, 32} x hidden in {8, 16, 32} — then for each model measure the
// validation MSE (whole scenes carved from the training split; the mean over the last
// 5 epochs, because with dropout 0.5 the per-epoch error still wanders by a few percent
// after convergence, more than the 2% the pick is about), the test MSE (reported, never
// used to choose) and the exact inference time per frame (median of 3 runs on the first
// test view), chart error against time and name the cheapest model (fewest depth samples
// per pixel, then fewest parameters) whose validation error is within 2% of the best.
// Output in OUT/sweep/: w<w>_h<h>/ or d<directions>_h<h>/ (each a train-nnao output),
// sweep.csv, sweep.svg/.png, sweep.md.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "report/chart.h"
#include "data/dataset.h"
#include "data/exr_io.h"
#include "data/validation_split.h"
#include "models/nnao/nnao_inference.h"
#include "runs/ao/train_nnao.h"

namespace nns::runs {

struct SweepEntry {
  int size, hidden;  // size: the grid's w, or the horizon's directions
  int samples;       // depth samples per pixel
  int64_t parameters;
  double val_mse, test_mse, ms_per_frame;  // MSE: mean over the last 5 epochs
};

// The validation share of train/'s scenes when the run names none.
inline constexpr double kSweepValidationFraction = 0.2;

inline std::vector<SweepEntry> run_sweep(const TrainOptions& requested, std::vector<int> sizes = {},
                                         std::vector<int> hiddens = {}) {
  namespace fs = std::filesystem;
  // Chosen on validation, never test: a share of the scenes when the run names no split.
  TrainOptions base = requested;
  if (base.validation_fraction == 0 && base.validation_families.empty())
    base.validation_fraction = kSweepValidationFraction;
  const bool horizon = base.net.input().is_horizon();
  if (sizes.empty()) sizes = horizon ? std::vector<int>{8, 16, 32} : std::vector<int>{7, 15, 23, 31};
  if (hiddens.empty()) hiddens = horizon ? std::vector<int>{8, 16, 32} : std::vector<int>{4, 8, 16};
  const std::string size_name = horizon ? "directions" : "w", tag = horizon ? "d" : "w";
  const fs::path dir = fs::path(base.out_dir) / "sweep";
  fs::create_directories(dir);
  const data::DatasetListing d = data::list_splits(base.data_dir);
  const std::string probe = d.test.views.empty() ? d.train.views.at(0) : d.test.views[0];
  data::View view = data::read_view(probe);
  screen_space::GBuffer g = screen_space::gbuffer_from_view(view, base.radius);
  std::vector<float> out(size_t(g.pixels()));
  std::vector<SweepEntry> entries;
  for (int w : sizes)
    for (int h : hiddens) {
      TrainOptions o = base;
      (horizon ? o.net.horizon.directions : o.net.window) = w;
      o.net.hidden = h;
      o.out_dir = (dir / (tag + std::to_string(w) + "_h" + std::to_string(h))).string();
      // --resume continues each rung from its own checkpoint (a finished rung only
      // rebuilds its points and re-times), so an interrupted sweep need not start over.
      o.resume = base.resume && fs::exists(fs::path(o.out_dir) / "checkpoint.blob");
      if (!o.quiet) std::fprintf(stderr, "sweep: %s %d, hidden %d\n", size_name.c_str(), w, h);
      TrainResult r = train_nnao(o);
      if (r.exit_code != 0) {
        std::fprintf(stderr, "sweep: %s %d, hidden %d left out: %s\n", size_name.c_str(), w, h, r.stop_message.c_str());
        continue;
      }
      // The rung's whole log (also the epochs of an earlier, resumed run).
      const auto log = runs::read_metrics((fs::path(o.out_dir) / "metrics.jsonl").string());
      auto last5 = [&](const char* key) {
        const std::vector<double> v = runs::metrics_series(log, key);
        const size_t k = std::min<size_t>(5, v.size());
        double m = 0;
        for (size_t i = v.size() - k; i < v.size(); ++i) m += v[i] / double(k);
        return k ? m : std::nan("");
      };
      const double mse = last5("test_mse"), val = last5("val_mse");
      nnao::NnaoWeights m = nnao::NnaoWeights::load((fs::path(o.out_dir) / "nnao.blob").string());
      std::vector<double> ms;
      for (int k = 0; k < 3; ++k) {
        auto t0 = std::chrono::steady_clock::now();
        nnao::infer_exact(m, g, out.data());
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
      std::sort(ms.begin(), ms.end());
      const int64_t F = o.net.inputs();
      entries.push_back(
          {w, h, o.net.input().samples(), F * h + h + 2 * (h * h + h) + h + 1 + 2 * (3 * h + 1), val, mse, ms[1]});
    }
  double best = 1e300;
  // Chosen on the validation scenes (carved from the training split), never the test.
  for (auto& e : entries) best = std::min(best, e.val_mse);
  const SweepEntry* pick = nullptr;
  for (auto& e : entries)
    if (e.val_mse <= best * 1.02 &&
        (!pick || std::pair(e.samples, e.parameters) < std::pair(pick->samples, pick->parameters)))
      pick = &e;
  std::string csv = size_name + ",hidden,samples,parameters,val_mse,test_mse,ms_per_frame\n";
  std::map<int, report::ChartSeries> by_hidden;
  for (auto& e : entries) {
    char line[160];
    std::snprintf(line, sizeof line, "%d,%d,%d,%lld,%.6g,%.6g,%.4g\n", e.size, e.hidden, e.samples,
                  (long long)e.parameters, e.val_mse, e.test_mse, e.ms_per_frame);
    csv += line;
    auto& s = by_hidden[e.hidden];
    s.name = "hidden " + std::to_string(e.hidden);
    s.x.push_back(e.ms_per_frame);
    s.y.push_back(e.val_mse);
    s.point_labels.push_back(tag + std::to_string(e.size));
  }
  write_file_atomic((dir / "sweep.csv").string(), csv);
  std::vector<report::ChartSeries> series;
  for (auto& [h, s] : by_hidden) series.push_back(s);
  report::ChartOptions co;
  co.title = "NNAO size ladder: validation error vs exact inference time";
  co.x_label = "ms per frame (exact inference, " + std::to_string(g.width) + "x" + std::to_string(g.height) + ")";
  co.y_label = "validation MSE";
  co.log_x = true;
  report::write_chart((dir / "sweep.svg").string(), series, co);
  char setup[256];
  std::snprintf(setup, sizeof setup, "%d epochs each, gamma %g, %d training points per view, batch %d, seed %llu",
                base.epochs, base.gamma, base.points_per_view, base.batch, (unsigned long long)base.seed);
  std::string val_note =
      "whole scenes carved from the training split (" + std::to_string(base.validation_fraction) + " of it)";
  if (!base.validation_families.empty()) {
    val_note = "the training split's families";
    for (auto& f : base.validation_families) val_note += " " + f;
    val_note += ", held out of training";
  }
  std::string md = "# NNAO size sweep (" + base.net.features + " features)\n\n" + std::string(setup) + ", data " +
                   base.data_dir + ". Validation MSE (the choice): " + val_note +
                   "; test MSE: the test split, reported, never used to choose. Both: mean over the last 5 epochs. "
                   "ms/frame: exact inference of the first test view, median of 3, " +
                   std::to_string(num_threads()) + " thread(s).\n\n| " + size_name +
                   " | hidden | samples | parameters | validation MSE | test MSE | ms/frame (exact) "
                   "|\n|---|---|---|---|---|---|---|\n";
  for (auto& e : entries) {
    char line[160];
    std::snprintf(line, sizeof line, "| %d | %d | %d | %lld | %.5f | %.5f | %.1f |\n", e.size, e.hidden, e.samples,
                  (long long)e.parameters, e.val_mse, e.test_mse, e.ms_per_frame);
    md += line;
  }
  if (pick) {
    char line[256];
    std::snprintf(line, sizeof line,
                  "\nBest validation MSE %.5f. Cheapest model within 2%% of it: **%s = %d, hidden = %d** (%lld "
                  "parameters, validation MSE %.5f, test MSE %.5f, %.1f ms/frame).\n",
                  best, size_name.c_str(), pick->size, pick->hidden, (long long)pick->parameters, pick->val_mse,
                  pick->test_mse, pick->ms_per_frame);
    md += line;
    std::printf("%s", line + 1);
  }
  write_file_atomic((dir / "sweep.md").string(), md);
  std::printf("sweep: %s (chart %s)\n", (dir / "sweep.md").string().c_str(), (dir / "sweep.svg").string().c_str());
  return entries;
}

}  // namespace nns::runs
