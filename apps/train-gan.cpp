// train-gan: learn screen-space global illumination from G-buffers with a pix2pix
// conditional GAN (U-Net generator, PatchGAN discriminator), front-only (Deep
// Illumination) or surround-aware (the thesis's global view). See docs/gan.md.
//
//   train-gan                                  default surround data, default model
//   train-gan --data DIR --mode front --out runs/front
//   train-gan --loss l1                        the non-adversarial baseline
//   train-gan --loss dssim --arch deepshading  Deep Shading's U-Net and loss
//   train-gan --out runs/x --resume            continue exactly where runs/x stopped
//   train-gan --aug-mirror --aug-exposure 1.4 --aug-tint 1.15   augmented samples (docs/gan.md)
//   mpirun -np 2 train-gan --accumulate 4      data-parallel: the weights of one process
//                                              with --accumulate 4 (docs/distributed.md)
#include <cstdio>
#include <filesystem>
#include <string>

#include "apps/args.h"
#include "data/require_valid_dataset.h"
#include "core/thread_pool.h"
#include "data/dataset.h"
#include "data/validation_split.h"
#include "render/default_dataset.h"
#include "runs/gi/gan_defaults.h"
#include "runs/gi/gan_run.h"
#include "runs/gi/gi_data.h"
#include "runs/gi/gi_evaluate.h"
#include "runs/distributed/world.h"

using namespace nns;
using namespace nns::gi;

int main(int argc, char** argv) {
  dist::Session mpi(argc, argv);
  return mpi.finish(cli::run_main("train-gan", [&] {
    cli::Args a(argc, argv, "train-gan",
                "Train a pix2pix GAN (or an L1/DSSIM U-Net) to predict diffuse global illumination.");
    const GanDefaults def;
    std::string data_dir = a.get_string("--data", "", "dataset folder (default: the built-in surround data, rendered once and cached)");
    std::string out = a.get_path("--out", "gan-out", "output folder");
    std::string mode = a.get_choice("--mode", "surround", {"front", "surround"}, "front view only, or the six-face global view");
    int size = a.get_int("--size", def.size, "face size the views are box-filtered to (0: as stored)", 4, 4096);
    int ngf = a.get_int("--ngf", def.ngf, "generator base width", 1, 1024);
    int ndf = a.get_int("--ndf", def.ndf, "discriminator base width", 1, 1024);
    int levels = a.get_int("--levels", def.levels, "U-Net levels (input size divisible by 2^levels)", 1, 12);
    int d_layers = a.get_int("--d-layers", 3, "PatchGAN layers (3: 70x70 patches)", 1, 10);
    int epochs = a.get_int("--epochs", def.epochs, "epochs in all", 1, 100000);
    int decay = a.get_int("--decay-epochs", -1, "of which the last N decay the rate linearly to 0 (default: half)", -1, 100000);
    double lambda = a.get_double("--lambda", 100, "weight of the L1 term in the generator loss", 0, HUGE_VAL);
    double dssim_weight = a.get_double("--dssim-weight", -1, "add this times DSSIM to the L1 term (default: 1 with --loss gan, 0 with l1; 0 is pix2pix's L1 alone)");
    double lr = a.get_double("--lr", def.lr, "Adam learning rate", 1e-12, 1e9);
    double lr_d = a.get_double("--lr-d", def.lr_d, "the discriminator's learning rate (0: --lr, as pix2pix; the default, a quarter of the default --lr, won the validation split: docs/gan.md)", 0, 1e9);
    double beta1 = a.get_double("--beta1", 0.5, "Adam beta1", 0, 0.9999);
    std::string coordconv = a.get_choice("--coordconv", "on", {"on", "off"}, "append coordinate channels");
    std::string loss = a.get_choice("--loss", "gan", {"gan", "l1", "dssim"}, "adversarial + L1, or a plain loss (baseline)");
    std::string g_norm = a.get_choice("--g-norm", def.g_norm, {"batch", "none"}, "normalisation in the pix2pix U-Net (docs/gan.md)");
    std::string arch = a.get_choice("--arch", "pix2pix", {"pix2pix", "deepshading"}, "generator: pix2pix U-Net, or Deep Shading's U-Net (mean-pool down, bilinear up)");
    std::string residual = a.get_choice("--residual", def.residual, {"off", "mapped", "linear"}, "predict a correction to the input light: none (pix2pix), in Tanh range, or the indirect light in linear light (docs/gan.md)");
    std::string precision = a.get_choice("--precision", "fp32", {"fp32", "bf16"}, "GEMM/convolution inputs: fp32, or bf16 with fp32 sums, master weights, Adam and BatchNorm (docs/gan.md)");
    int threads = a.get_int("--threads", 2, "worker threads", 1, 256);
    int accumulate = a.get_int("--accumulate", 1, "samples per optimizer step, their gradients averaged in a fixed order "
                               "(BatchNorm per image); under mpirun spread over the ranks, so at least the rank count", 1, 65536);
    double bucket_mb = a.get_double("--bucket-mb", 25, "MiB per gradient bucket sent between MPI ranks during backward "
                                    "(0: one bucket, sent after backward)", 0, 1e6);
    int seed = a.get_int("--seed", 1, "random seed (weights, dropout, data order, augmentation)", 0, INT_MAX);
    bool aug_mirror = a.get_flag("--aug-mirror", "augmentation: each sample mirrored left-right with probability 1/2 "
                                 "(surround: the mirrored cube; normals' x negated; needs an even face size)");
    double aug_exposure = a.get_double("--aug-exposure", 1, "augmentation: all light inputs and the target times one "
                                       "factor per sample, log-uniform in [1/F, F] (1: off)", 1, 100);
    double aug_tint = a.get_double("--aug-tint", 1, "augmentation: light per colour channel times a factor log-uniform "
                                   "in [1/T, T], rescaled to luminance 1 (1: off)", 1, 100);
    bool resume = a.get_flag("--resume", "continue from OUT/checkpoint.blob");
    int max_frames = a.get_int("--max-frames", 0, "use at most N train and N test items (0: all)", 0, INT_MAX);
    int sample_every = a.get_int("--sample-every", 250, "write sample PNGs every N steps (0: never)", 0, INT_MAX);
    bool no_eval = a.get_flag("--no-eval", "skip the evaluation on the test split");
    double subset = a.get_double("--train-subset", 1.0, "train on about this share of the training scenes (whole "
                                 "scenes, picked by a hash of their names: data-size curves)", 0.001, 1.0);
    std::string stream = a.get_choice("--stream", "auto", {"auto", "on", "off"},
                                      "read training frames from disk as they are needed (auto: when they would take "
                                      "more than --memory-budget); same numbers either way");
    double budget_gib = a.get_double("--memory-budget", 2.0, "GiB of training frames held in memory before --stream auto streams", 0, 1e6);
    double val_fraction = a.get_double("--validation-fraction", 0.15,
                                       "share of train/'s scenes held out as the validation split (model selection: "
                                       "eval-gi --split validation); 0: none", 0, 0.9);
    std::string test_bn = a.get_choice("--test-bn", "batch", {"batch", "running"}, "BatchNorm statistics at test time");
    std::string test_dropout = a.get_choice("--test-dropout", "off", {"on", "off"}, "dropout at test time");
    int poison = a.get_int("--debug-poison-step", -1, "testing only: a NaN enters the input at this step", -1, INT_MAX);
    int stop_after = a.get_int("--debug-stop-after-epochs", -1, "testing only: stop after N epochs as if interrupted", -1, INT_MAX);
    if (dssim_weight < 0 && dssim_weight != -1) a.error("--dssim-weight must be >= 0");
    if (dssim_weight == -1) dssim_weight = loss == "gan" ? def.dssim_weight : 0;  // --loss l1 stays L1 alone
    if (decay < 0) decay = epochs / 2;
    if (decay > epochs) a.error("--decay-epochs must be <= --epochs");
    if (accumulate < dist::size())
      a.error("--accumulate must be at least the number of MPI ranks (" + std::to_string(dist::size()) + ")");
    a.done();
    set_num_threads(threads);

    if (data_dir.empty()) data_dir = dist::rank0_first([&] { return data::ensure_default_dataset("surround", threads); });
    data::require_valid_dataset(data_dir, data::Purpose::gi);
    auto listing = data::list_dataset(data_dir);
    if (listing.flat) listing = data::split_flat_by_scene(listing, 0.2);
    if (listing.train.size() == 0) throw std::runtime_error(data_dir + ": no training views or frames");
    // Whole scenes, before anything is fitted: the normalisation never sees validation.
    const auto [train_all, val_listing] = data::hold_out_validation(listing.train, val_fraction);
    // A subset for data-size curves: the scenes hold_out_validation would move, i.e. the
    // same hash order, so a smaller subset is contained in a larger one.
    const data::SplitListing train_listing = subset < 1 ? data::hold_out_validation(train_all, subset).second : train_all;
    const size_t max_items = max_frames > 0 ? size_t(max_frames) : size_t(-1);

    GanRunOptions o;
    o.out = out;
    o.resume = resume;
    o.sample_every = sample_every;
    o.poison_step = poison;
    o.stop_after_epochs = stop_after;
    o.precision = parse_precision(precision);
    if (o.precision == Precision::bf16) std::fprintf(stderr, "train-gan: bf16 GEMMs on %s\n", bf16_isa_description().c_str());
    o.accumulate = accumulate;
    o.augment = {aug_mirror, aug_exposure, aug_tint};
    o.bucket_mb = bucket_mb;
    o.quiet = !dist::writer();
    o.data_identity = std::filesystem::weakly_canonical(data_dir).string() + " (" +
                      std::to_string(train_listing.size()) + " train, " + std::to_string(val_listing.size()) +
                      " validation, " + std::to_string(listing.test.size()) + " test)";
    GanTrainConfig& c = o.train;
    c.inputs.mode = parse_mode(mode);
    c.inputs.coordconv = coordconv == "on";
    c.inputs.size = size;
    c.inputs.validation_fraction = val_listing.size() > 0 ? val_fraction : 0;
    c.ngf = ngf, c.ndf = ndf, c.levels = levels, c.d_layers = d_layers;
    c.loss = parse_loss(loss);
    c.arch = parse_arch(arch);
    c.residual = parse_residual(residual);
    c.g_batchnorm = g_norm == "batch";
    c.lambda = lambda, c.lr = lr, c.lr_d = lr_d, c.beta1 = beta1, c.dssim_weight = dssim_weight;
    c.epochs = epochs - decay, c.epochs_decay = decay;
    c.seed = uint64_t(seed);

    GiItemReader rd{c.inputs.mode, size};
    c.inputs.norm = fit_normalisation(train_listing, rd, max_items);
    const size_t n_train = std::min(max_items, split_items(train_listing, rd.mode));
    if (n_train == 0) throw std::runtime_error(data_dir + ": no training samples for --mode " + mode);
    const GiSample first = load_sample(train_listing, rd, c.inputs, 0);
    if (aug_mirror) (void)mirrored(first);  // refuses an odd face size before the first step
    const double gib = double(sample_bytes(first)) * double(n_train) / double(1 << 30);
    const bool streamed = stream == "on" || (stream == "auto" && gib > budget_gib);
    GiTrainData train = streamed ? GiTrainData(train_listing, rd, c.inputs, n_train)
                                 : GiTrainData(load_samples(train_listing, rd, c.inputs, max_items, "loading train"));
    if (dist::writer())
      std::fprintf(stderr, "train-gan: %zu training %s (%zu more in validation scenes) from %s, input %s, depth_max %.3g, "
                 "hdr_scale %.3g, light_max %.3g; %.2f GiB of samples, %s\n",
                 n_train, c.inputs.mode == GiMode::surround ? "frames" : "views", val_listing.size(), data_dir.c_str(),
                 first.input.shape().str().c_str(), c.inputs.norm.depth_max, c.inputs.norm.hdr_scale,
                 c.inputs.norm.light_max, gib, streamed ? "streamed from disk" : "held in memory");

    GanRunResult r = run_gan_training(o, train);
    train = GiTrainData({});  // the evaluation loads its own frames
    if (dist::writer() && r.d_wins_windows > 0)
      std::fprintf(stderr, "train-gan: the discriminator won outright in %lld windows of %d steps (first at step %lld)\n",
                   (long long)r.d_wins_windows, DiscriminatorWatch::kWindow, (long long)r.first_d_wins_step);
    if (!r.finished) return 3;  // the run layer's non-finite stop
    if (!dist::writer()) return 0;  // rank 0 reports and evaluates
    std::printf("train-gan: %d epochs, %lld steps in %s; generator %s/G.blob\n", r.epochs_done,
                (long long)r.steps, Progress::format_seconds(r.seconds).c_str(), out.c_str());
    if (no_eval || listing.test.size() == 0) return 0;

    // The test split, and the held-out families when the data has them (eval-ao's layout).
    EvalOptions e;
    e.data = data_dir;
    e.out = out + "/eval";
    e.models = {out + "/G.blob"};
    e.bn_batch_stats = test_bn == "batch";
    e.dropout_on = test_dropout == "on";
    e.max_frames = max_items;
    evaluate_gi(e);
    std::printf("train-gan: training %s/report.html; evaluation %s/report.html, chart %s/speed_vs_ssim.png "
                "(report.md, results.csv, previews/ beside them)\n", out.c_str(), e.out.c_str(), e.out.c_str());
    if (listing.has_holdout) {
      e.split = "holdout";
      e.out = out + "/eval/holdout";
      evaluate_gi(e);
      std::printf("train-gan: held-out families %s/report.html, chart %s/speed_vs_ssim.png\n", e.out.c_str(),
                  e.out.c_str());
    }
    return 0;
  }));
}
