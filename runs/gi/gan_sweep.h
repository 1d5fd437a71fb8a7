#pragma once
// The GI GAN size sweep behind sweep-gan: "a model no more than a scene needs". Trains
// over a grid of face sizes x ngf x levels (or an explicit list of points), scores each
// on the validation split (scenes carved from train/, never the test split: the sweep
// chooses defaults; eval-gi's metrics), charts SSIM against ms per frame and against
// training time, and names the smallest model (fewest parameters) within `tolerance`
// SSIM of the best. A point finished by an earlier sweep into the same folder is reused.
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "data/dataset.h"
#include "data/validation_split.h"
#include "report/chart.h"
#include "runs/gi/gan_run.h"
#include "runs/gi/gi_samples.h"
#include "runs/gi/eval_gi.h"

namespace nns::runs {

struct GanSweepOptions {
  std::string data_dir, out, mode = "surround", points, loss = "gan", arch = "pix2pix", residual;
  std::vector<int> sizes, ngfs, levels;
  int epochs = 6, max_frames = 0, threads = 2, seed = 1;
  double tolerance = 0.01;
  double validation_fraction = 0.15;  // share of train/'s scenes every point is scored on
};

struct SweepPoint {
  int size, ngf, levels;
  int64_t params = 0;
  double train_seconds = 0, ms_per_frame = 0, ssim = 0, psnr = 0, mse = 0;
};

// The grid, or the explicit --points list (e.g. 64:16:5 where a full grid at the largest
// size would not fit the time budget): {size, ngf, levels} each.
inline std::vector<std::array<int, 3>> sweep_todo(const GanSweepOptions& so) {
  std::vector<std::array<int, 3>> todo;
  if (!so.points.empty()) {
    std::stringstream ss(so.points);
    std::string item;
    while (std::getline(ss, item, ',')) {
      std::array<int, 3> p{};
      if (std::sscanf(item.c_str(), "%d:%d:%d", &p[0], &p[1], &p[2]) != 3)
        throw std::invalid_argument("--points: expected size:ngf:levels,..., got '" + item + "'");
      todo.push_back(p);
    }
  } else {
    for (int size : so.sizes)
      for (int ngf : so.ngfs)
        for (int lv : so.levels) todo.push_back({size, ngf, lv});
  }
  return todo;
}

// The face sizes of the points, in their first order.
inline std::vector<int> sweep_sizes(const std::vector<std::array<int, 3>>& todo) {
  std::vector<int> sizes;
  for (auto& t : todo)
    if (std::find(sizes.begin(), sizes.end(), t[0]) == sizes.end()) sizes.push_back(t[0]);
  return sizes;
}

// One point's run: the sweep's schedule and losses at this size, width and depth.
inline GanRunOptions sweep_point_options(const GanSweepOptions& so, const gi::GiInputConfig& in, int ngf, int lv) {
  GanRunOptions o;
  o.out = so.out + "/s" + std::to_string(in.size) + "_g" + std::to_string(ngf) + "_l" + std::to_string(lv);
  o.sample_every = 0;
  o.data_identity = std::filesystem::weakly_canonical(so.data_dir).string();
  o.train.inputs = in;
  o.train.ngf = ngf, o.train.ndf = ngf, o.train.levels = lv;
  // PatchGAN n = 3 needs a front view of at least 24 pixels (3x3 logits before its
  // two stride-1 convs): smaller faces get the deepest discriminator that fits.
  while (o.train.d_layers > 1 && (in.size >> o.train.d_layers) < 3) --o.train.d_layers;
  o.train.epochs = so.epochs - so.epochs / 2, o.train.epochs_decay = so.epochs / 2;
  o.train.seed = uint64_t(so.seed);
  o.train.loss = parse_loss(so.loss);
  o.train.arch = gi::parse_arch(so.arch);
  o.train.residual = gi::parse_residual(so.residual);
  return o;
}

// A point finished by an earlier sweep into the same folder is reused, not retrained (an
// interrupted sweep resumes; a later one adds points to the same chart).
inline bool read_finished_point(const std::string& done, SweepPoint& p) {
  if (!std::filesystem::exists(done)) return false;
  std::string line = read_file(done);
  return std::sscanf(line.c_str(), "%lld,%lf,%lf,%lf,%lf,%lf", (long long*)&p.params, &p.train_seconds, &p.ms_per_frame,
                     &p.ssim, &p.psnr, &p.mse) == 6;
}

// Trains one point and scores G.blob on the validation split; false when the point
// cannot be trained (a failure must not end the sweep) or stopped on a non-finite value.
inline bool train_and_score_point(const GanSweepOptions& so, const GanRunOptions& o, GiTrainData& train,
                                  size_t max_items, SweepPoint& p) {
  GanRunResult r;
  try {
    r = run_gan_training(o, train);
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "sweep-gan: size %d ngf %d levels %d failed: %s\n", p.size, p.ngf, p.levels, ex.what());
    return false;
  }
  if (!r.finished) {
    std::fprintf(stderr, "sweep-gan: %s did not finish: %s\n", o.out.c_str(), r.stop_message.c_str());
    return false;
  }
  const GanRunFiles files{o.out};
  EvalOptions e;
  e.data = so.data_dir, e.out = files.eval(), e.models = {files.generator()}, e.split = "validation";
  e.max_frames = max_items, e.previews = 1, e.quiet = true;
  auto rows = evaluate_gi(e);
  const EvalRow& m = rows.back();
  p.params = gi::load_generator(files.generator()).G->parameter_count();
  p.train_seconds = r.seconds, p.ms_per_frame = m.ms_per_frame;
  p.ssim = m.all.ssim, p.psnr = m.all.psnr, p.mse = m.all.mse;
  return true;
}

// Every point of the sweep, trained or reused, size by size: a size's frames are
// loaded once, when its first point needs training.
inline std::vector<SweepPoint> sweep_points(const GanSweepOptions& so, const std::vector<std::array<int, 3>>& todo,
                                            const data::SplitListing& train_listing) {
  const size_t max_items = so.max_frames > 0 ? size_t(so.max_frames) : size_t(-1);
  std::vector<SweepPoint> points;
  for (int size : sweep_sizes(todo)) {
    gi::GiInputConfig in;
    in.mode = gi::parse_mode(so.mode);
    in.size = size;
    in.validation_fraction = so.validation_fraction;
    GiItemReader rd{in.mode, size};
    in.norm = fit_normalisation(train_listing, rd, max_items);
    std::optional<GiTrainData> train;
    for (auto& t : todo) {
      if (t[0] != size) continue;
      const int ngf = t[1], lv = t[2];
      const GanRunOptions o = sweep_point_options(so, in, ngf, lv);
      SweepPoint p{size, ngf, lv};
      const std::string done = o.out + "/sweep_point.csv";
      if (read_finished_point(done, p)) {
        std::fprintf(stderr, "sweep-gan: size %d ngf %d levels %d: reusing %s\n", size, ngf, lv, done.c_str());
        points.push_back(p);
        continue;
      }
      if (!train)
        train.emplace(load_samples(train_listing, rd, in, max_items, "sweep: loading size " + std::to_string(size)));
      if (train->empty()) throw std::runtime_error(so.data_dir + ": no training samples for --mode " + so.mode);
      const int64_t H = train->get(0).input.size(2);
      if (H % (int64_t(1) << lv)) {
        std::fprintf(stderr, "sweep-gan: skipping size %d levels %d (height %lld not divisible by 2^%d)\n", size, lv,
                     (long long)H, lv);
        continue;
      }
      std::fprintf(stderr, "sweep-gan: size %d ngf %d levels %d\n", size, ngf, lv);
      if (!train_and_score_point(so, o, *train, max_items, p)) continue;
      char line[160];
      std::snprintf(line, sizeof line, "%lld,%.3f,%.4f,%.6f,%.4f,%.7f\n", (long long)p.params, p.train_seconds,
                    p.ms_per_frame, p.ssim, p.psnr, p.mse);
      write_file_atomic(done, line);
      points.push_back(p);
    }
  }
  if (points.empty()) throw std::runtime_error("sweep-gan: no configuration finished");
  return points;
}

// The smallest model (fewest parameters, then fastest) within `tolerance` SSIM of the
// best. A NaN SSIM compares false with everything: then nothing is chosen, and the report
// must not read it.
inline const SweepPoint& choose_point(const std::vector<SweepPoint>& points, double tolerance, double& best,
                                      const std::string& out) {
  best = -1;
  for (auto& p : points) best = std::max(best, p.ssim);
  const SweepPoint* chosen = nullptr;
  for (auto& p : points)
    if (p.ssim >= best - tolerance &&
        (!chosen || p.params < chosen->params || (p.params == chosen->params && p.ms_per_frame < chosen->ms_per_frame)))
      chosen = &p;
  if (!chosen) throw std::runtime_error("sweep-gan: no configuration has a finite SSIM; see " + out + "/*/eval");
  return *chosen;
}

inline std::string sweep_csv(const std::vector<SweepPoint>& points, const SweepPoint& chosen) {
  std::string csv = "size,ngf,levels,params,train_seconds,ms_per_frame,ssim,psnr,mse,chosen\n";
  for (auto& p : points) {
    char line[256];
    std::snprintf(line, sizeof line, "%d,%d,%d,%lld,%.1f,%.3f,%.5f,%.3f,%.6f,%d\n", p.size, p.ngf, p.levels,
                  (long long)p.params, p.train_seconds, p.ms_per_frame, p.ssim, p.psnr, p.mse, &p == &chosen);
    csv += line;
  }
  return csv;
}

// SSIM against ms/frame and against training time, one series per face size.
inline void write_sweep_charts(const GanSweepOptions& so, const std::vector<SweepPoint>& points,
                               const std::vector<int>& sizes) {
  for (int which = 0; which < 2; ++which) {
    report::ChartOptions chart;
    chart.title = which == 0 ? "GI GAN sweep: SSIM vs inference time" : "GI GAN sweep: SSIM vs training time";
    chart.x_label = which == 0 ? "ms per frame (" + std::to_string(so.threads) + " thread(s))" : "training seconds";
    chart.y_label = "SSIM (mapped light, test split)";
    chart.log_x = true;
    std::vector<report::ChartSeries> series;
    for (int size : sizes) {
      report::ChartSeries s;
      s.name = "face " + std::to_string(size);
      for (auto& p : points)
        if (p.size == size) {
          s.x.push_back(which == 0 ? p.ms_per_frame : p.train_seconds);
          s.y.push_back(p.ssim);
          s.point_labels.push_back("g" + std::to_string(p.ngf) + "/l" + std::to_string(p.levels));
        }
      if (!s.x.empty()) series.push_back(s);
    }
    std::string note =
        report::write_chart(so.out + (which == 0 ? "/ssim_vs_ms.svg" : "/ssim_vs_train_time.svg"), series, chart);
    if (!note.empty()) std::fprintf(stderr, "sweep-gan: %s\n", note.c_str());
  }
}

inline void run_gan_sweep(const GanSweepOptions& so) {
  const data::TrainingSplits splits = data::open_training_splits(so.data_dir, so.validation_fraction);
  if (splits.validation.size() == 0)
    throw std::invalid_argument("sweep-gan: " + so.data_dir + " has too few training scenes for a validation split");
  std::filesystem::create_directories(so.out);
  const std::vector<std::array<int, 3>> todo = sweep_todo(so);
  const std::vector<SweepPoint> points = sweep_points(so, todo, splits.listing.train);
  double best = 0;
  const SweepPoint& chosen = choose_point(points, so.tolerance, best, so.out);
  const std::string csv = sweep_csv(points, chosen);
  write_file_atomic(so.out + "/sweep.csv", csv);
  write_sweep_charts(so, points, sweep_sizes(todo));
  std::printf("%s", csv.c_str());
  std::printf(
      "sweep-gan: best SSIM %.4f; smallest within %.3f: face %d, ngf %d, levels %d (%lld parameters, %.2f ms/frame)\n",
      best, so.tolerance, chosen.size, chosen.ngf, chosen.levels, (long long)chosen.params, chosen.ms_per_frame);
  std::printf("sweep-gan: %s/sweep.csv, %s/ssim_vs_ms.svg\n", so.out.c_str(), so.out.c_str());
}

}  // namespace nns::runs
