#pragma once
// render_dataset: renders a whole dataset (docs/dataset-format.md) from procedural
// scene families and/or mesh files, into DIR/train and DIR/test. Train and test never
// share a scene: test views come from other instances of each family (or other files).
// Held-out families (leave-families-out) go only to DIR/holdout, and DIR/metadata.txt
// records which families are in which split.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "render/integrator.h"

namespace nns::render {

struct DatasetJob {
  std::string out;                       // dataset folder (created)
  std::string preset = "nnao";           // nnao: Z N albedo AO; nnao-v2: nnao with varied views
                                         // and all families; gi: + lighting; surround: cube frames;
                                         // surround-v2: surround over all families, materials and
                                         // lights varied per scene (render/scenes/scene_variation.h);
                                         // surround-v3: surround-v2 over generations 1-3;
                                         // surround-v4: surround-v3 plus generation 4 and
                                         // textured materials (render/scenes/texture_variation.h);
                                         // surround-v5: surround-v4's frames, rendered faster
  int views = 80;                        // views (frames for surround) over train + test
  double test_fraction = 0.2;            // share of views rendered from held-out scenes
  int views_per_scene = 4;               // views taken in one scene before the next
  int width = 320, height = 180;         // surround: the face size is width x width
  float fov_y_deg = 60;                  // ignored for surround (faces are 90 degrees)
  int path_frames = 1;                   // > 1: views come as camera paths of this length
  std::vector<std::string> scene_files;  // OBJ / glTF; none = procedural families
  std::vector<std::string> families;     // procedural families to use; empty = the preset's
                                         // (generation 1 for nnao/gi/surround, 1-2 for nnao-v2
                                         // and surround-v2, 1-3 for surround-v3, 1-4 for surround-v4 and v5)
  // Leave-families-out: these families render only into holdout/, never into train/
  // or test/; they must be among `families` (or the preset's), and leave at least one.
  std::vector<std::string> holdout_families;
  double holdout_fraction = 0.2;  // share of `views` that goes to holdout/
  // Per-view randomisation of what real scenes vary (set by the nnao-v2 preset; see
  // ViewVariation): fov, aspect, resolution, AO radius, a wider pitch range.
  bool vary_views = false;
  // Per-scene albedos, light colours, exposure, sun and extra lamps (set by surround-v2/v3).
  bool vary_lighting = false;
  // Procedural albedo textures on most materials, per scene (set by surround-v4).
  bool vary_textures = false;
  RenderSettings settings;  // spp, bounces, seed; ao/lighting set by preset
  // >= 0: the Monte-Carlo noise comes from this seed instead of settings.seed, while
  // scenes, cameras and lighting keep settings.seed: the same views with independent
  // noise (two-seed noise estimates, a reference against which to measure an estimator).
  int64_t noise_seed = -1;
  // > 0: paths per pixel of the train/ views' env and indirect light, in place of
  // settings.gi_spp, which then renders test/ and holdout/ alone: training targets may
  // be noisier than the references that score a model (the default surround data trains
  // on 64 paths and is scored against 128, docs/renderer.md).
  int train_gi_spp = 0;
  bool progress = true;  // progress bar on stderr
  // Render only views i with i % parts == part (mpirun: rank and size). Every part walks
  // the same scenes and cameras, so a view's bytes never depend on the split; part 0
  // writes metadata.txt. The parts' views together are the whole dataset.
  int part = 0, parts = 1;
};

// The ranges nnao-v2 draws from, per view (per path for camera paths). The image keeps
// about the job's pixel count times `area` so every view costs about the same.
struct ViewVariation {
  float fov_min = 35, fov_max = 90;                          // vertical fov, degrees, uniform
  float area_min = 0.6f, area_max = 1.0f;                    // pixel count relative to width x height, uniform
  float radius_min = 0.1f, radius_max = 3;                   // AO radius in metres, log-uniform
  float pitch_widen = 10;                                    // degrees added to each end of the scene's pitch range
  static const std::vector<std::pair<int, int>>& aspects();  // 1:1 4:3 3:2 16:9 2:1 3:4
};

struct DatasetReport {
  int train_views = 0, test_views = 0, holdout_views = 0;  // files (surround: frames)
  uint64_t rays = 0;
  double render_seconds = 0, total_seconds = 0;  // wall clock: rendering, everything
  double cpu_seconds = 0;  // process CPU time (both threads): the figure a busy machine cannot inflate
  std::vector<std::string> train_scenes, test_scenes, holdout_scenes;
};

// Applies a preset's channel choice to job.settings (called by render_dataset).
void apply_preset(DatasetJob& job);

// Whether a preset renders AO alone (nnao, nnao-v2): AO is its target, so it cannot go
// without it (RenderSettings::ao).
inline bool is_ao_preset(const std::string& preset) { return preset == "nnao" || preset == "nnao-v2"; }

// Whether a preset writes cube frames (surround, surround-v2 .. v4) rather than single views.
inline bool is_surround_preset(const std::string& preset) {
  return preset == "surround" || preset == "surround-v2" || preset == "surround-v3" || preset == "surround-v4" ||
         preset == "surround-v5";
}

// surround-v5's AO / env rays per pixel on the side faces (RenderSettings::side_spp),
// unless a job sets its own, for a face of `size` pixels a side: 64 x 64 / size, at most
// 64 (surround-v4's), at least 8: 32 at 128, 16 at 256. Stratified rays' noise variance
// falls faster than 1 / rays (measured at face 128: 32 rays 2.9x, 16 rays 8.2x the
// variance of 64), so halving the rays per doubling of the face keeps the noise per area
// of a 64x64 face's pixel below that face's at 64 rays (0.73x at 128); a quarter
// (rays per face constant) would double it.
inline int surround_v5_side_spp(int size) {
  return int(std::clamp((64L * 64 + size / 2) / std::max(1L, long(size)), 8L, 64L));
}

// The metadata file of a dataset (DIR/metadata.txt, docs/dataset-format.md), written
// by every render before its first view: the preset, seeds, families and how many
// views (surround: frames) each split will hold ("views.train: 1680"), so dataset-info
// can tell a render that did not finish. The views themselves do not depend on it.
inline constexpr const char* kMetadataFile = "metadata.txt";
// Its line naming the format (the version follows): what tells a render's metadata from
// a user's file of the same name.
inline constexpr const char* kMetadataFormatLine = "format: nnshade-dataset-metadata";

DatasetReport render_dataset(DatasetJob job);

// Throws what render_dataset would throw for the job itself (preset, sizes, families,
// holdout, scene files there and parsed), touching no file: render-dataset calls it before
// it makes and locks the output folder, so a refused job leaves no folder behind.
void check_dataset_job(DatasetJob job);

// How many views (files *.exr, or surround frame folders) `out` holds from an earlier
// render, in train/, test/, holdout/ or at its top.
int rendered_views_in(const std::string& out);

// Before a render into `out`: a folder that holds another render's views is refused
// (render-dataset --views 6 and then --views 2 into one folder kept four stale views
// beside the new ones), unless `replace`, which removes those views and metadata.txt.
// So is, unless `replace`, a file in train/, test/ or holdout/ that is no view: a render
// owns those folders whole and removes them if it fails part-way, and a user's file
// there would go with them. So is a metadata.txt at the top that no render wrote: the
// render would write its own over it.
void prepare_render_folder(const std::string& out, bool replace);

// Removes a render from `out`: the views at its top, train/, test/, holdout/ and
// metadata.txt; false if something could not be removed. Never throws: render-dataset
// calls it while a failed render's error is on its way out, so that what is left is
// never a dataset that lists views it does not hold.
bool remove_render(const std::string& out) noexcept;

}  // namespace nns::render
