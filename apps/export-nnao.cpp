// export-nnao: a trained nnao.blob -> the engine's passes as GLSL fragment shaders
// (nnao.frag with the network embedded, nnao_blur.frag, a low-resolution model's
// nnao_downsample.frag and nnao_upsample.frag) and, for a grid model, the filter atlas
// texture the shader reads plus the four filter images (the paper's Figure 2)
// (runs/ao/nnao_export.h; docs/nnao.md, "The shader in an engine").
// With --ladder DIR --budget-ms X --size WxH it first picks the rung to ship: the most
// accurate rung of a trained ladder whose inference fits the budget on this machine
// (runs/ao/nnao_budget.h).
#include <cstdio>

#include "apps/args.h"
#include "core/folder_lock.h"
#include "core/staged_output.h"
#include "core/thread_pool.h"
#include "data/dataset.h"
#include "render/default_dataset.h"
#include "runs/ao/nnao_budget.h"
#include "runs/ao/nnao_export.h"

using namespace nns;

namespace {

// The rung of `ladder` to ship within the budget, its choice printed with every rung's
// time; "" when none fits.
std::string pick_from_ladder(const std::string& ladder, double budget_ms, int w, int h, std::string view_file,
                             int threads) {
  if (view_file.empty()) {
    const data::DatasetListing d = data::list_dataset(render::ensure_default_dataset("nnao", threads));
    view_file = d.test.views.empty() ? d.train.views.at(0) : d.test.views[0];
  }
  const data::View view = data::read_view(view_file);
  const auto timed = runs::time_ladder(ladder, view, w, h);
  const runs::TimedRung* pick = runs::pick_rung(timed, budget_ms);
  std::printf("rungs of %s timed at %dx%d on %s (%d thread%s; %s), budget %.3g ms:\n", ladder.c_str(), w, h,
              view_file.c_str(), threads, threads == 1 ? "" : "s", runs::cpu_model().c_str(), budget_ms);
  for (auto& t : timed)
    std::printf("  %-26s %8.3f ms%s\n", t.rung.name.c_str(), t.ms,
                &t == pick ? "  <- picked" : (t.ms > budget_ms ? "  (over budget)" : ""));
  return pick ? pick->rung.blob : "";
}

}  // namespace

int main(int argc, char** argv) {
  return apps::run_main("export-nnao", [&]() -> int {
    apps::Args args(argc, argv, "export-nnao",
                    "Export NNAO as GLSL passes (and a grid model's filter texture) for engines.");
    std::string model = args.get_string("--model", "", "nnao.blob from train-nnao");
    const std::string ladder =
        args.get_string("--ladder", "",
                        "instead of --model: a trained ladder (train-nnao --ladder); exports its highest (most "
                        "accurate) rung that fits --budget-ms at --size on this machine");
    const double budget = args.get_double(
        "--budget-ms", 0, "--ladder: the AO budget per frame in ms (timed here, on this machine's threads)", 1e-3, 1e6);
    const std::string size = args.get_string("--size", "1280x720", "--ladder: the frame size the budget is for, WxH");
    const std::string view = args.get_string(
        "--view", "", "--ladder: the view timed, resized to --size (default: the default dataset's first test view)");
    const int threads = args.get_int("--threads", 2, "--ladder: worker threads for the timing", 1, 256);
    std::string out = args.get_path("--out", "nnao-export", "output folder");
    int samples = args.get_int("--samples", 64, "grid models: the shader's default filter samples per pixel (uSamples)",
                               1, INT_MAX);
    int w = 0, h = 0;
    char tail = 0;
    if (std::sscanf(size.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 1 || h < 1 || w > 16384 || h > 16384)
      args.error("--size must be WxH with each side 1..16384, not '" + size + "'");
    if (model.empty() == ladder.empty()) args.error("give --model or --ladder (one of them)");
    if (!ladder.empty() && !(budget > 0)) args.error("--ladder needs --budget-ms");
    args.done();
    if (!ladder.empty()) {
      set_num_threads(threads);
      model = pick_from_ladder(ladder, budget, w, h, view, threads);
      if (model.empty()) {
        std::fprintf(stderr, "export-nnao: no rung of %s fits %.3g ms at %dx%d on this machine (times above)\n",
                     ladder.c_str(), budget, w, h);
        return 1;
      }
    }
    auto m = nnao::NnaoWeights::load(model);
    FolderLock lock = prepare_output_folder(out, "export-nnao");
    StagedOutput stage(out);  // the shaders of one model together, never beside an earlier export's
    std::string files;
    for (const std::string& f : runs::write_export(m, stage.dir(), samples)) files += (files.empty() ? "" : ", ") + f;
    stage.commit();
    std::printf("wrote %s into %s (%s)\n", files.c_str(), out.c_str(),
                m.input.is_horizon()
                    ? (std::to_string(m.input.samples()) + " depth samples per pixel, fixed by the model").c_str()
                    : ("default " + std::to_string(samples) + " filter samples per pixel").c_str());
    return 0;
  });
}
