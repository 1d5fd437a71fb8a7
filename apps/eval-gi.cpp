// eval-gi: score GI generators and the two non-learned references (direct + env, and
// that plus a constant ambient fitted on the training split) on a dataset's test split.
//
//   eval-gi --data DIR --model runs/surround/G.blob --model runs/front/G.blob --out eval
//   eval-gi --data DIR128 --model g64/G.blob --size 128 --upsample-from 64   a face-64 model at face 128
// writes eval/results.csv (model,mode,ms_per_frame,mse,psnr,ssim,...,flip,grad_error),
// results_offscreen.csv, results_by_family.csv, results_by_distance.csv (error by distance to
// the nearest depth jump or crease), frames.csv, report.md, report.html and previews/.
// See docs/gan.md.
#include <cstdio>

#include "apps/args.h"
#include "core/folder_lock.h"
#include "core/staged_output.h"
#include "core/thread_pool.h"
#include "runs/gi/eval_gi.h"

using namespace nns;

int main(int argc, char** argv) {
  return apps::run_main("eval-gi", [&] {
    apps::Args a(argc, argv, "eval-gi", "Evaluate GI generators against ray-traced ground truth.");
    runs::EvalOptions o;
    o.data =
        a.get_string("--data", "", "dataset folder (its test split is scored, its train split fits the ambient term)");
    o.models = a.get_list("--model", "a generator blob (G.blob) from train-gan");
    o.out = a.get_path("--out", "eval-gi-out", "output folder");
    o.split = a.get_choice("--split", "test", {"test", "validation", "holdout", "train"},
                           "frames scored: test/, the validation scenes train-gan carved from train/, holdout/, or "
                           "the scenes it trained on (the fitting error)");
    std::string bn = a.get_choice("--test-bn", "batch", {"batch", "running"}, "BatchNorm statistics at test time");
    std::string drop = a.get_choice("--test-dropout", "off", {"on", "off"}, "dropout at test time");
    int max_frames = a.get_int("--max-frames", 0, "score at most N test frames (0: all)", 0, INT_MAX);
    o.previews = a.get_int("--previews", 3, "frames with preview PNGs per model", 0, 100000);
    int threads = a.get_int("--threads", 2, "worker threads", 1, 256);
    o.offscreen_share = float(a.get_double(
        "--offscreen-share", 1.0 / 6,
        "a frame is off-screen-lit when its front face holds less than this share of its direct light", 0, 1));
    o.size = a.get_int("--size", 0,
                       "score at this face size, the views box-filtered to it (0: each model at the face it "
                       "was trained at); a model trained at another size runs fully convolutionally",
                       0, 16384);
    o.upsample_from = a.get_int("--upsample-from", 0,
                                "run each model at this face size and bring its indirect light up "
                                "to the scored size with an upsample guided by depth and normals (0: off)",
                                0, 16384);
    o.mirror_average = a.get_flag("--mirror-average",
                                  "average each model's light with its light for the mirrored frame, mirrored back "
                                  "(test-time augmentation: twice the time; surround needs an even face size)");
    o.second_render = a.get_path("--second-render", "",
                                 "another render of the scored frames with independent noise (render-dataset "
                                 "--noise-seed): scored as rows 'another render' (the noise floor) and, with "
                                 "--upsample-from, 'another render @L guided' (docs/gan.md)");
    o.best_gain = a.get_flag("--best-gain",
                             "a diagnostic row per model: its indirect light times the per-frame, per-channel gain "
                             "that fits the truth best; what it still gets wrong is the light's shape, not its level");
    if (o.upsample_from > 0 && o.size == 0)
      a.error("--upsample-from needs --size (the face the light is brought up to)");
    if (o.upsample_from > 0 && o.size > 0 && (o.upsample_from >= o.size || o.size % o.upsample_from))
      a.error("--upsample-from must be a proper divisor of --size (" + std::to_string(o.size) + ")");
    if (o.data.empty()) a.error("--data is required");
    if (o.models.empty()) a.error("at least one --model is required");
    a.done();
    o.bn_batch_stats = bn == "batch";
    o.dropout_on = drop == "on";
    if (max_frames > 0) o.max_frames = size_t(max_frames);
    set_num_threads(threads);
    FolderLock lock = prepare_output_folder(o.out, "eval-gi");
    const std::string out = o.out;
    StagedOutput stage(out);  // nothing appears in OUT unless all of it does
    o.out = stage.dir();
    auto rows = runs::evaluate_gi(o);
    stage.commit();
    std::printf("%s", runs::results_csv(rows, false).c_str());
    std::printf("eval-gi: report %s/report.html (and report.md)\n", out.c_str());
    return 0;
  });
}
