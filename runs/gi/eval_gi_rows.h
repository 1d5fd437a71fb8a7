#pragma once
// What eval-gi is asked (EvalOptions) and what it finds, one row per way of predicting
// light (EvalRow); eval_gi_report.h writes the rows, eval_gi.h scores them.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "runs/gi/gi_previews.h"
#include "runs/gi/gi_scores.h"

namespace nns::runs {

struct EvalOptions {
  std::string data, out;
  std::vector<std::string> models;  // G.blob files
  // "test"; "validation": the train/ scenes the first model's train-gan held out (its
  // G.blob records the share); "holdout": the families render-dataset held out.
  std::string split = "test";
  bool bn_batch_stats = true;  // test-time BatchNorm statistics (docs/gan.md)
  bool dropout_on = false;     // test-time dropout
  size_t max_frames = size_t(-1);
  int previews = 3;  // frames with preview PNGs per model
  // Off-screen-lit: the front face holds less than its uniform share (1/6) of the frame's
  // direct light, i.e. most directly lit surfaces are off the screen (docs/gan.md).
  float offscreen_share = 1.0f / 6;
  bool quiet = false;
  // The resolution study: every method is scored at face `size` (0: each model at the
  // face it was trained at); with `upsample_from` > 0 each model runs at that face and
  // its indirect light is brought up to the scored face by the guided upsample
  // (models/gi/guided_upsample.h), as engines bring up half-resolution GI.
  int size = 0, upsample_from = 0;
  // Each model's light averaged with its light for the mirrored frame, mirrored back
  // (test-time augmentation: twice the time per frame).
  bool mirror_average = false;
  // Another render of the scored frames with independent noise (second_render.h): its
  // light is scored as ceiling rows (empty: none).
  std::string second_render;
  // A diagnostic row per model: its indirect light times the per-frame gains that fit
  // the truth best (best_gain_light). What the row still gets wrong is the light's shape;
  // the difference to the model's own row is the frame's overall level and colour.
  bool best_gain = false;
};

struct EvalRow {
  std::string model, mode;
  bool ceiling = false;  // the upsampled truth: no method one could run, left out of the speed charts
  double ms_per_frame = 0;
  LightMetrics all, offscreen;
  int64_t frames = 0, offscreen_frames = 0;
  std::map<std::string, MetricsMean> by_family;  // scene family -> its frames' metrics
  DistanceBands bands;                           // all frames, by distance to a surface break
  // Reprojected along camera paths (gi_scores.h): the row's flicker, the ground truth's on
  // the same pairs, and the temporal error; NaN without camera paths.
  double flicker = NAN, flicker_truth = NAN, temporal_error = NAN;
  int64_t flicker_pairs = 0;
  std::vector<EvalPreview> previews;  // the frames with preview PNGs
};

namespace detail {

inline std::string fmt(double v, const char* f = "%.6g") {
  char b[48];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

inline std::string label_of(const std::string& path) {
  namespace fs = std::filesystem;
  fs::path p(path);
  std::string parent = p.parent_path().filename().string();
  return parent.empty() ? p.stem().string() : parent + "/" + p.stem().string();
}

inline std::string safe_name(std::string s) {
  for (char& c : s)
    if (c == '/' || c == ' ' || c == '\\' || c == '+') c = '_';
  return s;
}

}  // namespace detail

}  // namespace nns::runs
