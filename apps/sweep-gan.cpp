// sweep-gan: "a model no more than a scene needs". Trains the GI GAN over a grid of
// face sizes x ngf x levels, scores each on the test split (eval-gi's metrics), charts
// SSIM against ms per frame and against training time, and names the smallest model
// (fewest parameters) within 0.01 SSIM of the best. train-gan's defaults
// (runs/gi/gan_defaults.h) come from its answer; docs/gan.md has the table.
//
//   sweep-gan --out sweep --sizes 16,32 --ngf 8,16,32 --levels 4,5 --epochs 6
//   sweep-gan --out sweep --points 32:16:5,64:16:5     explicit points; finished ones are reused
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "apps/args.h"
#include "core/thread_pool.h"
#include "report/chart.h"
#include "render/default_dataset.h"
#include "runs/gi/gan_defaults.h"
#include "runs/gi/gan_run.h"
#include "runs/gi/gi_data.h"
#include "runs/gi/gi_evaluate.h"

using namespace nns;
using namespace nns::gi;

namespace {

std::vector<int> parse_ints(cli::Args& a, const std::string& flag, const std::string& s) {
  std::vector<int> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      out.push_back(std::stoi(item));
    } catch (...) {
      a.error(flag + ": expected a comma-separated list of integers, got '" + s + "'");
    }
  }
  return out;
}

struct Point {
  int size, ngf, levels;
  int64_t params = 0;
  double train_seconds = 0, ms_per_frame = 0, ssim = 0, psnr = 0, mse = 0;
};

}  // namespace

int main(int argc, char** argv) {
  return cli::run_main("sweep-gan", [&] {
    cli::Args a(argc, argv, "sweep-gan", "Sweep GI GAN sizes; name the smallest model within 0.01 SSIM of the best.");
    std::string data_dir = a.get_string("--data", "", "dataset (default: the built-in surround data)");
    std::string out = a.get_string("--out", "sweep-gan-out", "output folder");
    std::string mode = a.get_choice("--mode", "surround", {"front", "surround"}, "input mode");
    std::string sizes_s = a.get_string("--sizes", "16,32", "face sizes");
    std::string ngf_s = a.get_string("--ngf", "8,16,32", "generator widths (ndf follows ngf)");
    std::string levels_s = a.get_string("--levels", "4,5", "U-Net levels");
    std::string points_s = a.get_string("--points", "", "explicit size:ngf:levels list instead of the grid, e.g. 32:16:5,64:16:5");
    int epochs = a.get_int("--epochs", 6, "epochs per model");
    std::string loss = a.get_choice("--loss", "gan", {"gan", "l1", "dssim"}, "training loss of every point");
    std::string arch = a.get_choice("--arch", "pix2pix", {"pix2pix", "deepshading"}, "generator architecture");
    std::string residual = a.get_choice("--residual", GanDefaults{}.residual, {"off", "mapped", "linear"}, "residual output (docs/gan.md)");
    int max_frames = a.get_int("--max-frames", 0, "at most N train and N test frames (0: all)");
    double tolerance = a.get_double("--ssim-tolerance", 0.01, "how far below the best SSIM still counts");
    int threads = a.get_int("--threads", 2, "worker threads");
    int seed = a.get_int("--seed", 1, "random seed");
    auto sizes = parse_ints(a, "--sizes", sizes_s), ngfs = parse_ints(a, "--ngf", ngf_s),
         levels = parse_ints(a, "--levels", levels_s);
    a.done();
    set_num_threads(threads);
    if (data_dir.empty()) data_dir = data::ensure_default_dataset("surround", threads);
    auto listing = data::list_dataset(data_dir);
    if (listing.flat) listing = data::split_flat_by_scene(listing, 0.2);
    const size_t max_items = max_frames > 0 ? size_t(max_frames) : size_t(-1);
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

    std::vector<Point> points;
    for (int size : all_sizes) {
      GiInputConfig in;
      in.mode = parse_mode(mode);
      in.size = size;
      GiItemReader rd{in.mode, size};
      in.norm = fit_normalisation(listing.train, rd, max_items);
      std::vector<GiSample> train;  // loaded when a point of this size needs training
      for (auto& t : todo) {
        if (t[0] != size) continue;
        const int ngf = t[1], lv = t[2];
        GanRunOptions o;
        o.out = out + "/s" + std::to_string(size) + "_g" + std::to_string(ngf) + "_l" + std::to_string(lv);
        o.sample_every = 0;
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
        Point p{size, ngf, lv};
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
        if (train.empty())
          train = load_samples(listing.train, rd, in, max_items, "sweep: loading size " + std::to_string(size));
        const int64_t H = train[0].input.size(2);
        if (H % (int64_t(1) << lv)) {
          std::fprintf(stderr, "sweep-gan: skipping size %d levels %d (height %lld not divisible by 2^%d)\n",
                       size, lv, (long long)H, lv);
          continue;
        }
        std::fprintf(stderr, "sweep-gan: size %d ngf %d levels %d\n", size, ngf, lv);
        GanRunResult r;
        try {
          r = run_gan_training(o, train);
        } catch (const std::exception& ex) {  // one impossible point must not end the sweep
          std::fprintf(stderr, "sweep-gan: size %d ngf %d levels %d failed: %s\n", size, ngf, lv, ex.what());
          continue;
        }
        if (!r.finished) {
          std::fprintf(stderr, "sweep-gan: %s did not finish: %s\n", o.out.c_str(), r.stop_message.c_str());
          continue;
        }
        EvalOptions e;
        e.data = data_dir, e.out = o.out + "/eval", e.models = {o.out + "/G.blob"};
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
    const Point* chosen = nullptr;
    for (auto& p : points)
      if (p.ssim >= best - tolerance &&
          (!chosen || p.params < chosen->params || (p.params == chosen->params && p.ms_per_frame < chosen->ms_per_frame)))
        chosen = &p;

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
    return 0;
  });
}
