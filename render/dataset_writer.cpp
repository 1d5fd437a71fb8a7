#include "render/dataset_writer.h"

#include "core/atomic_file.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "core/progress.h"
#include "data/dataset.h"
#include "data/exr_io.h"
#include "render/placement.h"
#include "render/render_view.h"
#include "render/surround.h"
#include "render/scenes/families.h"
#include "render/scenes/mesh_loader.h"
#include "render/scenes/scene_variation.h"
#include "render/scenes/texture_variation.h"

namespace nns::render {

namespace fs = std::filesystem;

void apply_preset(DatasetJob& job) {
  RenderSettings& s = job.settings;
  // The lit presets write AO unless the job turned it off (s.ao): the GI networks never
  // read it, and at face 128 its rays are about a seventh of a frame's time.
  if (is_ao_preset(job.preset)) {
    if (!s.ao)
      throw std::invalid_argument("preset '" + job.preset + "': AO is its only target (no AO is for lit presets)");
    s.lighting = false;
    if (job.preset == "nnao-v2") job.vary_views = true;
  } else if (job.preset == "gi" || job.preset == "surround") {
    s.lighting = true, s.indirect = true;
  } else if (job.preset == "surround-v2" || job.preset == "surround-v3") {
    s.lighting = true, s.indirect = true;
    job.vary_lighting = true;
  } else if (job.preset == "surround-v4" || job.preset == "surround-v5") {
    s.lighting = true, s.indirect = true;
    job.vary_lighting = true;
    job.vary_textures = true;
    if (job.preset == "surround-v5") {
      // surround-v4's frames, rendered faster (docs/renderer.md, "surround-v5"): fewer
      // AO and env rays on the side faces of a large face (32 per pixel at 128).
      if (s.side_spp == 0) s.side_spp = surround_v5_side_spp(job.width);
    }
  } else {
    throw std::invalid_argument("unknown preset '" + job.preset +
                                "' (nnao, nnao-v2, gi, surround, surround-v2, surround-v3, surround-v4, surround-v5)");
  }
}

const std::vector<std::pair<int, int>>& ViewVariation::aspects() {
  static const std::vector<std::pair<int, int>> a = {{1, 1}, {4, 3}, {3, 2}, {16, 9}, {2, 1}, {3, 4}};
  return a;
}

namespace {
// One scene to render `views` views (or frames) of, into `split`.
struct SceneTask {
  std::string split;   // "train", "test" or "holdout"
  std::string family;  // procedural family, or empty for a file
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

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (auto& x : v) out += (out.empty() ? "" : ",") + x;
  return out;
}

// Checks the holdout list against the families to render and takes it out of them.
void split_off_holdout(std::vector<std::string>& families, const std::vector<std::string>& holdout,
                       bool families_given) {
  std::set<std::string> seen;
  for (auto& h : holdout) {
    try {
      scene_family(h);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--holdout-families: ") + e.what());
    }
    if (!seen.insert(h).second) throw std::invalid_argument("--holdout-families: '" + h + "' is listed twice");
    if (std::find(families.begin(), families.end(), h) == families.end())
      throw std::invalid_argument("--holdout-families: '" + h + "' is not among the families rendered (" +
                                  (families_given ? "--families " : "the preset's: ") + joined(families) + ")");
  }
  families.erase(
      std::remove_if(families.begin(), families.end(), [&](const std::string& f) { return seen.count(f) > 0; }),
      families.end());
  if (families.empty())
    throw std::invalid_argument("--holdout-families: holds out every family (" + joined(holdout) +
                                "), leaving none for train/ and test/");
}

// A view's size, fov and AO radius: the job's, or (vary_views) drawn from ViewVariation.
struct ViewShape {
  int width, height;
  float fov, ao_radius;  // ao_radius 0 = the scene's
};
ViewShape draw_view_shape(const DatasetJob& job, Rng& rng) {
  ViewVariation var;
  ViewShape v{job.width, job.height, job.fov_y_deg, 0};
  if (!job.vary_views) return v;
  v.fov = float(rng.uniform(var.fov_min, var.fov_max));
  auto [aw, ah] = ViewVariation::aspects()[rng.below(ViewVariation::aspects().size())];
  double area = double(job.width) * job.height * rng.uniform(var.area_min, var.area_max);
  v.height = std::max(8, int(std::lround(std::sqrt(area * ah / aw))));
  v.width = std::max(8, int(std::lround(double(v.height) * aw / ah)));
  v.ao_radius = float(std::exp(rng.uniform(std::log(double(var.radius_min)), std::log(double(var.radius_max)))));
  return v;
}

// The families that have at least one scene in `split`, in task order.
std::vector<std::string> families_in(const std::vector<SceneTask>& tasks, const std::string& split) {
  std::vector<std::string> out;
  for (auto& t : tasks)
    if (t.split == split && !t.family.empty() && std::find(out.begin(), out.end(), t.family) == out.end())
      out.push_back(t.family);
  return out;
}

// DIR/metadata.txt (docs/dataset-format.md): "key: value" lines, written to a
// temporary name and renamed like the views, before the first view. Train and test list the families they
// really hold (a small job may not reach every family); holdout lists every held-out
// family, since none of them may appear elsewhere, rendered or not.
void write_metadata(const DatasetJob& job, const std::vector<SceneTask>& tasks) {
  const std::vector<std::string>& holdout = job.holdout_families;
  fs::path path = fs::path(job.out) / kMetadataFile;
  {
    std::ostringstream m;
    m << "# nnshade dataset metadata (docs/dataset-format.md, \"Dataset metadata\")\n"
      << kMetadataFormatLine << " 1\n"
      << "preset: " << job.preset << "\n"
      << "seed: " << job.settings.seed << "\n";
    if (job.noise_seed >= 0) m << "noise-seed: " << job.noise_seed << "\n";
    m << "families.train: " << joined(families_in(tasks, "train")) << "\n"
      << "families.test: " << joined(families_in(tasks, "test")) << "\n";
    if (!holdout.empty()) m << "families.holdout: " << joined(holdout) << "\n";
    // What the finished render holds, from the plan: dataset-info compares the folders.
    for (const char* split : data::kSplitNames) {
      int views = 0;
      for (const SceneTask& t : tasks)
        if (t.split == split) views += t.views;
      m << "views." << split << ": " << views << "\n";
    }
    if (job.vary_lighting)
      m << "lighting-variation: albedo, light colour and exposure, sun direction and size, extra lamps per scene "
           "(render/scenes/scene_variation.h)\n";
    if (job.vary_textures)
      m << "texture-variation: procedural albedo textures (noise, bricks, tiles, wood, stains, dirt) on most "
           "materials per scene (render/scenes/texture_variation.h)\n";
    const RenderSettings& rs = job.settings;
    if (job.train_gi_spp > 0)
      m << "gi-spp.train: " << job.train_gi_spp << " env and indirect paths per pixel on train/ (" << rs.gi_spp
        << " on test/ and holdout/)\n";
    if (!rs.ao) m << "ao: none (no AO channel; every other channel as with it)\n";
    if (rs.side_spp > 0 && is_surround_preset(job.preset))
      m << "side-spp: " << rs.side_spp << (rs.ao ? " AO and env" : " env")
        << " rays per pixel on the five side faces\n";
    if (job.vary_views) {
      ViewVariation v;
      char buf[512];
      std::snprintf(buf, sizeof buf,
                    "view-variation: fovY %g-%g deg uniform; aspect 1:1 4:3 3:2 16:9 2:1 3:4; pixels %g-%g x %dx%d; "
                    "aoRadius %g-%g log-uniform; pitch range widened %g deg each way\n",
                    v.fov_min, v.fov_max, v.area_min, v.area_max, job.width, job.height, v.radius_min, v.radius_max,
                    v.pitch_widen);
      m << buf;
    }
    write_file_atomic(path.string(), m.str());
  }
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

// The families a job renders: its own list, or the preset's generations interleaved
// (scenes go to families round-robin, so a split with fewer scenes than families still
// mixes old and new kinds). The older presets keep their eight families (and nnao-v2 /
// surround-v2 their two generations), so their datasets do not change.
std::vector<std::string> families_to_render(const DatasetJob& job) {
  std::vector<std::string> families = job.families;
  if (families.empty()) {
    const int generations = job.preset == "surround-v4" || job.preset == "surround-v5" ? 4
                            : job.preset == "surround-v3"                              ? 3
                            : job.preset == "nnao-v2" || job.preset == "surround-v2"   ? 2
                                                                                       : 1;
    std::vector<std::vector<std::string>> gen;
    size_t longest = 0;
    for (int g = 1; g <= generations; ++g)
      gen.push_back(scene_family_names(g)), longest = std::max(longest, gen.back().size());
    for (size_t i = 0; i < longest; ++i)
      for (auto& names : gen)
        if (i < names.size()) families.push_back(names[i]);
  }
  for (auto& f : families) scene_family(f);  // validates the names
  return families;
}

// The scenes of every split and their view counts.
struct SplitPlan {
  std::vector<SceneTask> tasks;
  int holdout_views = 0;
};

// Train and test from disjoint scenes: held-out instances of every family, or held-out
// files (a single file cannot be split, so it all goes to train); holdout from the
// held-out families. `P`: frames per camera path (a path is never split).
SplitPlan plan_splits(const DatasetJob& job, std::vector<std::string> families, int P) {
  const bool holdout = !job.holdout_families.empty();
  if (holdout) {
    if (!job.scene_files.empty())
      throw std::invalid_argument("--holdout-families holds out procedural families; it cannot be used with --scene");
    if (!(job.holdout_fraction > 0 && job.holdout_fraction < 1))
      throw std::invalid_argument("--holdout-fraction must be in (0, 1)");
    split_off_holdout(families, job.holdout_families, !job.families.empty());
  }
  std::vector<std::string> train_files, test_files;
  check_unique_scene_names(job.scene_files);
  if (!job.scene_files.empty()) {
    size_t n_test =
        job.scene_files.size() >= 2 ? std::max<size_t>(1, size_t(job.scene_files.size() * job.test_fraction + 0.5)) : 0;
    train_files.assign(job.scene_files.begin(), job.scene_files.end() - long(n_test));
    test_files.assign(job.scene_files.end() - long(n_test), job.scene_files.end());
  }
  // Whole paths in each split, at least one in test (when there is a test scene).
  int n_test_views = std::max(1, int(job.views * job.test_fraction / P + 0.5)) * P;
  if ((!job.scene_files.empty() && test_files.empty()) || job.views < 2 * P) n_test_views = 0;
  SplitPlan plan;
  plan.holdout_views = holdout ? std::max(1, int(job.views * job.holdout_fraction / P + 0.5)) * P : 0;
  int n_train_views = job.views - n_test_views - plan.holdout_views;
  if (n_train_views < 1)
    throw std::invalid_argument("--views " + std::to_string(job.views) + " leaves no train view after " +
                                std::to_string(n_test_views) + " test and " + std::to_string(plan.holdout_views) +
                                " holdout views");
  const int per_scene = std::max(job.views_per_scene, P);
  add_tasks(plan.tasks, "train", n_train_views, per_scene, P, families, train_files, 0);
  add_tasks(plan.tasks, "test", n_test_views, per_scene, P, families, test_files, 100000);
  // Instances of their own, so even a dataset that trains on these families (another
  // job) never shares a scene with this holdout split.
  add_tasks(plan.tasks, "holdout", plan.holdout_views, per_scene, P, job.holdout_families, {}, 200000);
  return plan;
}

void warn_unrendered_holdout_families(const DatasetJob& job, const SplitPlan& plan) {
  std::vector<std::string> rendered = families_in(plan.tasks, "holdout");
  for (auto& f : job.holdout_families)
    if (std::find(rendered.begin(), rendered.end(), f) == rendered.end())
      std::fprintf(stderr, "render-dataset: held-out family '%s' gets no view (%d holdout views for %zu families)\n",
                   f.c_str(), plan.holdout_views, job.holdout_families.size());
}

// A task's scene, with the job's lighting and view variation.
Scene prepare_scene(const DatasetJob& job, const SceneTask& task) {
  Scene scene =
      task.file.empty() ? make_family_scene(task.family, task.instance, job.settings.seed) : load_mesh_scene(task.file);
  if (job.vary_lighting) {
    // A stream of its own, like the view shapes.
    Rng light_rng = Rng(job.settings.seed ^ 0x11947ull).fork(hash_name(scene.name));
    vary_materials_and_lights(scene, light_rng);
  }
  if (job.vary_textures) {
    // A stream of its own again: the albedos, lights and cameras are surround-v3's.
    Rng texture_rng = Rng(job.settings.seed ^ 0x7E57A7E5ull).fork(hash_name(scene.name));
    vary_textures(scene, texture_rng);
  }
  if (job.vary_views || job.vary_lighting) {
    ViewVariation var;
    scene.cameras.pitch_min_deg = std::max(-80.0f, scene.cameras.pitch_min_deg - var.pitch_widen);
    scene.cameras.pitch_max_deg = std::min(70.0f, scene.cameras.pitch_max_deg + var.pitch_widen);
  }
  return scene;
}

// What the views rendered so far share: the dataset-wide view counter (noise ids, the
// part a view belongs to), the progress and the report, and the files of the last view
// still being written.
struct RenderState {
  DatasetReport report;
  Progress bar;
  int done = 0;
  uint64_t view_counter = 0;
  RenderStats stats;
  std::future<void> writing;

  // Writes on a thread of their own while the next view renders: compressing a surround
  // frame's six EXR files is serial work that left one core idle (the default surround
  // job ran at 187% CPU on 2 cores). One write at a time, in order; a failed write
  // surfaces at the next call or at finish_writing.
  void write_later(std::function<void()> write) {
    finish_writing();
    writing = std::async(std::launch::async, std::move(write));
  }
  void finish_writing() {
    if (writing.valid()) writing.get();
  }
};

// One view (or surround frame) of a scene, when it belongs to this part of the job.
void render_one(const DatasetJob& job, const SceneTask& task, const Scene& scene, RayTracer& rt, const Camera& cam,
                const fs::path& dir, const std::string& name, int w, const RenderSettings& settings, RenderState& st) {
  // View ids mix the dataset-wide counter with the scene, so no two views share noise.
  const bool mine = st.view_counter % uint64_t(job.parts) == uint64_t(job.part);
  uint64_t id = hash_name(scene.name) ^ (st.view_counter++ * 0x9E3779B97F4A7C15ull);
  if (!mine) {
    ++st.done;
    return;
  }
  if (is_surround_preset(job.preset)) {
    auto faces = render_surround(rt, cam, w, settings, id, false, &st.stats);
    st.write_later([faces = std::move(faces), frame = dir / name] {
      fs::create_directories(frame);
      for (int i = 0; i < 6; ++i)
        data::write_view((frame / (cube_face_names()[size_t(i)] + ".exr")).string(), faces[size_t(i)]);
    });
  } else {
    data::View view = render_view(rt, cam, settings, id, nullptr, &st.stats);
    st.write_later([view = std::move(view), file = dir / (name + ".exr")] { data::write_view(file.string(), view); });
  }
  (task.split == "train"  ? st.report.train_views
   : task.split == "test" ? st.report.test_views
                          : st.report.holdout_views)++;
  ++st.done;
  if (job.progress) {
    char status[64];
    std::snprintf(status, sizeof status, "%.1f Mrays/s",
                  st.stats.seconds > 0 ? st.stats.rays / st.stats.seconds * 1e-6 : 0.0);
    st.bar.update(st.done, status);
  }
}

// A scene ready to render: the scene and the BVH over it, on the heap since the
// RayTracer keeps a reference to the scene.
struct PreparedScene {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<RayTracer> rt;
};

PreparedScene prepare_scene_and_bvh(const DatasetJob& job, const SceneTask& task) {
  PreparedScene p;
  p.scene = std::make_unique<Scene>(prepare_scene(job, task));
  p.rt = std::make_unique<RayTracer>(*p.scene);
  return p;
}

// Every view of one scene: camera paths of P frames (or single cameras), each view's
// shape drawn from a stream of the scene's own.
void render_scene(const DatasetJob& job, const SceneTask& task, const Scene& scene, RayTracer& rt, int P,
                  RenderState& st) {
  const bool surround = is_surround_preset(job.preset);
  (task.split == "train"  ? st.report.train_scenes
   : task.split == "test" ? st.report.test_scenes
                          : st.report.holdout_scenes)
      .push_back(scene.name);
  fs::path dir = fs::path(job.out) / task.split;
  fs::create_directories(dir);
  Rng cam_rng = Rng(job.settings.seed).fork(hash_name(scene.name));
  // A stream of its own: drawing view shapes must not move the cameras of the presets
  // that do not vary them.
  Rng shape_rng = Rng(job.settings.seed ^ 0x5eed5eed5eedull).fork(hash_name(scene.name));
  for (int v0 = 0; v0 < task.views; v0 += P) {
    ViewShape shape = draw_view_shape(job, shape_rng);
    int w = shape.width, h = surround ? shape.width : shape.height;
    float fov = surround ? 90.0f : shape.fov;
    RenderSettings settings = job.settings;
    if (job.noise_seed >= 0) settings.seed = uint64_t(job.noise_seed);
    if (job.train_gi_spp > 0 && task.split == "train") settings.gi_spp = job.train_gi_spp;
    settings.ao_radius = shape.ao_radius;
    std::vector<Camera> cams;
    if (P == 1) cams.push_back(place_camera(rt, w, h, fov, cam_rng));
    else cams = camera_path(rt, w, h, fov, std::min(P, task.views - v0), cam_rng);
    for (size_t f = 0; f < cams.size(); ++f) {
      std::string name = scene.name + (P == 1 ? "-v" + zero_padded(v0, 3)
                                              : "-p" + zero_padded(v0 / P, 2) + "-f" + zero_padded(int(f), 3));
      render_one(job, task, scene, rt, cams[f], dir, name, w, settings, st);
    }
  }
}

// What train/, test/, holdout/ and the folder's top hold: the views (EXRs, and surround
// frames' folders in the splits), the first file in a split that is neither, and a
// metadata.txt at the top that no render wrote (a render writes its own there).
struct FolderContents {
  int views = 0;
  std::string stranger;
  std::string foreign_metadata;
};

// A render's metadata names its format on a line of its own (write_metadata).
bool is_render_metadata(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  for (int i = 0; i < 8 && std::getline(in, line); ++i)
    if (line.rfind(kMetadataFormatLine, 0) == 0) return true;
  return false;
}

FolderContents folder_contents(const std::string& out) {
  FolderContents c;
  const fs::path meta = fs::path(out) / kMetadataFile;
  std::error_code meta_ec;
  if (fs::exists(fs::symlink_status(meta, meta_ec)) && !is_render_metadata(meta)) c.foreign_metadata = meta.string();
  auto scan = [&](const fs::path& dir, bool split) {
    std::error_code ec;
    for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
      std::error_code type_ec;
      if (it->is_regular_file(type_ec) && it->path().extension() == ".exr") ++c.views;
      else if (split && it->is_directory(type_ec)) ++c.views;  // a surround frame
      else if (split && c.stranger.empty()) c.stranger = it->path().string();
    }
  };
  scan(out, false);
  for (const char* split : data::kSplitNames) scan(fs::path(out) / split, true);
  return c;
}
}  // namespace

int rendered_views_in(const std::string& out) { return folder_contents(out).views; }

void prepare_render_folder(const std::string& out, bool replace) {
  const auto [n, stranger, foreign_metadata] = folder_contents(out);
  if (!replace && !foreign_metadata.empty())
    throw std::runtime_error(foreign_metadata + ": not a render's metadata (no '" + kMetadataFormatLine +
                             "' line), where the render writes its own; move it, render into a new folder, or "
                             "pass --replace to replace it");
  if (n == 0 && stranger.empty()) return;
  if (!replace && !stranger.empty())
    throw std::runtime_error(
        stranger +
        ": not a view of a render, in a split folder a render owns whole (and removes if it "
        "fails part-way); move it, render into a new folder, or pass --replace to remove those folders first");
  if (!replace)
    throw std::runtime_error(
        out + ": holds " + std::to_string(n) +
        " views of another render; render into a new folder, or pass --replace to remove them first");
  if (!remove_render(out)) throw std::runtime_error(out + ": cannot remove the earlier render's views");
}

bool remove_render(const std::string& out) noexcept {
  // Listing the views and joining paths allocate: memory running out here makes a render
  // that could not be removed, not a std::terminate while the render's own error is on
  // its way out.
  try {
    std::error_code ec, failed;
    std::vector<fs::path> top;
    for (auto it = fs::directory_iterator(out, ec); !ec && it != fs::directory_iterator(); it.increment(ec))
      if (it->path().extension() == ".exr") top.push_back(it->path());
    for (auto& p : top)
      if (fs::remove(p, ec); ec) failed = ec;
    for (const char* split : data::kSplitNames)
      if (fs::remove_all(fs::path(out) / split, ec); ec) failed = ec;
    if (fs::remove(fs::path(out) / kMetadataFile, ec); ec) failed = ec;
    return !failed;
  } catch (...) {
    return false;
  }
}

namespace {
// Everything render_dataset checks of a job before it writes: the preset applied, the
// sizes, the families and the splits planned, then the scene files there (a bad
// combination of flags is named before a missing file). Touches no file.
SplitPlan checked_plan(DatasetJob& job) {
  apply_preset(job);
  if (job.views < 1) throw std::invalid_argument("render_dataset: --views must be >= 1");
  if (job.width < 8 || job.height < 8) throw std::invalid_argument("render_dataset: image size below 8x8");
  if (job.parts < 1 || job.part < 0 || job.part >= job.parts)
    throw std::invalid_argument("render_dataset: part " + std::to_string(job.part) + " of " +
                                std::to_string(job.parts));
  SplitPlan plan = plan_splits(job, families_to_render(job), std::max(1, job.path_frames));
  for (const auto& f : job.scene_files) {
    std::error_code ec;
    if (!fs::is_regular_file(f, ec)) throw std::invalid_argument("--scene " + f + ": no such file");
  }
  return plan;
}
}  // namespace

void check_dataset_job(DatasetJob job) {
  (void)checked_plan(job);
  // Each scene file parsed once here as well: one that is there but is no scene would
  // otherwise be found only when its turn to render came, after metadata.txt (and maybe
  // other scenes' views) were written. Parsing is small beside rendering the scene.
  for (const auto& f : job.scene_files) (void)load_mesh_scene(f);
}

DatasetReport render_dataset(DatasetJob job) {
  auto t0 = std::chrono::steady_clock::now();
  std::clock_t c0 = std::clock();
  const SplitPlan plan = checked_plan(job);
  const int P = std::max(1, job.path_frames);
  if (job.scene_files.size() == 1)
    std::fprintf(stderr,
                 "render-dataset: one scene file: every view goes to train/ (a scene is never in both splits)\n");
  fs::create_directories(job.out);
  if (!job.holdout_families.empty()) warn_unrendered_holdout_families(job, plan);
  if (job.part == 0) write_metadata(job, plan.tasks);
  RenderState st{{}, Progress("render " + job.preset, job.views)};
  // The next scene and its BVH are built on a thread of their own while this one renders
  // (one thread builds each: serial work that left a core idle between scenes).
  const auto& tasks = plan.tasks;
  std::future<PreparedScene> next;
  if (!tasks.empty()) next = std::async(std::launch::async, prepare_scene_and_bvh, std::cref(job), std::cref(tasks[0]));
  for (size_t i = 0; i < tasks.size(); ++i) {
    PreparedScene prepared = next.get();
    if (i + 1 < tasks.size())
      next = std::async(std::launch::async, prepare_scene_and_bvh, std::cref(job), std::cref(tasks[i + 1]));
    render_scene(job, tasks[i], *prepared.scene, *prepared.rt, P, st);
  }
  st.finish_writing();
  if (job.progress) st.bar.finish();
  DatasetReport report = std::move(st.report);
  report.rays = st.stats.rays;
  report.render_seconds = st.stats.seconds;
  report.cpu_seconds = double(std::clock() - c0) / CLOCKS_PER_SEC;
  report.total_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace nns::render
