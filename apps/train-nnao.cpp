// train-nnao: train Neural Network Ambient Occlusion on an EXR G-buffer dataset.
//   train-nnao [--data DIR] [--out DIR] [--preset default|grid|paper] [--features grid|horizon]
//              [--epochs N] [--batch 16] [--lr 1e-3] [--window 31] [--directions 16] [--steps 8]
//              [--bands 4] [--hidden 16] [--radius R] [--dropout 0] [--gamma 1e-4]
//              [--points-per-view 1024] [--threads 2] [--seed S] [--resume] [--sweep]
//              [--shuffle-chunk 256] [--shuffle-buffer-mb 512] [--precision fp32|bf16]
// The points go to unnamed files in --out (7.7 KB each for a w-31 grid, 0.14 KB for the
// default horizons): memory stays at the two shuffle buffers whatever the data size.
// Without --data it renders (once, cached) and uses the built-in default dataset.
// --sweep trains a size sweep instead (runs/ao/nnao_sweep.h; --resume continues an
// interrupted sweep); --ladder trains the speed/accuracy ladder (runs/ao/nnao_ladder.h).
// `mpirun -np N train-nnao --accumulate K ...` (K >= N) trains data-parallel with the
// weights of the one-process run with --accumulate K (docs/distributed.md).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "apps/args.h"
#include "core/thread_pool.h"
#include "render/default_dataset.h"
#include "runs/ao/nnao_ladder.h"
#include "runs/ao/nnao_sweep.h"
#include "runs/ao/train_nnao.h"
#include "runs/distributed/world.h"

using namespace nns;

// What the command line asks for: the training options and what to train.
struct Command {
  runs::TrainOptions options;
  int threads = 2;
  bool ladder = false, sweep = false;
  int sweep_epochs = 8;
  std::vector<runs::Rung> rungs;
};

// The network's and the inference's flags (features, sizes, blur, resolution), over the
// preset's values d.
void read_network_flags(apps::Args& args, const runs::TrainOptions& d, runs::TrainOptions& o) {
  o.net.features = args.get_choice("--features", d.net.features, {"grid", "horizon"},
                                   "grid: the paper's w x w grid of normal/depth differences; horizon: horizon "
                                   "profiles (models/nnao/horizon_features.h)");
  o.net.window = args.get_int("--window", d.net.window, "grid features: grid size w (w x w samples)", 1, 63);
  o.net.horizon.directions =
      args.get_int("--directions", d.net.horizon.directions, "horizon features: screen directions", 1, 64);
  o.net.horizon.steps = args.get_int("--steps", d.net.horizon.steps, "horizon features: samples per direction", 1, 64);
  o.net.horizon.bands =
      args.get_int("--bands", d.net.horizon.bands, "horizon features: distance bands (must divide --steps)", 1, 64);
  o.blur_passes =
      args.get_int("--blur-passes", d.blur_passes,
                   "horizon features: bilateral blur passes of the exact inference (recorded in the blob)", 1, 16);
  o.blur_depth = args.get_double("--blur-depth", d.blur_depth,
                                 "horizon features: the blur's depth term, exp(-(dz / (D r))^2): larger blurs across "
                                 "bigger depth steps (recorded)",
                                 0.01, 100);
  o.blur_normal_power = args.get_int(
      "--blur-normal-power", d.blur_normal_power,
      "horizon features: the blur's normal term, max(0, n.n')^P: smaller blurs across sharper creases (recorded)", 0,
      64);
  o.radius_term_max = args.get_double("--radius-term-max", d.radius_term_max,
                                      "horizon features: the inference holds the radius term log2(1 + R_px) / 8 at "
                                      "most at X (0: no ceiling; training sees it unclamped; recorded)",
                                      0, 100);
  o.downsample = std::stoi(args.get_choice(
      "--downsample", std::to_string(d.downsample), {"1", "2", "4"},
      "horizon features: march, network and blur at 1/s of the resolution, then a depth- and normal-guided upsample; "
      "trained on points of frames downsampled alike, against the full-resolution truth (recorded)"));
  o.net.hidden = args.get_int("--hidden", d.net.hidden, "hidden units per layer", 1, 64);
  o.radius = float(args.get_double("--radius", d.radius, "AO radius (0 = each view's aoRadius)", 0, HUGE_VAL));
  o.net.dropout = args.get_double("--dropout", d.net.dropout, "dropout on the input", 0, 0.99);
}

Command read_flags(apps::Args& args) {
  Command c;
  runs::TrainOptions& o = c.options;
  o.data_dir = args.get_string("--data", o.data_dir,
                               "dataset folder (default: the built-in default nnao dataset, rendered once and cached)");
  o.out_dir = args.get_path("--out", o.out_dir, "output folder: nnao.blob, metrics.jsonl, loss.svg, checkpoint");
  // The presets are what the project's measurements chose (runs/ao/nnao_train_options.h,
  // docs/nnao.md); every flag below overrides its part of the preset.
  const std::string preset = args.get_choice(
      "--preset", "default", {"default", "grid", "paper"},
      "default: horizon features 16x8 in 4 bands, hidden 16 (chosen on validation families); "
      "grid: the paper's w 31 grid, hidden 4, gamma 1e-4; paper: Holden et al.'s w 31, hidden 4, gamma 0.01");
  const runs::TrainOptions d = runs::preset_options(preset);  // the flags' defaults
  read_network_flags(args, d, o);
  o.epochs = args.get_int("--epochs", d.epochs, "training epochs (the paper: 100)", 0, 100000);
  o.batch = args.get_int("--batch", d.batch, "mini-batch size (the global batch under mpirun, whatever the rank count)",
                         1, 65536);
  o.accumulate = args.get_int("--accumulate", runs::default_accumulate(d.accumulate),
                              "micro-batches per step (of --batch / K points; their gradients averaged in a fixed "
                              "order); under mpirun spread over the ranks, so at least the rank count",
                              1, 65536);
  o.bucket_mb =
      args.get_double("--bucket-mb", d.bucket_mb,
                      "MiB per gradient bucket sent between MPI ranks (0: one bucket, sent after backward)", 0, 1e6);
  o.lr = args.get_double("--lr", d.lr, "Adam learning rate", 1e-12, 1e9);
  o.gamma = args.get_double("--gamma", d.gamma, "L1 weight penalty gamma", 0, HUGE_VAL);
  o.points_per_view = args.get_int("--points-per-view", d.points_per_view, "training pixels per view", 1, 1 << 20);
  o.test_points_per_view =
      args.get_int("--test-points-per-view", d.test_points_per_view, "test pixels per view (test loss)", 1, 1 << 20);
  o.shuffle_chunk = args.get_int("--shuffle-chunk", d.shuffle_chunk,
                                 "points per chunk of the chunked shuffle (read from disk in one piece)", 1, 1 << 24);
  o.shuffle_buffer_mb = args.get_double(
      "--shuffle-buffer-mb", d.shuffle_buffer_mb,
      "MiB per shuffle buffer (two are held); one that holds every training point gives the global shuffle", 1e-6, 1e7);
  o.precision = parse_precision(args.get_choice(
      "--precision", precision_name(d.precision), {"fp32", "bf16"},
      "inputs of the network's products: fp32, or bf16 with fp32 sums, weights and Adam (docs/nnao.md)"));
  c.threads = args.get_int("--threads", 2, "worker threads", 1, 256);
  o.seed = uint64_t(args.get_int("--seed", int(d.seed), "random seed", 0, INT_MAX));
  o.validation_fraction = args.get_double(
      "--validation-fraction", d.validation_fraction,
      "share of the training split's scenes held out as validation (val_mse); --sweep uses 0.2 when 0", 0, 0.9);
  o.validation_families = args.get_names(
      "--validation-families", "",
      "scene families of the training split held out as validation (val_mse), e.g. vaults,foliage,terrain");
  o.resume = args.get_flag("--resume", "continue from OUT/checkpoint.blob (refused if any other flag changed)");
  c.ladder = args.get_flag(
      "--ladder",
      "train the NNAO ladder instead of one model: every rung (cheapest first) into OUT/<rung>/, listed in "
      "OUT/ladder.csv, for eval-ao --ladder and export-nnao --ladder (runs/ao/nnao_ladder.h)");
  const std::string rungs = args.get_string(
      "--ladder-rungs", "",
      "--ladder's rungs as D:S:B:H:s:P[:N] (directions, steps, bands, hidden, downsample 1/2/4, blur passes, the "
      "blur's normal power), comma-separated (default: the ladder chosen on the validation families)");
  c.sweep = args.get_flag("--sweep",
                          "train the size ladder (grid: w 7/15/23/31 x hidden 4/8/16; horizon: directions 8/16/32 "
                          "x hidden 8/16/32) and chart error vs ms/frame");
  c.sweep_epochs = args.get_int("--sweep-epochs", o.net.features == "horizon" ? 8 : 40,
                                "epochs per model in --sweep (grid 40: converged on the default data; horizon 8, "
                                "as the preset; the sweep trains with the preset's or --gamma's gamma)",
                                1, 100000);
  if (o.batch % o.accumulate != 0)
    args.error("--accumulate must divide --batch" +
               (runs::size() > 1 ? " (under mpirun its default is the rank count, " + std::to_string(runs::size()) + ")"
                                 : std::string()));
  if (c.sweep && runs::size() > 1) args.error("--sweep runs in one process (not under mpirun)");
  if (c.ladder && (c.sweep || runs::size() > 1)) args.error("--ladder runs in one process, without --sweep");
  c.rungs = runs::default_ladder();
  if (!rungs.empty()) try {
      c.rungs = runs::parse_rungs(rungs);
    } catch (const std::invalid_argument& e) {
      args.error(e.what());
    }
  if (o.accumulate < runs::size())
    args.error("--accumulate must be at least the number of MPI ranks (" + std::to_string(runs::size()) + ")");
  args.done();
  return c;
}

int main(int argc, char** argv) {
  runs::Session mpi(argc, argv);
  return mpi.finish(apps::run_main("train-nnao", [&]() -> int {
    apps::Args args(argc, argv, "train-nnao", "Train NNAO (Holden et al. 2016) on EXR G-buffers.");
    Command c = read_flags(args);
    runs::TrainOptions& o = c.options;
    const int threads = c.threads;
    runs::announce_accumulate("train-nnao", o.accumulate);
    o.quiet = !runs::writer();
    set_num_threads(threads);
    if (o.data_dir.empty())
      o.data_dir = runs::rank0_first([&] { return render::ensure_default_dataset("nnao", threads); });
    if (c.ladder) {
      runs::train_ladder(o, c.rungs);
      return 0;
    }
    if (c.sweep) {
      o.epochs = c.sweep_epochs;
      runs::run_sweep(o);
      return 0;
    }
    runs::TrainResult r = runs::train_nnao(o);
    if (r.exit_code != 0) return r.exit_code;  // the run layer's non-finite stop, already reported
    if (!runs::writer()) return 0;
    char mse[48] = "not measured (no epoch ran)";
    if (std::isfinite(r.test_mse)) std::snprintf(mse, sizeof mse, "%.5f", r.test_mse);
    std::printf(
        "trained on %lld points (%lld test), %lld steps, %.1f us/step (%.0f samples/s), test MSE %s, "
        "%.1f s (points %.1f s, %.2f s/epoch)\n",
        (long long)r.train_points, (long long)r.test_points, (long long)r.steps, r.step_microseconds,
        r.step_microseconds > 0 ? 1e6 * o.batch / r.step_microseconds : 0.0, mse, r.seconds, r.build_seconds,
        r.epoch_seconds);
    std::printf("model: %s/nnao.blob  metrics: %s/metrics.jsonl  chart: %s/loss.svg  report: %s/report.html\n",
                o.out_dir.c_str(), o.out_dir.c_str(), o.out_dir.c_str(), o.out_dir.c_str());
    return 0;
  }));
}
