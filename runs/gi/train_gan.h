#pragma once
// train-gan's whole work behind one call, as train_nnao is train-nnao's: the data (the
// splits, the normalisation fitted on the training scenes, the frames held in memory or
// streamed), the run (gan_run.h), then G.blob evaluated on the test split and on the
// held-out families (eval_gi.h).
//
//   TrainGanOptions o;            // the defaults below are the chosen model
//   o.data_dir = "data/surround";
//   return train_gan(o).exit_code;
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "data/require_valid_dataset.h"
#include "data/validation_split.h"
#include "data/kept_views.h"
#include "runs/available_memory.h"
#include "runs/distributed/world.h"
#include "runs/gi/gan_run.h"
#include "runs/gi/gi_samples.h"
#include "runs/gi/eval_gi.h"
#include "runs/run_report.h"

namespace nns::runs {

// train-gan's options; the initialisers are the defaults, and the flags read them.
//
// The model and schedule come from the sweep (apps/sweep-gan.cpp, docs/gan.md "Model no
// more than a scene needs"): on the default surround data, the smallest generator
// within 0.01 SSIM of the best of 16 points (faces 16/32/64, ngf 8/16/32, levels 4/5/6,
// 10 epochs each) is face 64 (global view 256x128), ngf 16, 5 levels: 1.05 M generator
// parameters. ndf follows ngf as in the sweep. 10 epochs: 20 changed SSIM by 0.003 at
// face 32, the limit is the data, not the schedule. The residual output in linear light
// (generator.h) and the DSSIM term are measured deviations from pix2pix (the sweep
// itself ran with L1 alone).
// Rechecked on data v3's validation split (docs/gan.md, "Choosing the default on the
// validation split"): L1 alone, DSSIM weight 0, ngf 32, 30 epochs and the Deep Shading
// U-Net all land within 0.01 SSIM of this model (the best, Deep Shading, 0.937 against
// 0.934, is 7x slower per frame), so the rule above keeps it. Training on v3: ~5 minutes
// with one thread; on data v4 (twice the frames): 6 min 52 s with two threads.
struct TrainGanOptions {
  std::string data_dir;  // train/ + test/ (or flat: split by scene)
  std::string out = "gan-out";
  std::string mode = "surround";  // front | surround (the six-face global view)
  int size = 64;                  // face size the views are box-filtered to (0: as stored)
  int ngf = 16, ndf = 16;         // generator and discriminator base widths
  int levels = 5;                 // U-Net levels
  int d_layers = 3;               // PatchGAN layers (3: 70x70 patches)
  int epochs = 10;                // in all
  int decay_epochs = -1;          // of which the last N decay the rate linearly to 0 (-1: half)
  double lambda = 100;            // weight of the reconstruction term in G's loss
  // Reconstruction = L1 + w x DSSIM (gan_trainer.h); -1: 1 with loss gan or l1 (loss dssim
  // is DSSIM alone). Measured at the chosen size, 1 beats L1 alone on MSE, PSNR, SSIM and
  // linear MSE (docs/gan.md, final table); pix2pix's L1 alone is --dssim-weight 0.
  double dssim_weight = -1;
  double dssim_weight_used() const { return dssim_weight >= 0 ? dssim_weight : loss == "dssim" ? 0 : 1; }
  // + w x L1 of the image's finite differences (models/gi/gi_losses.h). On the textured
  // face-128 data (the default data), w = 1 against 0, 3 seeds each on the validation
  // scenes: MSE 0.00265 (0.00261-0.00271) against 0.00324 (0.00275-0.00378), ꟻLIP 0.179
  // against 0.189, the error within a pixel of a depth or normal break 0.00359 against
  // 0.00434; w = 4 ties 1 (docs/results/2026-12-05-gi-gradient-loss.md).
  double gradient_weight = 1;
  // > 0: G.blob holds the exponential moving average of G's weights with this decay
  // (optim/weight_average.h); 0: the last step's weights.
  double ema = 0;
  // Adam's rate and beta1; unset (-1): by the loss. pix2pix's 2e-4 and 0.5 are a GAN's
  // setting (a low beta1 keeps G's momentum from chasing a discriminator that moves under
  // it); alone on its reconstruction term the generator does better with the ordinary
  // regression setting. For --loss l1, lr 5e-4 with beta1 0.9 against 2e-4 with 0.5, 3
  // seeds each on the validation scenes of the default data v6: FLIP 0.146 (0.144-0.148)
  // against 0.161 (0.159-0.162), SSIM 0.8256 against 0.8245, linear MSE -4%, all beyond
  // the seed range; MSE tied (0.00234 against 0.00235), the error within a pixel of a
  // break +3% inside it. beta1 0.9 at 2e-4 and lr 1e-3 (seed 1 each) were worse
  // (docs/results/2026-12-07-gi-regression-optimizer.md).
  double lr = -1;
  double lr_used() const { return lr > 0 ? lr : loss == "l1" ? 5e-4 : 2e-4; }
  // Data v4 (docs/gan.md, "Results (default data v4)"): the discriminator at a quarter of
  // the generator's rate (two time-scale updates) wins the validation split on MSE and
  // PSNR by more than the 3-seed spread, ties SSIM, and had none of the equal rate's
  // linear-light blow-ups (validation linear MSE: one seed in three at 0.70, the others
  // 0.037-0.042, at a quarter 0.032-0.033; on test four frames at 30-51). At the equal
  // rate D stays ahead (last 10% of steps: D loss 0.16-0.17, G's adversarial 5.8); at a
  // quarter, 0.20-0.21 and 4.7-4.9. lr_d is a rate, not a ratio: another lr leaves it.
  double lr_d = 5e-5;  // 0: lr (pix2pix)
  double beta1 = -1;
  double beta1_used() const { return beta1 >= 0 ? beta1 : loss == "l1" ? 0.9 : 0.5; }
  bool coordconv = true;  // coordinate channels appended to the input
  // gan | l1 | dssim. l1: G alone on the reconstruction term, no discriminator. On the
  // default data v6, 3 seeds each on the validation scenes, it beats the GAN's mean on
  // every measure (MSE 0.00235 (0.00229-0.00243) against 0.00246 (0.00238-0.00257), the
  // error within a pixel of a break 0.00322 against 0.00344, beyond the GAN's range; SSIM
  // 0.8245 against 0.8232) and ties it on the held-out families, for 18% less training time
  // (docs/results/2026-12-07-gi-without-discriminator-three-seeds.md).
  std::string loss = "l1";
  std::string g_norm = "batch";  // batch | none: normalisation in the pix2pix U-Net
  double g_dropout = 0.5;        // dropout in the U-Net's three innermost up blocks (pix2pix)
  // Hidden width of the frame-level head (models/gi/unet.h; 0: none). With 32 the
  // validation MSE fell 7% and the error within a pixel of a break 7%, every seed better
  // in MSE, SSIM and FLIP, at no measurable cost (docs/results/2026-12-06-gi-frame-level.md).
  int level_head = 32;
  // The head also reads the view's light energy (models/gi/frame_level_features.h):
  // validation MSE -15%, every seed better in every measure; held out SSIM 0.904 -> 0.926
  // (docs/results/2026-12-06-gi-frame-energy.md).
  bool level_energy = true;
  std::string arch = "pix2pix";     // pix2pix | deepshading
  std::string residual = "linear";  // off | mapped | linear (generator.h)
  // bf16 where it trains faster and scored within fp32's seed spread on the validation
  // split (core/kernels/gemm_precision.h), fp32 elsewhere.
  Precision precision = faster_training_precision(cpu_features());
  int accumulate = 1;     // samples per optimizer step
  double bucket_mb = 25;  // MiB per gradient bucket of the MPI exchange (0: one)
  int seed = 1;
  GiAugment augment;  // off
  bool resume = false;
  int max_frames = 0;                 // at most N train and N test items (0: all)
  int sample_every = 250;             // sample PNGs every N steps (0: never)
  bool eval = true;                   // evaluate G.blob on the test split (and holdout/) after training
  double train_subset = 1;            // about this share of the training scenes (data-size curves)
  std::string stream = "auto";        // auto | on | off: read training frames from disk as needed
  double memory_budget_gib = -1;      // GiB held in memory before stream auto streams (-1: half the available)
  double validation_fraction = 0.15;  // share of train/'s scenes held out for model selection
  bool test_bn_batch = true;          // BatchNorm batch statistics at test time (else running)
  bool test_dropout = false;
  int poison_step = -1;        // testing: a NaN enters the input at this step
  int stop_after_epochs = -1;  // testing: stop after N epochs as if interrupted
};

struct TrainGanResult {
  GanRunResult run;
  int exit_code = 0;  // 0 finished, 3 stopped on a non-finite value
};

// The splits train-gan reads: validation scenes carved out before anything is fitted,
// then (for data-size curves) a share of the training scenes.
struct GanSplits {
  data::TrainingSplits splits;
  data::SplitListing train;  // splits.listing.train, or the --train-subset of it
};

// The listing alone: the dataset check runs with the first read of the training frames
// (load_training_frames), which keeps what it decodes. A dataset too broken to list gets
// the check's full report instead of the listing's first complaint.
inline GanSplits open_gan_splits(const TrainGanOptions& o) {
  GanSplits s;
  try {
    s.splits = data::open_training_splits(o.data_dir, o.validation_fraction);
  } catch (const std::exception&) {
    data::require_valid_dataset(o.data_dir, data::Purpose::gi);
    throw;
  }
  // The scenes hold_out_validation would move, i.e. the same hash order, so a smaller
  // subset is contained in a larger one.
  s.train = o.train_subset < 1 ? data::hold_out_validation(s.splits.listing.train, o.train_subset).second
                               : s.splits.listing.train;
  return s;
}

inline size_t max_items(const TrainGanOptions& o) { return o.max_frames > 0 ? size_t(o.max_frames) : size_t(-1); }

// The run's options: the model, the schedule and what a --resume must match.
inline GanRunOptions run_options(const TrainGanOptions& o, const GanSplits& s) {
  GanRunOptions r;
  r.out = o.out;
  r.resume = o.resume;
  r.sample_every = o.sample_every;
  r.poison_step = o.poison_step;
  r.stop_after_epochs = o.stop_after_epochs;
  r.precision = o.precision;
  r.accumulate = o.accumulate;
  r.augment = o.augment;
  r.bucket_mb = o.bucket_mb;
  r.quiet = !runs::writer();
  r.data_identity = std::filesystem::weakly_canonical(o.data_dir).string() + " (" + std::to_string(s.train.size()) +
                    " train, " + std::to_string(s.splits.validation.size()) + " validation, " +
                    std::to_string(s.splits.listing.test.size()) + " test)";
  GanTrainConfig& c = r.train;
  c.inputs.mode = gi::parse_mode(o.mode);
  c.inputs.coordconv = o.coordconv;
  c.inputs.size = o.size;
  c.inputs.validation_fraction = s.splits.validation.size() > 0 ? o.validation_fraction : 0;
  c.ngf = o.ngf, c.ndf = o.ndf, c.levels = o.levels, c.d_layers = o.d_layers;
  c.loss = parse_loss(o.loss);
  c.arch = gi::parse_arch(o.arch);
  c.residual = gi::parse_residual(o.residual);
  c.g_batchnorm = o.g_norm == "batch";
  c.g_dropout = float(o.g_dropout);
  // The head scales the predicted indirect light: only the pix2pix U-Net with the linear
  // residual has one.
  c.level_head = c.arch == gi::GiArch::pix2pix && c.residual == gi::GiResidual::linear ? o.level_head : 0;
  c.level_energy = o.level_energy;
  c.lambda = o.lambda, c.lr = o.lr_used(), c.lr_d = o.lr_d, c.beta1 = o.beta1_used();
  c.dssim_weight = o.dssim_weight_used();
  c.gradient_weight = o.gradient_weight;
  c.ema = o.ema;
  const int decay = o.decay_epochs >= 0 ? o.decay_epochs : o.epochs / 2;
  c.epochs = o.epochs - decay, c.epochs_decay = decay;
  c.seed = uint64_t(o.seed);
  return r;
}

// The generator halves its input `levels` times (Deep Shading's U-Net one time fewer), so
// both sides must be divisible by that power of two. A non-square view (the gi preset's
// 256x144) fits only fewer levels: the error says how many, and which sizes would do.
inline void require_unet_divisible(const TrainGanOptions& o, int height, int width) {
  const int halvings = o.arch == "deepshading" ? o.levels - 1 : o.levels;
  const int m = 1 << halvings;
  if (height % m == 0 && width % m == 0) return;
  int fits = 0;
  while (fits < 30 && height % (2 << fits) == 0 && width % (2 << fits) == 0) ++fits;
  const int levels_that_fit = o.arch == "deepshading" ? fits + 1 : fits;
  std::string msg = o.data_dir + ": the generator's input is " + std::to_string(width) + "x" + std::to_string(height) +
                    " (--size " + std::to_string(o.size) + (o.size == 0 ? ": as stored" : "") +
                    "), whose sides are not both divisible by 2^" + std::to_string(halvings) + " = " +
                    std::to_string(m) + " (--levels " + std::to_string(o.levels) + "): ";
  msg += levels_that_fit >= 1 ? "--levels " + std::to_string(levels_that_fit) + " or fewer fits" : "no --levels fits";
  msg += width != height && o.mode == "front"
             ? " (--size N box-filters square views only; a non-square view trains at its stored size)"
             : ", or a --size N that divides the stored face size and is a multiple of " + std::to_string(m);
  throw std::runtime_error(msg);
}

// GiB of training data a run may hold in memory: --memory-budget, or half of what the
// machine has available when the run starts.
inline double memory_budget_gib(const TrainGanOptions& o) {
  return o.memory_budget_gib >= 0 ? o.memory_budget_gib : default_memory_budget_gib();
}

// The files of the first n items of a split as the reader takes them.
inline std::vector<std::string> item_files(const data::SplitListing& s, gi::GiMode mode, size_t n) {
  std::vector<std::string> files;
  const bool frames = mode == gi::GiMode::surround || s.views.empty();
  for (size_t i = 0; i < n; ++i)
    if (frames) files.insert(files.end(), s.frames[i].faces.begin(), s.frames[i].faces.end());
    else files.push_back(s.views[i]);
  return files;
}

// The training frames, normalised with statistics of the training scenes alone; held in
// memory, or streamed from disk when asked or when they would take more than the budget.
// Every split is checked first (a bad file in test/ stops the run now, not after hours of
// training); the check keeps the training files it decodes, at the training size, so that
// in memory each file is decoded once. Streamed, or when the kept views would not fit,
// the normalisation fit reads the files again (and a streamed run every step).
inline GiTrainData load_training_frames(const TrainGanOptions& o, const GanSplits& s, gi::GiInputConfig& inputs) {
  GiItemReader rd{inputs.mode, o.size};
  const size_t n_train = std::min(max_items(o), split_items(s.train, rd.mode));
  if (n_train == 0) throw std::runtime_error(o.data_dir + ": no training samples for --mode " + o.mode);
  const double budget = memory_budget_gib(o);
  data::KeptViews kept(item_files(s.train, rd.mode, n_train), o.stream == "on" ? 0 : budget * double(1 << 30),
                       [rd](data::View&& v) { return rd.shrink(std::move(v)); });
  data::require_valid_dataset(o.data_dir, data::Purpose::gi, &kept);
  if (kept.complete()) rd.kept = &kept;
  // The first item: its shape is every sample's (the checks and the memory estimate need
  // nothing else).
  const gi::GiSample first = load_sample(s.train, rd, inputs, 0);
  require_unet_divisible(o, int(first.input.size(2)), int(first.input.size(3)));
  if (o.augment.mirror) (void)mirrored(first);  // refuses an odd face size before the first step
  inputs.norm = fit_normalisation(s.train, rd, max_items(o));
  const double gib = double(sample_bytes(first)) * double(n_train) / double(1 << 30);
  const bool streamed = o.stream == "on" || (o.stream == "auto" && gib > budget);
  GiItemReader last_use = rd;
  last_use.take = true;
  GiTrainData train = streamed ? GiTrainData(s.train, GiItemReader{rd.mode, rd.size}, inputs, n_train)
                               : GiTrainData(load_samples(s.train, last_use, inputs, max_items(o), "loading train"));
  if (runs::writer()) {
    std::fprintf(stderr,
                 "train-gan: %zu training %s (%zu more in validation scenes) from %s, input %s, depth_max %.3g, "
                 "hdr_scale %.3g, light_max %.3g; %.2f GiB of samples, %s (budget %.1f GiB)\n",
                 n_train, inputs.mode == gi::GiMode::surround ? "frames" : "views", s.splits.validation.size(),
                 o.data_dir.c_str(), first.input.shape().str().c_str(), inputs.norm.depth_max, inputs.norm.hdr_scale,
                 inputs.norm.light_max, gib, streamed ? "streamed from disk" : "held in memory", budget);
    if (rd.kept && !streamed)
      std::fprintf(stderr, "train-gan: each training file decoded once, by the dataset check\n");
    else if (rd.kept)
      std::fprintf(stderr,
                   "train-gan: the dataset check's decoded files served the normalisation; streamed, each "
                   "step reads its frame again\n");
    else
      std::fprintf(stderr, "train-gan: training files decoded again after the dataset check: %s\n",
                   o.stream == "on" ? "--stream on" : kept.reason().c_str());
  }
  return train;
}

// The face size the test frames are stored at (the front view's width; 0 if unknown).
inline int stored_face_size(const data::SplitListing& test, gi::GiMode mode) {
  const std::vector<std::string> files = item_files(test, mode, std::min<size_t>(1, split_items(test, mode)));
  if (files.empty()) return 0;
  data::ReadOptions header;
  header.header_only = true;
  const data::View v = data::read_view(files[0], header);
  return v.width == v.height ? v.width : 0;
}

// G.blob on the test split, and on the held-out families when the data has them
// (eval-ao's layout). Frames stored larger than the training --size are scored at their
// own size, the model's indirect light brought up by the guided upsample (eval-gi's
// --upsample-from, gi-infer's default): the resolution the light is delivered at.
inline void evaluate_trained(const TrainGanOptions& o, const GanSplits& s) {
  const GanRunFiles files{o.out};
  EvalOptions e;
  e.data = o.data_dir;
  e.out = files.eval();
  e.models = {files.generator()};
  e.bn_batch_stats = o.test_bn_batch;
  e.dropout_on = o.test_dropout;
  e.max_frames = max_items(o);
  const int stored = o.size > 0 ? stored_face_size(s.splits.listing.test, gi::parse_mode(o.mode)) : 0;
  if (stored > o.size && stored % o.size == 0) e.size = stored, e.upsample_from = o.size;
  evaluate_gi(e);
  std::printf(
      "train-gan: training %s/report.html; evaluation %s/report.html, chart %s/speed_vs_ssim.png "
      "(report.md, results.csv, previews/ beside them)\n",
      o.out.c_str(), e.out.c_str(), e.out.c_str());
  if (!s.splits.listing.has_holdout) return;
  e.split = "holdout";
  e.out = files.eval_holdout();
  evaluate_gi(e);
  std::printf("train-gan: held-out families %s/report.html, chart %s/speed_vs_ssim.png\n", e.out.c_str(),
              e.out.c_str());
}

inline TrainGanResult train_gan(const TrainGanOptions& o) {
  if (o.precision == Precision::bf16)
    std::fprintf(stderr, "train-gan: bf16 GEMMs on %s\n", bf16_isa_description().c_str());
  else std::fprintf(stderr, "train-gan: fp32 GEMMs\n");
  const GanSplits splits = open_gan_splits(o);
  GanRunOptions run = run_options(o, splits);
  TrainGanResult res;
  {
    GiTrainData train = load_training_frames(o, splits, run.train.inputs);
    res.run = run_gan_training(run, train);
  }  // the evaluation loads its own frames
  const GanRunResult& r = res.run;
  if (runs::writer() && r.d_wins_windows > 0)
    std::fprintf(stderr, "train-gan: the discriminator won outright in %lld windows of %d steps (first at step %lld)\n",
                 (long long)r.d_wins_windows, DiscriminatorWatch::kWindow, (long long)r.first_d_wins_step);
  if (!r.finished) return res.exit_code = 3, res;  // the run layer's non-finite stop
  if (!runs::writer()) return res;                 // rank 0 reports and evaluates
  std::printf("train-gan: %s, %s in %s; generator %s\n", runs::count_of(r.epochs_done, "epoch").c_str(),
              runs::count_of(r.steps, "step").c_str(), Progress::format_seconds(r.seconds).c_str(),
              GanRunFiles{o.out}.generator().c_str());
  if (o.eval && splits.splits.listing.test.size() > 0) evaluate_trained(o, splits);
  return res;
}

}  // namespace nns::runs
