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
#include "report/chart.h"
#include "runs/gi/gan_run.h"
#include "runs/gi/gi_data.h"
#include "runs/gi/gi_evaluate.h"

namespace nns::gi {

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

inline void run_gan_sweep(const GanSweepOptions& so) {
  const std::string &data_dir = so.data_dir, &out = so.out, &mode = so.mode, &points_s = so.points, &loss = so.loss,
                    &arch = so.arch, &residual = so.residual;
  const auto &sizes = so.sizes, &ngfs = so.ngfs, &levels = so.levels;
  const int epochs = so.epochs, max_frames = so.max_frames, threads = so.threads, seed = so.seed;
  const double tolerance = so.tolerance;
  auto listing = data::list_dataset(data_dir);
  if (listing.flat) listing = data::split_flat_by_scene(listing, 0.2);
  const size_t max_items = max_frames > 0 ? size_t(max_frames) : size_t(-1);
  const auto [train_listing, val_listing] = data::hold_out_validation(listing.train, so.validation_fraction);
  if (val_listing.size() == 0)
    throw std::invalid_argument("sweep-gan: " + data_dir + " has too few training scenes for a validation split");
  std::filesystem::create_directories(out);

  // The grid, or the explicit --points list (e.g. 64:16:5 where a full grid at the
  // largest size would not fit the time budget).
  std::vector<std::array<int, 3>> todo;
  if (!points_s.empty()) {
    std::stringstream ss(points_s);
    std::string item;
    while (std::getline(ss, item, ',')) {
      std::array<int, 3> p{};
      if (std::sscanf(item.c_str(), "%d:%d:%d", &p[0], &p[1], &p[2]) != 3)
        throw std::invalid_argument("--points: expected size:ngf:levels,..., got '" + item + "'");
      todo.push_back(p);
    }
  } else {
    for (int size : sizes)
      for (int ngf : ngfs)
        for (int lv : levels) todo.push_back({size, ngf, lv});
  }
  std::vector<int> all_sizes;
  for (auto& t : todo)
    if (std::find(all_sizes.begin(), all_sizes.end(), t[0]) == all_sizes.end()) all_sizes.push_back(t[0]);

  std::vector<SweepPoint> points;
  for (int size : all_sizes) {
    GiInputConfig in;
    in.mode = parse_mode(mode);
    in.size = size;
    in.validation_fraction = so.validation_fraction;
    GiItemReader rd{in.mode, size};
    in.norm = fit_normalisation(train_listing, rd, max_items);
    std::optional<GiTrainData> train;  // loaded when a point of this size needs training
    for (auto& t : todo) {
      if (t[0] != size) continue;
      const int ngf = t[1], lv = t[2];
      GanRunOptions o;
      o.out = out + "/s" + std::to_string(size) + "_g" + std::to_string(ngf) + "_l" + std::to_string(lv);
      o.sample_every = 0;
      o.data_identity = std::filesystem::weakly_canonical(data_dir).string();
      o.train.inputs = in;
      o.train.ngf = ngf, o.train.ndf = ngf, o.train.levels = lv;
      // PatchGAN n = 3 needs a front view of at least 24 pixels (3x3 logits before its
      // two stride-1 convs): smaller faces get the deepest discriminator that fits.
      while (o.train.d_layers > 1 && (size >> o.train.d_layers) < 3) --o.train.d_layers;
      o.train.epochs = epochs - epochs / 2, o.train.epochs_decay = epochs / 2;
      o.train.seed = uint64_t(seed);
      o.train.loss = parse_loss(loss);
      o.train.arch = parse_arch(arch);
      o.train.residual = parse_residual(residual);
      SweepPoint p{size, ngf, lv};
      // A point finished by an earlier sweep into the same folder is reused, not retrained
      // (an interrupted sweep resumes; a later one adds points to the same chart).
      const std::string done = o.out + "/sweep_point.csv";
      if (std::filesystem::exists(done)) {
        std::string line = read_file(done);
        if (std::sscanf(line.c_str(), "%lld,%lf,%lf,%lf,%lf,%lf", (long long*)&p.params, &p.train_seconds,
                        &p.ms_per_frame, &p.ssim, &p.psnr, &p.mse) == 6) {
          std::fprintf(stderr, "sweep-gan: size %d ngf %d levels %d: reusing %s\n", size, ngf, lv, done.c_str());
          points.push_back(p);
          continue;
        }
      }
      if (!train)
        train.emplace(load_samples(train_listing, rd, in, max_items, "sweep: loading size " + std::to_string(size)));
      if (train->empty()) throw std::runtime_error(data_dir + ": no training samples for --mode " + mode);
      const int64_t H = train->get(0).input.size(2);
      if (H % (int64_t(1) << lv)) {
        std::fprintf(stderr, "sweep-gan: skipping size %d levels %d (height %lld not divisible by 2^%d)\n",
                     size, lv, (long long)H, lv);
        continue;
      }
      std::fprintf(stderr, "sweep-gan: size %d ngf %d levels %d\n", size, ngf, lv);
      GanRunResult r;
      try {
        r = run_gan_training(o, *train);
      } catch (const std::exception& ex) {  // one impossible point must not end the sweep
        std::fprintf(stderr, "sweep-gan: size %d ngf %d levels %d failed: %s\n", size, ngf, lv, ex.what());
        continue;
      }
      if (!r.finished) {
        std::fprintf(stderr, "sweep-gan: %s did not finish: %s\n", o.out.c_str(), r.stop_message.c_str());
        continue;
      }
      EvalOptions e;
      e.data = data_dir, e.out = o.out + "/eval", e.models = {o.out + "/G.blob"}, e.split = "validation";
      e.max_frames = max_items, e.previews = 1, e.quiet = true;
      auto rows = evaluate_gi(e);
      const EvalRow& m = rows.back();
      p.params = load_generator(o.out + "/G.blob").G->parameter_count();
      p.train_seconds = r.seconds, p.ms_per_frame = m.ms_per_frame;
      p.ssim = m.all.ssim, p.psnr = m.all.psnr, p.mse = m.all.mse;
      char line[160];
      std::snprintf(line, sizeof line, "%lld,%.3f,%.4f,%.6f,%.4f,%.7f\n", (long long)p.params, p.train_seconds,
                    p.ms_per_frame, p.ssim, p.psnr, p.mse);
      write_file_atomic(done, line);
      points.push_back(p);
    }
  }
  if (points.empty()) throw std::runtime_error("sweep-gan: no configuration finished");

  double best = -1;
  for (auto& p : points) best = std::max(best, p.ssim);
  const SweepPoint* chosen = nullptr;
  for (auto& p : points)
    if (p.ssim >= best - tolerance &&
        (!chosen || p.params < chosen->params || (p.params == chosen->params && p.ms_per_frame < chosen->ms_per_frame)))
      chosen = &p;
  // A NaN SSIM compares false with everything: then nothing is chosen, and the report
  // below must not read it (it used to crash after writing sweep.csv).
  if (!chosen) throw std::runtime_error("sweep-gan: no configuration has a finite SSIM; see " + out + "/*/eval");

  std::string csv = "size,ngf,levels,params,train_seconds,ms_per_frame,ssim,psnr,mse,chosen\n";
  for (auto& p : points) {
    char line[256];
    std::snprintf(line, sizeof line, "%d,%d,%d,%lld,%.1f,%.3f,%.5f,%.3f,%.6f,%d\n", p.size, p.ngf, p.levels,
                  (long long)p.params, p.train_seconds, p.ms_per_frame, p.ssim, p.psnr, p.mse, &p == chosen);
    csv += line;
  }
  write_file_atomic(out + "/sweep.csv", csv);

  // SSIM against ms/frame and against training time, one series per face size.
  for (int which = 0; which < 2; ++which) {
    data::ChartOptions chart;
    chart.title = which == 0 ? "GI GAN sweep: SSIM vs inference time" : "GI GAN sweep: SSIM vs training time";
    chart.x_label = which == 0 ? "ms per frame (" + std::to_string(threads) + " thread(s))" : "training seconds";
    chart.y_label = "SSIM (mapped light, test split)";
    chart.log_x = true;
    std::vector<data::ChartSeries> series;
    for (int size : all_sizes) {
      data::ChartSeries s;
      s.name = "face " + std::to_string(size);
      for (auto& p : points)
        if (p.size == size) {
          s.x.push_back(which == 0 ? p.ms_per_frame : p.train_seconds);
          s.y.push_back(p.ssim);
          s.point_labels.push_back("g" + std::to_string(p.ngf) + "/l" + std::to_string(p.levels));
        }
      if (!s.x.empty()) series.push_back(s);
    }
    std::string note = data::write_chart(out + (which == 0 ? "/ssim_vs_ms.svg" : "/ssim_vs_train_time.svg"), series, chart);
    if (!note.empty()) std::fprintf(stderr, "sweep-gan: %s\n", note.c_str());
  }
  std::printf("%s", csv.c_str());
  std::printf("sweep-gan: best SSIM %.4f; smallest within %.3f: face %d, ngf %d, levels %d (%lld parameters, %.2f ms/frame)\n",
              best, tolerance, chosen->size, chosen->ngf, chosen->levels, (long long)chosen->params,
              chosen->ms_per_frame);
  std::printf("sweep-gan: %s/sweep.csv, %s/ssim_vs_ms.svg\n", out.c_str(), out.c_str());
}

}  // namespace nns::gi
