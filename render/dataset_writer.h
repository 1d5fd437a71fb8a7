#pragma once
// render_dataset: renders a whole dataset (docs/dataset-format.md) from procedural
// scene families and/or mesh files, into DIR/train and DIR/test. Train and test never
// share a scene: test views come from other instances of each family (or other files).
#include <cstdint>
#include <string>
#include <vector>

#include "render/integrator.h"

namespace nns::data {

struct DatasetJob {
  std::string out;                     // dataset folder (created)
  std::string preset = "nnao";         // nnao: Z N albedo AO; gi: + lighting; surround: cube frames
  int views = 80;                      // views (frames for surround) over train + test
  double test_fraction = 0.2;          // share of views rendered from held-out scenes
  int views_per_scene = 4;             // views taken in one scene before the next
  int width = 320, height = 180;       // surround: the face size is width x width
  float fov_y_deg = 60;                // ignored for surround (faces are 90 degrees)
  int path_frames = 1;                 // > 1: views come as camera paths of this length
  std::vector<std::string> scene_files;  // OBJ / glTF; none = procedural families
  std::vector<std::string> families;     // procedural families to use; empty = all
  RenderSettings settings;             // spp, bounces, seed; ao/lighting set by preset
  bool progress = true;                // progress bar on stderr
};

struct DatasetReport {
  int train_views = 0, test_views = 0;  // files (surround: frames)
  uint64_t rays = 0;
  double render_seconds = 0, total_seconds = 0;  // wall clock: rendering, everything
  double cpu_seconds = 0;  // process CPU time (both threads): the figure a busy machine cannot inflate
  std::vector<std::string> train_scenes, test_scenes;
};

// Applies a preset's channel choice to job.settings (called by render_dataset).
void apply_preset(DatasetJob& job);

DatasetReport render_dataset(DatasetJob job);

}  // namespace nns::data
