// sweep-gan: "a model no more than a scene needs". Trains the GI GAN over a grid of
// face sizes x ngf x levels, scores each on the validation split (eval-gi's metrics), charts
// SSIM against ms per frame and against training time, and names the smallest model
// (fewest parameters) within 0.01 SSIM of the best. train-gan's defaults
// (runs/gi/train_gan.h) come from its answer; docs/gan.md has the table.
//
//   sweep-gan --out sweep --sizes 16,32 --ngf 8,16,32 --levels 4,5 --epochs 6
//   sweep-gan --out sweep --points 32:16:5,64:16:5     explicit points; finished ones are reused
#include <string>

#include "apps/args.h"
#include "core/folder_lock.h"
#include "core/thread_pool.h"
#include "data/require_valid_dataset.h"
#include "render/default_dataset.h"
#include "runs/gi/gan_sweep.h"
#include "runs/gi/train_gan.h"

using namespace nns;
using namespace nns::gi;
using namespace nns::runs;

int main(int argc, char** argv) {
  return apps::run_main("sweep-gan", [&] {
    apps::Args a(argc, argv, "sweep-gan", "Sweep GI GAN sizes; name the smallest model within 0.01 SSIM of the best.");
    std::string data_dir = a.get_string("--data", "", "dataset (default: the built-in surround data)");
    std::string out = a.get_path("--out", "sweep-gan-out", "output folder");
    std::string mode = a.get_choice("--mode", "surround", {"front", "surround"}, "input mode");
    auto sizes = a.get_int_list("--sizes", "16,32", "face sizes", 4, 4096);
    auto ngfs = a.get_int_list("--ngf", "8,16,32", "generator widths (ndf follows ngf)", 1, 1024);
    auto levels = a.get_int_list("--levels", "4,5", "U-Net levels", 1, 12);
    std::string points_s =
        a.get_string("--points", "", "explicit size:ngf:levels list instead of the grid, e.g. 32:16:5,64:16:5");
    int epochs = a.get_int("--epochs", 6, "epochs per model", 1, 100000);
    std::string loss = a.get_choice("--loss", "gan", {"gan", "l1", "dssim"}, "training loss of every point");
    std::string arch = a.get_choice("--arch", "pix2pix", {"pix2pix", "deepshading"}, "generator architecture");
    std::string residual = a.get_choice("--residual", TrainGanOptions{}.residual, {"off", "mapped", "linear"},
                                        "residual output (docs/gan.md)");
    int max_frames = a.get_int("--max-frames", 0, "at most N train and N test frames (0: all)", 0, INT_MAX);
    double tolerance = a.get_double("--ssim-tolerance", 0.01, "how far below the best SSIM still counts", 0, 1);
    int threads = a.get_int("--threads", 2, "worker threads", 1, 256);
    int seed = a.get_int("--seed", 1, "random seed", 0, INT_MAX);
    double val_fraction =
        a.get_double("--validation-fraction", 0.15, "share of train/'s scenes every point is scored on", 0.01, 0.9);
    a.done();
    set_num_threads(threads);
    if (data_dir.empty()) data_dir = render::ensure_default_dataset("surround", threads);
    data::require_valid_dataset(data_dir, data::Purpose::gi);
    FolderLock lock = prepare_output_folder(out, "sweep-gan");
    run_gan_sweep({data_dir, out, mode, points_s, loss, arch, residual, sizes, ngfs, levels, epochs, max_frames,
                   threads, seed, tolerance, val_fraction});
    return 0;
  });
}
