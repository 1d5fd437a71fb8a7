#pragma once
// NNAO as a curve, not a point: a ladder of trained models from very cheap to the
// default's quality, so that an engine with a time budget has an NNAO to pick. A rung is
// a horizon layout (directions x steps in bands), a hidden width, the resolution it runs
// at (screen_space/low_resolution.h: 1, 1/2 or 1/4 of the frame in each axis, upsampled
// guided by the full-resolution depth and normals) and its blur passes. Every rung is a
// train-nnao run of its own (same data, seed and epochs), in OUT/<rung>/, listed in
// OUT/ladder.csv from the least to the most accurate (on the validation families);
// eval-ao --ladder OUT draws them as one curve and export-nnao --ladder OUT --budget-ms X
// picks the highest rung within a budget.
//
// The rungs were chosen on the validation families (docs/nnao.md, "The ladder").
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "runs/ao/train_nnao.h"

namespace nns::runs {

struct Rung {
  int directions, steps, bands, hidden, downsample, blur_passes;
  // The blur's and the upsample's normal term, max(0, n.n')^power; -1: the preset's (2).
  // 0 drops the term: at 1/4 resolution it was the flicker's cure (below).
  int normal_power = -1;
  std::string name() const {
    static const char* res[] = {"", "full", "half", "", "quarter"};
    return "d" + std::to_string(directions) + "s" + std::to_string(steps) + "h" + std::to_string(hidden) + "-" +
           res[downsample] + "-b" + std::to_string(blur_passes) +
           (normal_power >= 0 ? "-n" + std::to_string(normal_power) : "");
  }
  // Depth samples per full-resolution pixel: the march's cost, spread over s^2 pixels.
  double samples_per_pixel() const { return double(directions) * steps / double(downsample * downsample); }
};

// The default ladder, least accurate (and cheapest) first, chosen on the validation
// families (vaults, foliage, terrain held out of training; 3 seeds;
// docs/results/2026-12-04-nnao-ladder.md and 2026-12-05-nnao-ladder-nine-rungs.md). A
// candidate is kept unless a cheaper one is at least as good in both validation MSE and
// SSIM (the two measures a rung must beat a classical setting in), and only with flicker
// at most 1.5x the ground truth's. The 1/4-resolution rungs flickered at 1.8x with one
// blur pass; two passes without the normal term bring them to 1.3-1.4x. The top rung is
// the default preset. Validation MSE, SSIM and flicker (means over 3 seeds):
inline std::vector<Rung> default_ladder() {
  return {
      {4, 4, 2, 4, 4, 2, 0},  // 0.0099, 0.843, 1.31x (hidden 8: 0.0104, 0.840, 1.43x, no faster)
      {8, 4, 2, 8, 4, 2, 0},  // 0.0073, 0.852, 1.37x
      {4, 4, 2, 4, 2, 1},     // 0.0088, 0.854, 1.40x (hidden 8: 0.0084, 0.850)
      {4, 4, 2, 4, 2, 2},     // 0.0087, 0.862, 1.21x
      {4, 4, 2, 8, 2, 2},     // 0.0084, 0.859, 1.24x (no normal term: 0.0085, 0.851)
      {8, 4, 2, 8, 2, 1},     // 0.0064, 0.877, 1.32x
      {8, 4, 2, 8, 2, 2},     // 0.0064, 0.880, 1.17x (no normal term: 0.0066, 0.870)
      {16, 8, 4, 16, 2, 2},   // 0.0058, 0.883, 1.19x
      {16, 8, 4, 16, 1, 4},   // 0.0048, 0.905, 0.72x: train-nnao --preset default
  };
}

// Parses "D:S:B:H:s:P[:N]" rungs, comma-separated (train-nnao --ladder-rungs).
inline std::vector<Rung> parse_rungs(const std::string& text) {
  std::vector<Rung> rungs;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) {
    const std::string form =
        "--ladder-rungs: '" + item +
        "' is not D:S:B:H:s:P[:N] (directions, steps, bands, hidden, downsample, blur passes, normal power 0..64)";
    std::vector<int> v;
    std::stringstream fs(item);
    for (std::string f; std::getline(fs, f, ':');) {
      size_t used = 0;
      int x = 0;
      try {
        x = std::stoi(f, &used);
      } catch (const std::exception&) {
        throw std::invalid_argument(form);
      }
      if (used != f.size()) throw std::invalid_argument(form);
      v.push_back(x);
    }
    if (v.size() != 6 && v.size() != 7) throw std::invalid_argument(form);
    Rung r{v[0], v[1], v[2], v[3], v[4], v[5], v.size() == 7 ? v[6] : -1};
    if (v.size() == 7 && (r.normal_power < 0 || r.normal_power > 64)) throw std::invalid_argument(form);
    if (r.downsample != 1 && r.downsample != 2 && r.downsample != 4)
      throw std::invalid_argument("--ladder-rungs: '" + item + "': downsample must be 1, 2 or 4");
    // Refused here, not after the rungs before it have trained.
    if (const std::string p = nnao::HorizonLayout{r.directions, r.steps, r.bands}.problem(); !p.empty())
      throw std::invalid_argument("--ladder-rungs: '" + item + "': " + p);
    if (r.hidden < 1 || r.hidden > 64 || r.blur_passes < 1 || r.blur_passes > 16)
      throw std::invalid_argument("--ladder-rungs: '" + item + "': hidden must be 1..64 and blur passes 1..16");
    rungs.push_back(r);
  }
  if (rungs.empty()) throw std::invalid_argument("--ladder-rungs: no rungs");
  return rungs;
}

// One rung's train-nnao options: the base's data, seed, epochs and blur edges.
inline TrainOptions rung_options(const TrainOptions& base, const Rung& r, const std::string& dir) {
  TrainOptions o = base;
  o.net.features = "horizon";
  o.net.horizon.directions = r.directions, o.net.horizon.steps = r.steps, o.net.horizon.bands = r.bands;
  o.net.hidden = r.hidden;
  o.downsample = r.downsample;
  o.blur_passes = r.blur_passes;
  if (r.normal_power >= 0) o.blur_normal_power = r.normal_power;
  o.out_dir = (std::filesystem::path(dir) / r.name()).string();
  o.resume = base.resume && std::filesystem::exists(std::filesystem::path(o.out_dir) / "checkpoint.blob");
  return o;
}

struct LadderEntry {
  std::string name, blob;  // the rung's folder name and its nnao.blob
  double samples_per_pixel = 0;
};

// Trains every rung into OUT/<rung>/ and writes OUT/ladder.csv (cheapest first). A rung
// that stops on a non-finite value is left out and said so.
inline void train_ladder(const TrainOptions& base, const std::vector<Rung>& rungs) {
  namespace fs = std::filesystem;
  fs::create_directories(base.out_dir);
  std::string csv =
      "rung,directions,steps,bands,hidden,downsample,blur_passes,samples_per_pixel,test_mse,val_mse,seconds\n";
  for (size_t i = 0; i < rungs.size(); ++i) {
    const Rung& r = rungs[i];
    if (!base.quiet) std::fprintf(stderr, "ladder: rung %zu of %zu: %s\n", i + 1, rungs.size(), r.name().c_str());
    const TrainResult t = train_nnao(rung_options(base, r, base.out_dir));
    if (t.exit_code != 0) {
      std::fprintf(stderr, "ladder: %s left out: %s\n", r.name().c_str(), t.stop_message.c_str());
      continue;
    }
    char line[256];
    std::snprintf(line, sizeof line, "%s,%d,%d,%d,%d,%d,%d,%.6g,%.6g,%.6g,%.1f\n", r.name().c_str(), r.directions,
                  r.steps, r.bands, r.hidden, r.downsample, r.blur_passes, r.samples_per_pixel(), t.test_mse, t.val_mse,
                  t.seconds);
    csv += line;
  }
  write_file_atomic((fs::path(base.out_dir) / "ladder.csv").string(), csv);
  if (!base.quiet) std::printf("ladder: %s\n", (fs::path(base.out_dir) / "ladder.csv").string().c_str());
}

// The rungs of a trained ladder, in ladder.csv's order; every blob must exist.
inline std::vector<LadderEntry> read_ladder(const std::string& dir) {
  namespace fs = std::filesystem;
  const std::string csv = (fs::path(dir) / "ladder.csv").string();
  std::ifstream in(csv);
  if (!in) throw std::runtime_error(csv + ": cannot read (train-nnao --ladder writes it)");
  std::vector<LadderEntry> rungs;
  std::string line;
  std::getline(in, line);
  if (line.rfind("rung,", 0) != 0)
    throw std::runtime_error(csv + ": not a ladder file (its first line must start 'rung,')");
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) f.push_back(c);
    if (f.size() < 8 || f[0].empty() || f[0].find_first_of("/\\") != std::string::npos || f[0][0] == '.')
      throw std::runtime_error(csv + ": line " + std::to_string(n) + " is not a rung");
    LadderEntry e{f[0], (fs::path(dir) / f[0] / "nnao.blob").string(), std::atof(f[7].c_str())};
    if (!fs::is_regular_file(e.blob))
      throw std::runtime_error(csv + ": rung " + e.name + " has no model (" + e.blob + ")");
    rungs.push_back(e);
  }
  if (rungs.empty()) throw std::runtime_error(csv + ": no rungs");
  return rungs;
}

}  // namespace nns::runs
