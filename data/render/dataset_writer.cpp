#include "data/render/dataset_writer.h"

#include <chrono>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include "core/progress.h"
#include "data/exr_io.h"
#include "data/render/placement.h"
#include "data/render/render_view.h"
#include "data/render/surround.h"
#include "data/scenes/families.h"
#include "data/scenes/mesh_loader.h"

namespace nns::data {

namespace fs = std::filesystem;

void apply_preset(DatasetJob& job) {
  RenderSettings& s = job.settings;
  if (job.preset == "nnao") {
    s.ao = true, s.lighting = false;
  } else if (job.preset == "gi" || job.preset == "surround") {
    s.ao = true, s.lighting = true, s.indirect = true;
  } else {
    throw std::invalid_argument("unknown preset '" + job.preset + "' (nnao, gi, surround)");
  }
}

namespace {
// One scene to render `views` views (or frames) of, into `split`.
struct SceneTask {
  std::string split;        // "train" or "test"
  std::string family;       // procedural family, or empty for a file
  int instance = 0;
  std::string file;
  int views = 0;
};

uint64_t hash_name(const std::string& s) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (char c : s) h = (h ^ uint64_t(uint8_t(c))) * 0x100000001B3ull;
  return h;
}

std::string zero_padded(int i, int width) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%0*d", width, i);
  return buf;
}

// Splits `total` views over scenes of about `per_scene` views each (whole paths of
// `path` frames), drawn round-robin from the families (instances counted from
// `first_instance`) or from the files (one task per file). Every family gets a scene
// when there are at least as many paths as families, so both splits cover every family.
void add_tasks(std::vector<SceneTask>& tasks, const std::string& split, int total, int per_scene, int path,
               const std::vector<std::string>& families, const std::vector<std::string>& files, int first_instance) {
  int paths = (total + path - 1) / path;
  if (paths == 0) return;
  int sources = int(files.empty() ? families.size() : files.size());
  int scenes = std::max(1, (paths * path + per_scene - 1) / per_scene);
  if (paths >= sources) scenes = std::max(scenes, sources);
  if (!files.empty()) scenes = sources;  // a file is one scene: its views in one task, names unique
  scenes = std::min(scenes, paths);
  for (int k = 0; k < scenes; ++k) {
    SceneTask t;
    t.split = split;
    int my_paths = paths / scenes + (k < paths % scenes ? 1 : 0);
    t.views = std::min(my_paths * path, total);
    total -= t.views;
    if (!files.empty()) {
      t.file = files[size_t(k) % files.size()];
    } else {
      t.family = families[size_t(k) % families.size()];
      t.instance = first_instance + k / int(families.size());
    }
    if (t.views > 0) tasks.push_back(t);
  }
}
}  // namespace

DatasetReport render_dataset(DatasetJob job) {
  auto t0 = std::chrono::steady_clock::now();
  std::clock_t c0 = std::clock();
  apply_preset(job);
  if (job.views < 1) throw std::invalid_argument("render_dataset: --views must be >= 1");
  if (job.width < 8 || job.height < 8) throw std::invalid_argument("render_dataset: image size below 8x8");
  const bool surround = job.preset == "surround";
  const int P = std::max(1, job.path_frames);
  int per_scene = std::max(job.views_per_scene, P);

  std::vector<std::string> families = job.families;
  if (families.empty())
    for (auto& f : scene_families()) families.push_back(f.name);
  for (auto& f : families) scene_family(f);  // validates the names

  // Train and test from disjoint scenes: held-out instances of every family, or
  // held-out files (a single file cannot be split, so it all goes to train).
  std::vector<std::string> train_files, test_files;
  check_unique_scene_names(job.scene_files);
  if (!job.scene_files.empty()) {
    size_t n_test = job.scene_files.size() >= 2 ? std::max<size_t>(1, size_t(job.scene_files.size() * job.test_fraction + 0.5)) : 0;
    train_files.assign(job.scene_files.begin(), job.scene_files.end() - long(n_test));
    test_files.assign(job.scene_files.end() - long(n_test), job.scene_files.end());
    if (n_test == 0)
      std::fprintf(stderr, "render-dataset: one scene file: every view goes to train/ (a scene is never in both splits)\n");
  }
  // Whole paths in each split, at least one in test (when there is a test scene).
  int n_test_views = std::max(1, int(job.views * job.test_fraction / P + 0.5)) * P;
  if ((!job.scene_files.empty() && test_files.empty()) || job.views < 2 * P) n_test_views = 0;
  int n_train_views = job.views - n_test_views;
  std::vector<SceneTask> tasks;
  add_tasks(tasks, "train", n_train_views, per_scene, P, families, train_files, 0);
  add_tasks(tasks, "test", n_test_views, per_scene, P, families, test_files, 100000);

  fs::create_directories(job.out);
  DatasetReport report;
  Progress bar("render " + job.preset, job.views);
  int done = 0;
  uint64_t view_counter = 0;
  RenderStats stats;
  for (const SceneTask& task : tasks) {
    Scene scene = task.file.empty() ? make_family_scene(task.family, task.instance, job.settings.seed)
                                    : load_mesh_scene(task.file);
    RayTracer rt(scene);
    (task.split == "train" ? report.train_scenes : report.test_scenes).push_back(scene.name);
    fs::path dir = fs::path(job.out) / task.split;
    fs::create_directories(dir);
    Rng cam_rng = Rng(job.settings.seed).fork(hash_name(scene.name));
    int w = job.width, h = surround ? job.width : job.height;
    float fov = surround ? 90.0f : job.fov_y_deg;
    for (int v0 = 0; v0 < task.views; v0 += P) {
      std::vector<Camera> cams;
      if (P == 1) cams.push_back(place_camera(rt, w, h, fov, cam_rng));
      else cams = camera_path(rt, w, h, fov, std::min(P, task.views - v0), cam_rng);
      for (size_t f = 0; f < cams.size(); ++f) {
        std::string name = scene.name + (P == 1 ? "-v" + zero_padded(v0, 3)
                                                : "-p" + zero_padded(v0 / P, 2) + "-f" + zero_padded(int(f), 3));
        // View ids mix the dataset-wide counter with the scene, so no two views share noise.
        uint64_t id = hash_name(scene.name) ^ (view_counter++ * 0x9E3779B97F4A7C15ull);
        if (surround) {
          auto faces = render_surround(rt, cams[f], w, job.settings, id, false, &stats);
          fs::create_directories(dir / name);
          for (int i = 0; i < 6; ++i) write_view((dir / name / (cube_face_names()[size_t(i)] + ".exr")).string(), faces[size_t(i)]);
        } else {
          write_view((dir / (name + ".exr")).string(), render_view(rt, cams[f], job.settings, id, nullptr, &stats));
        }
        (task.split == "train" ? report.train_views : report.test_views)++;
        ++done;
        if (job.progress) {
          char status[64];
          std::snprintf(status, sizeof status, "%.1f Mrays/s", stats.seconds > 0 ? stats.rays / stats.seconds * 1e-6 : 0.0);
          bar.update(done, status);
        }
      }
    }
  }
  if (job.progress) bar.finish();
  report.rays = stats.rays;
  report.render_seconds = stats.seconds;
  report.cpu_seconds = double(std::clock() - c0) / CLOCKS_PER_SEC;
  report.total_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace nns::data
