// eval-ao: every AO method at every sample count on every view of a dataset, timed
// and scored against the ray-traced AO — the paper's Table 1 and Figure 4 for this data.
//
//   eval-ao --data DIR --model nnao.blob --out DIR [--methods NNAO,SSAO,...] [--threads 2]
//   eval-ao --data DIR --ladder LADDER --out DIR   (every rung of train-nnao --ladder as one curve)
//
// DIR is a split folder or a flat folder; a dataset root with train/ + test/ means its
// test/ split, and its holdout/ split (whole families never trained on) goes to OUT/holdout
// with the same files. Writes results.csv, results_by_scene.csv, failure_bands.csv,
// temporal.csv, timing.csv, pareto.csv, speed_vs_accuracy.svg/.png, previews/, report.md and report.html.
// Temporal stability is measured on camera-path frames (files "<scene>-pNN-fNNN.exr", or
// surround frame folders of that name, as render-dataset --path-frames writes them),
// reprojected: classical_ao/temporal.h.
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "apps/args.h"
#include "core/folder_lock.h"
#include "core/staged_output.h"
#include "core/thread_pool.h"
#include "data/dataset.h"
#include "render/default_dataset.h"
#include "runs/ao/eval_ao.h"

using namespace nns;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  return apps::run_main("eval-ao", [&]() -> int {
    apps::Args args(argc, argv, "eval-ao",
                    "Time and score NNAO and the classical SSAO methods against ground-truth AO.");
    runs::EvalAoOptions o;
    std::string data_dir = args.get_string(
        "--data", "",
        "dataset: a split folder, a flat folder, or a root with test/ (default: the built-in default nnao dataset)");
    std::string model =
        args.get_string("--model", "", "nnao.blob from train-nnao (omit to run only the classical methods)");
    o.ladder = args.get_string("--ladder", "",
                               "a trained NNAO ladder's folder (train-nnao --ladder): every rung as NNAO-exact, drawn "
                               "as one curve (instead of --model)");
    std::string out = args.get_path("--out", "eval-out", "output folder");
    std::string methods_flag;
    for (const std::string& m : args.get_names("--methods", "NNAO-exact,NNAO,SSAO,SSAO+,HBAO,Alchemy,GTAO", "methods"))
      methods_flag += (methods_flag.empty() ? "" : ",") + m;
    std::vector<int> nnao_samples =
        args.get_int_list("--nnao-samples", "16,32,64,128,256", "shader-style NNAO sample counts", 1, INT_MAX);
    int threads = args.get_int("--threads", 2, "worker threads", 1, 256);
    int previews = args.get_int("--previews", 3, "views to write preview PNGs for", 0, 100000);
    int max_views = args.get_int("--max-views", 0, "evaluate at most this many views (0 = all)", 0, INT_MAX);
    int repeat =
        args.get_int("--repeat", 3, "time each method this many times per view and keep the fastest (>= 1)", 1, 1000);
    std::string params_file = args.get_string(
        "--classical-params", "", "parameter file from tune-classical-ao (default: the built-in parameters)");
    const std::string split = args.get_choice(
        "--split", "both", {"test", "holdout", "both"},
        "both: the test split into OUT and, if the data has one, the held-out families into OUT/holdout");
    o.temporal_blend =
        args.get_double("--temporal-blend", 0,
                        "> 0: also score every method with temporal accumulation ('<method>+TA': out = a * this frame "
                        "+ (1 - a) * the previous output reprojected, on camera paths); a = this value",
                        0, 1);
    o.vary_pattern = args.get_flag("--vary-pattern",
                                   "shader-style NNAO: a jitter pattern per camera-path frame (for --temporal-blend to "
                                   "average), instead of one fixed pattern");
    bool scalar = args.get_flag(
        "--scalar",
        "run the scalar per-pixel reference loops instead of the vectorised ones (to measure the speed-up)");
    args.done();
    set_num_threads(threads);
    if (data_dir.empty()) data_dir = render::ensure_default_dataset("nnao", threads);
    o.data_dir = data_dir, o.model = model, o.out = out, o.methods = methods_flag, o.nnao_samples = nnao_samples;
    o.threads = threads, o.previews = previews, o.max_views = max_views, o.repeat = repeat;
    o.params_file = params_file, o.scalar = scalar;
    const bool has_holdout = data::list_dataset(data_dir).has_holdout;
    FolderLock lock = prepare_output_folder(out, "eval-ao");        // OUT/holdout is inside it
    StagedOutput stage(out);                                        // nothing appears in OUT unless all of it does
    std::vector<std::pair<std::string, runs::ChartNotes>> written;  // folder under OUT, its charts' notes
    o.out = stage.dir();
    if (split != "holdout") written.emplace_back("", runs::evaluate_ao(o));
    if (split == "holdout" || (split == "both" && has_holdout)) {
      o.split = "holdout";
      const std::string sub = split == "both" ? "holdout" : "";
      o.out = (fs::path(stage.dir()) / sub).string();
      written.emplace_back(sub, runs::evaluate_ao(o));
    }
    stage.commit();
    for (const auto& [sub, notes] : written) {
      const fs::path dir = fs::path(out) / sub;
      std::printf("chart: %s%s\nreport: %s (and report.md)\n", (dir / "speed_vs_accuracy.svg").string().c_str(),
                  notes.accuracy.empty() ? " (+ .png)" : "", (dir / "report.html").string().c_str());
    }
    return 0;
  });
}
