// train-gan: learn screen-space global illumination from G-buffers with pix2pix's U-Net
// generator, trained on its reconstruction loss or as a conditional GAN with a PatchGAN
// discriminator, front-only (Deep Illumination) or surround-aware (the thesis's global
// view). See docs/gan.md.
//
//   train-gan                                  default surround data, default model
//   train-gan --data DIR --mode front --out runs/front
//   train-gan --loss gan                       pix2pix's adversarial training (PatchGAN)
//   train-gan --loss dssim --arch deepshading  Deep Shading's U-Net and loss
//   train-gan --out runs/x --resume            continue exactly where runs/x stopped
//   train-gan --aug-mirror --aug-exposure 1.4 --aug-tint 1.15   augmented samples (docs/gan.md)
//   mpirun -np 2 train-gan --accumulate 4      data-parallel: the weights of one process
//                                              with --accumulate 4 (docs/distributed.md)
#include <cstdio>
#include <string>

#include "apps/args.h"
#include "core/thread_pool.h"
#include "render/default_dataset.h"
#include "runs/distributed/world.h"
#include "runs/gi/train_gan.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::runs;

std::string on(bool b) { return b ? "on" : "off"; }

// The generator's and the discriminator's shape and loss.
void read_model_flags(apps::Args& a, TrainGanOptions& o) {
  o.size = a.get_int("--size", o.size,
                     "face size the views are box-filtered to (0: as stored; sides divisible by "
                     "2^levels)",
                     0, 4096);
  if (o.size > 0 && o.size < 4) a.error("--size must be 0 (as stored) or in [4, 4096]");
  o.ngf = a.get_int("--ngf", o.ngf, "generator base width", 1, 1024);
  o.ndf = a.get_int("--ndf", o.ndf, "discriminator base width (--loss gan)", 1, 1024);
  o.levels = a.get_int("--levels", o.levels, "U-Net levels (input size divisible by 2^levels)", 1, 12);
  o.d_layers = a.get_int("--d-layers", o.d_layers, "PatchGAN layers (3: 70x70 patches; --loss gan)", 1, 10);
  o.coordconv = a.get_choice("--coordconv", on(o.coordconv), {"on", "off"}, "append coordinate channels") == "on";
  o.loss = a.get_choice("--loss", o.loss, {"gan", "l1", "dssim"},
                        "l1: the reconstruction term (L1 + DSSIM + gradient terms) alone; gan: adversarial + "
                        "lambda x it (PatchGAN); dssim: DSSIM alone");
  o.g_norm = a.get_choice("--g-norm", o.g_norm, {"batch", "none"}, "normalisation in the pix2pix U-Net (docs/gan.md)");
  o.level_head = a.get_int("--level-head", o.level_head,
                           "hidden width of a frame-level head scaling the predicted indirect light (0: none; "
                           "pix2pix with --residual linear only)",
                           0, 4096);
  o.level_energy = a.get_choice("--level-energy", on(o.level_energy), {"on", "off"},
                                "the frame-level head also reads the view's light energy") == "on";
  o.g_dropout =
      a.get_double("--g-dropout", o.g_dropout,
                   "dropout probability in the U-Net's three innermost up blocks (pix2pix: 0.5; 0: none)", 0, 0.95);
  o.arch = a.get_choice("--arch", o.arch, {"pix2pix", "deepshading"},
                        "generator: pix2pix U-Net, or Deep Shading's U-Net (mean-pool down, bilinear up)");
  o.residual = a.get_choice("--residual", o.residual, {"off", "mapped", "linear"},
                            "predict a correction to the input light: none (pix2pix), in Tanh range, or the indirect "
                            "light in linear light (docs/gan.md)");
}

// The optimisation: schedule, rates, precision, gradient exchange, augmentation.
void read_training_flags(apps::Args& a, TrainGanOptions& o) {
  o.epochs = a.get_int("--epochs", o.epochs, "epochs in all", 1, 100000);
  o.decay_epochs = a.get_int("--decay-epochs", o.decay_epochs,
                             "of which the last N decay the rate linearly to 0 (default: half)", -1, 100000);
  o.lambda = a.get_double("--lambda", o.lambda,
                          "weight of the reconstruction term against the adversarial one (--loss gan)", 0, HUGE_VAL);
  o.dssim_weight =
      a.get_double("--dssim-weight", o.dssim_weight,
                   "add this times DSSIM to the L1 term (default: 1 with --loss gan or l1; 0 is pix2pix's L1 alone)");
  o.gradient_weight = a.get_double("--gradient-weight", o.gradient_weight,
                                   "add this times the L1 of the images' finite differences (edges)", 0, HUGE_VAL);
  o.ema = a.get_double("--ema", o.ema,
                       "G.blob holds the moving average of G's weights with this decay, e.g. 0.999 (0: the last "
                       "step's weights)",
                       0, 0.999999);
  o.lr = a.get_double("--lr", o.lr, "Adam learning rate (-1, unset: 0.0005 with --loss l1, 0.0002 with gan or dssim)",
                      -1, 1e9);
  o.lr_d = a.get_double(
      "--lr-d", o.lr_d,
      "the discriminator's learning rate with --loss gan (0: --lr, as pix2pix; the default, a quarter of the "
      "GAN's --lr, won the validation split: docs/gan.md)",
      0, 1e9);
  o.beta1 =
      a.get_double("--beta1", o.beta1, "Adam beta1 (-1, unset: 0.9 with --loss l1, 0.5 with gan or dssim)", -1, 0.9999);
  o.precision = parse_precision(a.get_choice(
      "--precision", "auto", {"auto", "fp32", "bf16"},
      std::string("GEMM/convolution inputs: fp32, or bf16 with fp32 sums, master weights, Adam and BatchNorm; "
                  "auto: bf16 on an AMD CPU with AVX512-BF16, where it trains faster, else fp32 (here ") +
          precision_name(o.precision) + "; docs/gan.md)"));
  o.accumulate = a.get_int("--accumulate", runs::default_accumulate(o.accumulate),
                           "samples per optimizer step, their gradients averaged in a fixed order "
                           "(BatchNorm per image); under mpirun spread over the ranks, so at least the rank count",
                           1, 65536);
  o.bucket_mb = a.get_double("--bucket-mb", o.bucket_mb,
                             "MiB per gradient bucket sent between MPI ranks during backward "
                             "(0: one bucket, sent after backward)",
                             0, 1e6);
  o.seed = a.get_int("--seed", o.seed, "random seed (weights, dropout, data order, augmentation)", 0, INT_MAX);
  o.augment.mirror = a.get_flag("--aug-mirror",
                                "augmentation: each sample mirrored left-right with probability 1/2 "
                                "(surround: the mirrored cube; normals' x negated; needs an even face size)");
  o.augment.exposure = a.get_double("--aug-exposure", o.augment.exposure,
                                    "augmentation: all light inputs and the target times one "
                                    "factor per sample, log-uniform in [1/F, F] (1: off)",
                                    1, 100);
  o.augment.tint = a.get_double("--aug-tint", o.augment.tint,
                                "augmentation: light per colour channel times a factor log-uniform "
                                "in [1/T, T], rescaled to luminance 1 (1: off)",
                                1, 100);
  o.resume = a.get_flag("--resume", "continue from OUT/checkpoint.blob");
}

// Every flag over TrainGanOptions' initialisers, which are the defaults (runs/gi/train_gan.h).
TrainGanOptions read_flags(apps::Args& a, int& threads) {
  TrainGanOptions o;
  o.data_dir = a.get_string("--data", o.data_dir,
                            "dataset folder (default: the built-in surround data, rendered once and cached)");
  o.out = a.get_path("--out", o.out, "output folder");
  o.mode = a.get_choice("--mode", o.mode, {"front", "surround"}, "front view only, or the six-face global view");
  read_model_flags(a, o);
  read_training_flags(a, o);
  threads = a.get_int("--threads", 2, "worker threads", 1, 256);
  o.max_frames = a.get_int("--max-frames", o.max_frames, "use at most N train and N test items (0: all)", 0, INT_MAX);
  o.sample_every =
      a.get_int("--sample-every", o.sample_every, "write sample PNGs every N steps (0: never)", 0, INT_MAX);
  o.eval = !a.get_flag("--no-eval", "skip the evaluation on the test split");
  o.train_subset = a.get_double("--train-subset", o.train_subset,
                                "train on about this share of the training scenes (whole "
                                "scenes, picked by a hash of their names: data-size curves)",
                                0.001, 1.0);
  o.stream = a.get_choice("--stream", o.stream, {"auto", "on", "off"},
                          "read training frames from disk as they are needed (auto: "
                          "when they would take more than --memory-budget); same numbers either way");
  o.memory_budget_gib = a.get_double("--memory-budget", o.memory_budget_gib,
                                     "GiB of training frames held in memory before --stream auto streams "
                                     "(-1: half the memory available when the run starts)",
                                     -1, 1e6);
  o.validation_fraction = a.get_double("--validation-fraction", o.validation_fraction,
                                       "share of train/'s scenes held out as the "
                                       "validation split (model selection: eval-gi --split validation); 0: none",
                                       0, 0.9);
  o.test_bn_batch = a.get_choice("--test-bn", o.test_bn_batch ? "batch" : "running", {"batch", "running"},
                                 "BatchNorm statistics at test time") == "batch";
  o.test_dropout = a.get_choice("--test-dropout", on(o.test_dropout), {"on", "off"}, "dropout at test time") == "on";
  o.poison_step =
      a.get_int("--debug-poison-step", o.poison_step, "testing only: a NaN enters the input at this step", -1, INT_MAX);
  o.stop_after_epochs = a.get_int("--debug-stop-after-epochs", o.stop_after_epochs,
                                  "testing only: stop after N epochs as if interrupted", -1, INT_MAX);
  if (o.dssim_weight < 0 && o.dssim_weight != -1) a.error("--dssim-weight must be >= 0");
  if (o.lr <= 0 && o.lr != -1) a.error("--lr must be > 0");
  if (o.beta1 < 0 && o.beta1 != -1) a.error("--beta1 must be >= 0");
  if (o.decay_epochs > o.epochs) a.error("--decay-epochs must be <= --epochs");
  if (o.accumulate < runs::size())
    a.error("--accumulate must be at least the number of MPI ranks (" + std::to_string(runs::size()) + ")");
  a.done();

  return o;
}

int main(int argc, char** argv) {
  runs::Session mpi(argc, argv);
  return mpi.finish(apps::run_main("train-gan", [&] {
    apps::Args a(argc, argv, "train-gan",
                 "Train pix2pix's U-Net to predict diffuse global illumination: alone on L1 + DSSIM by default, "
                 "or as a GAN against a PatchGAN (--loss gan).");
    int threads = 2;
    TrainGanOptions o = read_flags(a, threads);
    runs::announce_accumulate("train-gan", o.accumulate);
    set_num_threads(threads);
    if (o.data_dir.empty())
      o.data_dir = runs::rank0_first([&] { return render::ensure_default_dataset("surround", threads); });
    return train_gan(o).exit_code;
  }));
}
