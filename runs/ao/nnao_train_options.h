#pragma once
// What train-nnao is asked: the named presets (each chosen by measurements, docs/nnao.md),
// the options of one training run, and what it reports (train_nnao.h trains).
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/kernels/gemm_precision.h"
#include "models/nnao/nnao_model.h"

namespace nns::runs {

// Named settings of train-nnao, each chosen by measurements (docs/nnao.md):
// `paper`: Holden et al. 2016 (grid w 31, hidden 4, dropout 0.5, gamma 0.01).
// `grid`: the paper's grid with gamma 1e-4, chosen on validation scenes (at w 31 /
//   hidden 4, gamma 0.01 gives validation MSE 0.0163, 0.000625 0.0126, 1e-4 0.0117: the
//   L1 term at 0.01 switches hidden units off; the size ladder's smallest rung within 2%
//   of its best is w 31 / hidden 4).
// `default`: horizon features (horizon_features.h), 16 directions x 8 steps in 4 bands,
//   hidden 16, no dropout, gamma 1e-4, 8 epochs: the size sweep's pick on validation
//   *families* of the default data v4 (vaults, foliage, terrain held out of training;
//   mean of 3 seeds): the cheapest rung within 2% of the best (docs/nnao.md); its
//   exact inference blurs 4 times (1, 2, 3, 4, 6, 8 passes on the same validation
//   families, 3 seeds: 4 and 6 have the lowest MSE, 4 costs less) with the looser edge
//   terms depth 0.3, normal power 2 (passes 4 and 8 x depth 0.1-0.5 x power 1-8 on those
//   families, 3 seeds: the lowest flicker among the settings within 2% of the best MSE),
//   and its inference holds the radius term at 0.6 (0.4-0.8 and none on those families,
//   3 seeds: the lowest MSE; horizon_features.h says why).
struct Preset {
  std::string features;
  int window;
  nnao::HorizonLayout horizon;
  int hidden;
  double dropout, gamma;
  int epochs;
  int blur_passes;    // horizon models: the exact inference's bilateral blur passes
  double blur_depth;  // and its edge terms (nnao::BlurEdges)
  int blur_normal_power;
  double radius_term_max;  // horizon models: the inference's ceiling on the radius term (0: none)
};
inline Preset preset(const std::string& name) {
  if (name == "paper")
    return {.features = "grid",
            .window = 31,
            .horizon = {},
            .hidden = 4,
            .dropout = 0.5,
            .gamma = 0.01,
            .epochs = 12,
            .blur_passes = 1,
            .blur_depth = 0.1,
            .blur_normal_power = 8,
            .radius_term_max = 0};
  if (name == "grid")
    return {.features = "grid",
            .window = 31,
            .horizon = {},
            .hidden = 4,
            .dropout = 0.5,
            .gamma = 1e-4,
            .epochs = 12,
            .blur_passes = 1,
            .blur_depth = 0.1,
            .blur_normal_power = 8,
            .radius_term_max = 0};
  if (name == "default")
    return {.features = "horizon",
            .window = 31,
            .horizon = {.directions = 16, .steps = 8, .bands = 4},
            .hidden = 16,
            .dropout = 0.0,
            .gamma = 1e-4,
            .epochs = 8,
            .blur_passes = 4,
            .blur_depth = 0.3,
            .blur_normal_power = 2,
            .radius_term_max = 0.6};
  throw std::invalid_argument("unknown NNAO preset '" + name + "' (known: default, grid, paper)");
}

struct TrainOptions {
  std::string data_dir;  // train/ + test/ (or flat: split by scene)
  std::string out_dir = "nnao-out";
  nnao::NnaoNetConfig net;
  int epochs = 20;
  int blur_passes = 1;      // horizon models: recorded in the blob for the exact inference
  double blur_depth = 0.1;  // and the blur's edge terms (nnao::BlurEdges)
  int blur_normal_power = 8;
  double radius_term_max = 0;  // horizon models: recorded for inference only (training sees the term unclamped)
  int downsample = 1;     // horizon models: points and inference at 1/s of the resolution (NnaoWeights::downsample)
  int batch = 16;         // the global batch, whatever the number of MPI ranks
  int accumulate = 1;     // micro-batches per step (batch / accumulate points each)
  double bucket_mb = 25;  // MiB per gradient bucket of the MPI exchange (<= 0: one)
  double lr = 1e-3;
  double gamma = 0.01;
  int points_per_view = 1024;
  int test_points_per_view = 1024;
  float radius = 0;  // <= 0: each view's aoRadius
  uint64_t seed = 1;
  // bf16: the products of the network take bf16 inputs (fp32 sums, weights, Adam, loss).
  Precision precision = Precision::fp32;
  // The chunked shuffle (row_file.h): points per chunk read in one piece, and the MiB
  // of each of the two buffers (a buffer holds whole chunks, at least one).
  int shuffle_chunk = 256;
  double shuffle_buffer_mb = 512;
  bool resume = false;
  bool quiet = false;
  // Whole scenes of the training split held out for model selection (val_mse in the
  // log); 0 trains on all of it. The sweep selects on it, never on the test split.
  double validation_fraction = 0;
  // Or whole scene families of the training split (validation_split.h); wins over the fraction.
  std::vector<std::string> validation_families;
};

// The options a preset names; the rest keep TrainOptions' initialisers.
inline TrainOptions preset_options(const std::string& name) {
  const Preset p = preset(name);
  TrainOptions o;
  o.net.features = p.features;
  o.net.window = p.window;
  o.net.horizon = p.horizon;
  o.net.hidden = p.hidden;
  o.net.dropout = p.dropout;
  o.gamma = p.gamma;
  o.epochs = p.epochs;
  o.blur_passes = p.blur_passes;
  o.blur_depth = p.blur_depth;
  o.blur_normal_power = p.blur_normal_power;
  o.radius_term_max = p.radius_term_max;
  return o;
}

struct TrainResult {
  int64_t train_points = 0, test_points = 0, steps = 0;
  // NaN until an epoch has run (--epochs 0 measures nothing; summary.json says null).
  double train_loss = std::nan(""), test_mse = std::nan(""), val_mse = std::nan(""), seconds = 0;
  double step_microseconds = 0;  // training steps only (no data building, no test pass)
  double build_seconds = 0;      // points of both splits: features, statistics, standardising
  double epoch_seconds = 0;      // mean wall time of the epochs this process ran (steps + test pass)
  std::string stop_message;      // empty: finished; else why it stopped (non-finite value)
  int exit_code = 0;             // 0 finished, 3 stopped on a non-finite value
};

}  // namespace nns::runs
