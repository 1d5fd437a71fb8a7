// render-dataset: renders a G-buffer dataset with ray-traced ground truth
// (docs/renderer.md, docs/dataset-format.md).
//
//   render-dataset --out data/nnao --preset nnao --views 80
//   render-dataset --out data/gi --preset surround --size 64x64 --views 200 --path-frames 10
//   render-dataset --out data/mine --preset gi --scene a.obj --scene b.gltf
//   render-dataset --out data/v2 --preset nnao-v2 --views 400 --holdout-families cave,arcade
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "apps/args.h"
#include "core/folder_lock.h"
#include "core/thread_pool.h"
#include "data/exr_header_check.h"
#include "render/dataset_writer.h"
#include "render/scenes/families.h"
#include "runs/distributed/world.h"

using namespace nns;

namespace {
// The side the dataset readers take (a larger view could not be read back).
constexpr int kMaxSide = int(data::ExrHeaderLimits{}.max_side);

bool parse_size(const std::string& s, int& w, int& h) {
  auto x = s.find('x');
  if (x == std::string::npos) return false;
  try {
    size_t a, b;
    w = std::stoi(s.substr(0, x), &a);
    h = std::stoi(s.substr(x + 1), &b);
    return a == x && b == s.size() - x - 1 && w > 0 && h > 0;
  } catch (...) {
    return false;
  }
}
}  // namespace

// What the command line asks for: the dataset job, the threads, and whether an earlier
// render in --out is replaced.
struct Command {
  render::DatasetJob job;
  int threads = 2;
  bool replace = false;
};

Command read_flags(apps::Args& args) {
  std::string families_help =
      "procedural scene families (default: surround-v4 and v5 all, surround-v3 generations 1-3, nnao-v2 and "
      "surround-v2 generations 1-2, other presets the first eight; generation 3 is corridor, courtyard, multiroom, "
      "generation 4 cloister, basilica: ";
  for (auto& f : render::scene_families())
    families_help += f.name + (&f == &render::scene_families().back() ? ")" : ", ");
  Command c;
  render::DatasetJob& job = c.job;
  job.out = args.get_path("--out", "", "output dataset folder (required)");
  job.preset = args.get_choice(
      "--preset", "nnao",
      {"nnao", "nnao-v2", "gi", "surround", "surround-v2", "surround-v3", "surround-v4", "surround-v5"},
      "channels: nnao = Z N albedo AO; nnao-v2 = nnao over all families with per-view fov, "
      "aspect, size, AO radius and pitch varied; gi = + direct emission env indirect; "
      "surround = gi as cube frames; surround-v2 = surround over generations 1-2, albedos, lights, sun "
      "and extra lamps varied per scene, pitch widened; surround-v3 = surround-v2 plus the third generation "
      "(corridor, courtyard, multiroom); surround-v4 = surround-v3 plus the fourth generation (cloister, basilica) "
      "and procedural albedo textures on most materials; surround-v5 = surround-v4's frames "
      "rendered faster: fewer AO and env rays on the side faces (--side-spp)");
  job.views = args.get_int("--views", 80, "views (surround: frames) over train + test", 1, 1000000);
  std::string size = args.get_string(
      "--size", "",
      "image size WxH, each side 1 to " + std::to_string(kMaxSide) +
          " (default 320x180; gi 256x144; surround 64x64 faces; nnao-v2: 0.6-1.0 x its pixels, aspect varied)");
  job.settings.ao_spp = args.get_int("--spp", 256, "AO rays per pixel", 1, 65536);
  job.settings.gi_spp = args.get_int("--gi-spp", 128, "env/indirect paths per pixel", 1, 65536);
  job.train_gi_spp = args.get_int("--train-gi-spp", 0,
                                  "env/indirect paths per pixel on train/ alone (0: --gi-spp): noisier training "
                                  "targets than the test/ and holdout/ references",
                                  0, 65536);
  job.settings.side_spp = args.get_int("--side-spp", 0,
                                       "AO and env rays per pixel on the five side faces of a surround frame (0: the "
                                       "preset's: surround-v5 64 x 64 / face size, 8 to 64; the others --spp and "
                                       "min(--gi-spp, 64))",
                                       0, 65536);
  job.settings.ao = !args.get_flag("--no-ao",
                                   "lit presets: write no AO channel and trace no AO rays (the GI networks never "
                                   "read it; every other channel is the same bits)");
  job.settings.bounces = args.get_int("--bounces", 3, "indirect bounces (>= 2 for GI targets)", 1, 64);
  job.settings.seed = uint64_t(args.get_int("--seed", 1, "seed: scenes, cameras and noise", 0, INT_MAX));
  int noise_seed = args.get_int(
      "--noise-seed", -1,
      "seed of the Monte-Carlo noise alone (-1: --seed): the same scenes and cameras with independent noise", -1,
      INT_MAX);
  job.noise_seed = noise_seed;
  c.threads = args.get_int("--threads", 2, "worker threads", 1, 256);
  job.scene_files = args.get_list("--scene", "an OBJ or glTF scene file instead of the procedural families");
  job.families = args.get_names("--families", "", families_help);
  job.holdout_families =
      args.get_names("--holdout-families", "", "families rendered only into holdout/ (leave-families-out)");
  job.holdout_fraction =
      args.get_double("--holdout-fraction", 0.2, "share of views in holdout/ (with --holdout-families)", 0.01, 0.9);
  job.path_frames =
      args.get_int("--path-frames", 1, "> 1: views come as smooth camera paths of this many frames", 1, 10000);
  job.views_per_scene = args.get_int("--views-per-scene", 4, "views rendered in one scene before the next", 1, 1000000);
  job.test_fraction = args.get_double("--test-fraction", 0.2, "share of views from held-out scenes (test/)", 0, 0.95);
  job.fov_y_deg = float(args.get_double(
      "--fov", 60, "vertical field of view in degrees (not surround; nnao-v2 draws one per view)", 1, 179));
  c.replace = args.get_flag(
      "--replace", "remove the views of an earlier render in --out first (without it such a folder is refused)");
  args.done();
  if (job.out.empty()) args.error("--out is required"), args.done();

  const bool surround = render::is_surround_preset(job.preset);
  int w = job.preset == "gi" ? 256 : surround ? 64 : 320;
  int h = job.preset == "gi" ? 144 : surround ? 64 : 180;
  if (!size.empty() && !parse_size(size, w, h)) args.error("--size: expected WxH, got '" + size + "'");
  else if (w > kMaxSide || h > kMaxSide)  // 65536x65536 died in std::bad_alloc naming nothing
    args.error("--size: " + size + " is out of range: each side at most " + std::to_string(kMaxSide) + " pixels");
  if (surround && w != h) args.error("--size: surround faces are square, got " + size);
  if (!job.settings.ao && render::is_ao_preset(job.preset))
    args.error("--no-ao: preset " + job.preset + " renders AO alone (its target)");
  args.done();
  job.width = w, job.height = h;
  return c;
}

// The one line that sums up a render: views, scenes, time, ray throughput.
void print_summary(const render::DatasetJob& job, const render::DatasetReport& r) {
  const bool surround = render::is_surround_preset(job.preset);
  int n = std::max(1, r.train_views + r.test_views + r.holdout_views);
  std::string held = r.holdout_views ? " + " + std::to_string(r.holdout_views) + " holdout" : "";
  std::string held_scenes = r.holdout_views ? " + " + std::to_string(r.holdout_scenes.size()) : "";
  std::printf(
      "%s: %d train + %d test%s %s (%zu + %zu%s scenes), %.1f s; per %s %.2f s wall, %.2f CPU-s; "
      "%.2f Mrays/s wall, %.2f Mrays per CPU-s\n",
      job.out.c_str(), r.train_views, r.test_views, held.c_str(), surround ? "frames" : "views", r.train_scenes.size(),
      r.test_scenes.size(), held_scenes.c_str(), r.total_seconds, surround ? "frame" : "view", r.render_seconds / n,
      r.cpu_seconds / n, r.render_seconds > 0 ? r.rays / r.render_seconds * 1e-6 : 0.0,
      r.cpu_seconds > 0 ? r.rays / r.cpu_seconds * 1e-6 : 0.0);
}

int main(int argc, char** argv) {
  // mpirun -np N: view i is rendered by rank i % N, the dataset is the one-process one.
  runs::Session mpi(argc, argv);
  apps::Args args(argc, argv, "render-dataset", "Render a G-buffer dataset with Embree ground truth.");
  Command c = read_flags(args);
  render::DatasetJob& job = c.job;
  const int threads = c.threads;

  job.part = runs::rank(), job.parts = runs::size();
  job.progress = runs::writer();
  return mpi.finish(apps::run_main("render-dataset", [&] {
    render::check_dataset_job(job);  // a refused job makes no folder
    // Rank 0 locks and checks the folder before any rank writes a view into it.
    FolderLock lock;
    if (runs::writer()) {
      lock = prepare_output_folder(job.out, "render-dataset");
      render::prepare_render_folder(job.out, c.replace);
    }
    runs::barrier();
    set_num_threads(threads);
    render::DatasetReport r;
    try {
      r = render::render_dataset(job);
    } catch (...) {
      // A render cut short is no dataset. The folder held no other render's views
      // (prepare_render_folder), so its views and metadata.txt are this run's; the lock
      // then removes the folder itself if this run made it (core/folder_lock.h).
      if (runs::writer()) (void)render::remove_render(job.out);
      throw;
    }
    std::vector<double> sums = {double(r.train_views), double(r.test_views), double(r.holdout_views),
                                double(r.rays),        r.render_seconds,     r.cpu_seconds};
    runs::sum_over_ranks(sums);  // the report counts every rank's views
    r.train_views = int(sums[0]), r.test_views = int(sums[1]), r.holdout_views = int(sums[2]);
    r.rays = uint64_t(sums[3]), r.render_seconds = sums[4], r.cpu_seconds = sums[5];
    if (!runs::writer()) return 0;
    print_summary(job, r);
    return 0;
  }));
}
