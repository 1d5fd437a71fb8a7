#pragma once
// eval-gi: scores trained generators and the two references that need no learning on
// one split of a dataset — test, validation or holdout (the thesis's Table 5.3 metrics,
// gi_scores.h):
//   direct+env          the light a rasterizer has: no indirect light at all
//   direct+env+ambient  plus a constant per-channel ambient term, the mean indirect
//                       light of the scenes trained on (least squares in linear HDR)
// Files in OUT: results.csv (all test frames), results_offscreen.csv (the frames whose
// directly lit surfaces are off the front view), frames.csv (every frame of every
// model), results_by_family.csv, results_by_distance.csv (error by distance to the nearest
// depth jump or crease, gi_scores.h), report.md and report.html, speed_vs_ssim.svg/.png,
// speed_vs_mse_linear.svg/.png and speed_vs_flip.svg/.png,
// previews/<model>_<frame>_{prediction,truth,error}.png (eval_gi_report.h writes them).
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "data/validation_split.h"
#include "models/gi/gi_model_io.h"
#include "models/gi/upsampled_light.h"
#include "runs/gi/eval_gi_report.h"
#include "runs/gi/eval_gi_rows.h"
#include "runs/gi/gi_samples.h"
#include "runs/gi/gi_scores.h"
#include "runs/gi/model_light.h"
#include "runs/gi/second_render.h"

namespace nns::runs {

// Scores one way of predicting light on `samples`; predict(sample) returns linear light
// (3, h, w). Appends per-frame lines to `frames_csv`.
template <class Predict>
EvalRow score(const std::string& model, const std::string& mode, std::vector<gi::GiSample>& samples,
              const gi::HdrMapping& hdr, const EvalOptions& o, Predict&& predict, std::string& frames_csv) {
  EvalRow row;
  row.model = model, row.mode = mode;
  MetricsMean all, off;
  double ms = 0;
  classical_ao::TemporalStats temporal, truth_temporal;
  std::vector<float> prev_pred, prev_truth;
  const gi::GiSample* prev = nullptr;
  int previews = 0;
  for (auto& s : samples) {
    auto t0 = std::chrono::steady_clock::now();
    Tensor<float> p = predict(s);
    ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    LightMetrics m = light_metrics(p, s.target_linear, s.geometry, hdr);
    std::vector<float> pred = mapped(p, hdr), truth = mapped(s.target_linear, hdr);
    const int h = int(s.target_linear.size(1)), w = int(s.target_linear.size(2));
    const std::vector<float> flip_map = frame_detail(pred, truth, s.geometry, w, h, m);
    add_to_bands(row.bands, distance_bands_of(s), pred, truth, flip_map, s.geometry);
    all.add(m);
    row.by_family[data::scene_family_of(s.scene)].add(m);
    const bool is_off = s.front_direct_share < o.offscreen_share;  // NaN: unknown, not off
    if (is_off) off.add(m);
    if (prev && next_on_path(*prev, s)) {
      const std::vector<int64_t> map = reproject_front(s, *prev);
      add_flicker_pair(temporal, map, pred, prev_pred, truth, prev_truth);
      add_flicker_pair(truth_temporal, map, truth, prev_truth, truth, prev_truth);
    }
    prev = &s, prev_pred = std::move(pred), prev_truth = std::move(truth);
    frames_csv += report::csv_field(model) + "," + report::csv_field(mode) + "," + report::csv_field(s.name) + "," +
                  report::csv_field(s.scene) + "," + detail::fmt(s.front_direct_share) + "," + (is_off ? "1" : "0") +
                  "," + detail::fmt(m.mse) + "," + detail::fmt(m.psnr) + "," + detail::fmt(m.ssim) + "," +
                  detail::fmt(m.mse_linear) + "," + detail::fmt(m.psnr_linear) + "," + detail::fmt(m.ssim_linear) +
                  "," + detail::fmt(m.flip) + "," + detail::fmt(m.grad_error) + "\n";
    if (previews < o.previews) {
      const std::string prefix =
          "previews/" + detail::safe_name(model) + "_" + detail::safe_name(detail::label_of(s.name));
      write_eval_pngs(o.out + "/" + prefix, p, s.target_linear, hdr, s.geometry);
      row.previews.push_back({model + (mode == "-" ? "" : " (" + mode + ")"), detail::label_of(s.name), prefix, m});
      ++previews;
    }
  }
  row.frames = all.frames, row.offscreen_frames = off.frames;
  row.all = all.mean(), row.offscreen = off.mean();
  row.ms_per_frame = samples.empty() ? 0 : ms / double(samples.size());
  row.flicker = temporal.flicker(), row.flicker_truth = truth_temporal.flicker();
  row.temporal_error = temporal.error(), row.flicker_pairs = temporal.pairs / 3;
  return row;
}

// Whether a frame's front geometry receives no light at all (target 0 everywhere).
inline bool unlit(const gi::GiSample& s) {
  const int64_t n = int64_t(s.geometry.size());
  for (int c = 0; c < 3; ++c)
    for (int64_t i = 0; i < n; ++i)
      if (s.geometry[size_t(i)] && s.target_linear[c * n + i] > 0) return false;
  return true;
}

// The mean indirect light (target - direct - env) per channel over training geometry,
// read a frame at a time: at face 128 the training split's samples take 10 GiB.
inline std::array<float, 3> fit_ambient(const data::SplitListing& train, const GiItemReader& rd,
                                        const gi::GiInputConfig& cfg, size_t max_items, bool quiet) {
  std::array<double, 3> s{0, 0, 0};
  int64_t count = 0;
  const size_t items = std::min(max_items, split_items(train, rd.mode));
  Progress bar("eval-gi ambient fit", int64_t(items));
  for (size_t k = 0; k < items; ++k) {
    const gi::GiSample x = load_sample(train, rd, cfg, k);
    const int64_t n = int64_t(x.geometry.size());
    for (int64_t i = 0; i < n; ++i) {
      if (!x.geometry[size_t(i)]) continue;
      for (int c = 0; c < 3; ++c) s[size_t(c)] += x.target_linear[c * n + i] - x.direct_env[c * n + i];
      ++count;
    }
    if (!quiet) bar.update(int64_t(k + 1));
  }
  std::array<float, 3> a{0, 0, 0};
  for (int c = 0; c < 3; ++c) a[size_t(c)] = count ? float(s[size_t(c)] / double(count)) : 0.0f;
  return a;
}

// The frames an evaluation scores: test/, the validation scenes the first model's run
// carved out of train/, holdout/, or the rest of train/ (the scenes it trained on); and
// the train/ scenes the ambient term is fitted on.
struct EvalSplits {
  data::DatasetListing listing;
  data::SplitListing fit, validation;
  const data::SplitListing* scored = nullptr;
};

inline EvalSplits open_eval_splits(const EvalOptions& o, double validation_fraction) {
  EvalSplits e;
  e.listing = data::list_splits(o.data);
  std::tie(e.fit, e.validation) = data::hold_out_validation(e.listing.train, validation_fraction);
  e.scored = &e.listing.test;
  if (o.split == "validation") {
    if (e.validation.size() == 0)
      throw std::runtime_error(o.models.front() +
                               ": trained without a validation split (train-gan --validation-fraction)");
    e.scored = &e.validation;
  } else if (o.split == "holdout") {
    if (!e.listing.has_holdout)
      throw std::runtime_error(o.data + ": no holdout/ split (render-dataset --holdout-families makes one)");
    e.scored = &e.listing.holdout;
  } else if (o.split == "train") {
    e.scored = &e.fit;  // what the models fitted: their error there against validation's is the generalisation gap
  } else if (o.split != "test") {
    throw std::invalid_argument("eval-gi: unknown split '" + o.split + "' (test, validation, holdout, train)");
  }
  if (e.scored->size() == 0) throw std::runtime_error(o.data + ": no " + o.split + " views or frames");
  return e;
}

// A frame with no light at all on its front geometry (every lamp of the scene hidden
// from the camera's room: 12 of the default data's 180 holdout frames) has nothing to
// predict: its PSNR is infinite for direct+env and SSIM is undefined, and a constant
// ambient term loses there by construction. Such frames are set aside and counted.
inline size_t set_aside_unlit(std::vector<gi::GiSample>& frames, const EvalOptions& o) {
  const size_t before = frames.size();
  frames.erase(std::remove_if(frames.begin(), frames.end(), [](const gi::GiSample& s) { return unlit(s); }),
               frames.end());
  const size_t unlit_frames = before - frames.size();
  if (unlit_frames && !o.quiet)
    std::fprintf(stderr, "eval-gi: %zu unlit %s frames set aside (no light on the front view)\n", unlit_frames,
                 o.split.c_str());
  if (frames.empty())
    throw std::runtime_error(o.data + ": every " + o.split + " frame is unlit (no light on its front view)");
  return unlit_frames;
}

// The two references that learn nothing: direct + env, and that plus a constant ambient
// fitted on the training scenes.
inline void score_references(const EvalSplits& e, const GiItemReader& rd, const gi::GiInputConfig& cfg,
                             std::vector<gi::GiSample>& frames, const gi::HdrMapping& hdr, const EvalOptions& o,
                             std::vector<EvalRow>& rows, std::string& frames_csv) {
  const auto ambient = fit_ambient(e.fit, rd, cfg, o.max_frames, o.quiet);
  rows.push_back(score(
      "direct+env", "-", frames, hdr, o, [](const gi::GiSample& s) { return s.direct_env.clone(); }, frames_csv));
  rows.push_back(score(
      "direct+env+ambient", "-", frames, hdr, o,
      [&](const gi::GiSample& s) {
        Tensor<float> p = s.direct_env.clone();
        const int64_t n = int64_t(s.geometry.size());
        for (int c = 0; c < 3; ++c)
          for (int64_t i = 0; i < n; ++i) p[c * n + i] += ambient[size_t(c)];
        return p;
      },
      frames_csv));
}

// The frames box-filtered to the face the models run at (--upsample-from), by name.
struct LowFrames {
  std::vector<gi::GiSample> samples;
  std::map<std::string, size_t> index;
  const gi::GiSample& of(const gi::GiSample& full) const { return samples.at(index.at(full.name)); }
};

inline LowFrames load_low_frames(const EvalSplits& e, const gi::GiInputConfig& cfg, const EvalOptions& o) {
  LowFrames low;
  low.samples =
      load_samples(*e.scored, GiItemReader{cfg.mode, o.upsample_from}, cfg, o.max_frames, "eval-gi low", o.quiet);
  for (size_t i = 0; i < low.samples.size(); ++i) low.index[low.samples[i].name] = i;
  return low;
}

// What a model run at the low face would score if it predicted the reduced frame's light
// exactly: the true light box-filtered to that face and brought up by the same guided
// upsample. Its error is the resolution's share; the rest of a model's is the network's.
inline EvalRow score_upsampled_truth(const LowFrames& low, std::vector<gi::GiSample>& frames, const gi::HdrMapping& hdr,
                                     const EvalOptions& o, std::string& frames_csv) {
  EvalRow row = score(
      "truth @" + std::to_string(o.upsample_from) + " guided", "-", frames, hdr, o,
      [&](const gi::GiSample& s) {
        const gi::GiSample& l = low.of(s);
        return gi::upsampled_light(l.target_linear.clone(), l, s);
      },
      frames_csv);
  row.ceiling = true;
  return row;
}

// The light of another render of the same frames (second_render.h): its own row, the
// noise floor; with --upsample-from also as a face-L network that knew the light would
// deliver it (its indirect light brought up by the guided upsample). Ceiling rows.
inline void score_second_render(const SecondRender& other, const GiItemReader& rd, const gi::GiInputConfig& cfg,
                                const LowFrames* low, std::vector<gi::GiSample>& frames, const gi::HdrMapping& hdr,
                                const EvalOptions& o, std::vector<EvalRow>& rows, std::string& frames_csv) {
  rows.push_back(score(
      "another render", "-", frames, hdr, o,
      [&](const gi::GiSample& s) { return other.of(s, rd, cfg).target_linear.clone(); }, frames_csv));
  rows.back().ceiling = true;
  if (!low) return;
  const GiItemReader low_reader{cfg.mode, o.upsample_from};
  rows.push_back(score(
      "another render @" + std::to_string(o.upsample_from) + " guided", "-", frames, hdr, o,
      [&](const gi::GiSample& s) {
        const gi::GiSample& l = low->of(s);
        const gi::GiSample b = other.of(l, low_reader, cfg);
        // The other render's indirect light on this frame's direct and env light.
        Tensor<float> light = b.target_linear.clone();
        for (int64_t i = 0; i < light.numel(); ++i) light[i] += l.direct_env[i] - b.direct_env[i];
        return gi::upsampled_light(light, l, s);
      },
      frames_csv));
  rows.back().ceiling = true;
}

// The light `light` (3, h, w) of frame s with its indirect part (light - direct - env)
// scaled, per colour channel, by the gain that fits the true indirect light best in
// least squares over the geometry pixels: g = sum(p t) / sum(p p) (1 where the
// prediction has no indirect light at all).
inline Tensor<float> best_gain_light(Tensor<float> light, const gi::GiSample& s) {
  const int64_t n = light.numel() / 3;
  for (int c = 0; c < 3; ++c) {
    double pt = 0, pp = 0;
    for (int64_t i = 0; i < n; ++i) {
      if (!s.geometry[size_t(i)]) continue;
      const double p = light[c * n + i] - s.direct_env[c * n + i];
      pt += p * (s.target_linear[c * n + i] - s.direct_env[c * n + i]);
      pp += p * p;
    }
    const double g = pp > 0 ? pt / pp : 1.0;
    for (int64_t i = 0; i < n; ++i) {
      const float d = s.direct_env[c * n + i];
      light[c * n + i] = d + float(g) * (light[c * n + i] - d);
    }
  }
  return light;
}

// One model's row. With --upsample-from (`low` given), the model sees the frames
// box-filtered to that face, and its indirect light (prediction - direct - env) is
// brought up to the scored frames by the guided upsample; the direct and env light are
// the scored frames' own. best_gain: the diagnostic row of --best-gain (a ceiling row).
inline EvalRow score_model(const std::string& path, gi::LoadedGenerator& g, const LowFrames* low,
                           std::vector<gi::GiSample>& frames, const gi::HdrMapping& hdr, const EvalOptions& o,
                           std::string& frames_csv, bool best_gain = false) {
  const gi::GiInputConfig& cfg = g.inputs;
  NoGradGuard ng;
  const std::string label = detail::label_of(path) + (o.mirror_average ? " mirror-avg" : "") +
                            (low ? " @" + std::to_string(o.upsample_from) + " guided" : "") +
                            (best_gain ? " x best gain" : "");
  EvalRow row = score(
      label, gi::mode_name(cfg.mode), frames, hdr, o,
      [&](const gi::GiSample& s) {
        const gi::GiSample& f = low ? low->of(s) : s;
        Tensor<float> light = model_light(g, f, o.bn_batch_stats, o.dropout_on, o.mirror_average);
        if (low) light = gi::upsampled_light(light, f, s);
        return best_gain ? best_gain_light(std::move(light), s) : light;
      },
      frames_csv);
  row.ceiling = best_gain;
  return row;
}

inline std::vector<EvalRow> evaluate_gi(const EvalOptions& o) {
  if (o.models.empty()) throw std::invalid_argument("eval-gi: no --model given");
  std::filesystem::create_directories(o.out + "/previews");
  // Every model read once, before any frame: a bad blob stops the run at once.
  std::vector<gi::LoadedGenerator> generators;
  for (const auto& path : o.models) generators.push_back(gi::load_generator(path));
  // The second render's folder listed before any frame too.
  std::optional<SecondRender> second;
  if (!o.second_render.empty()) second.emplace(o.second_render);
  // The ambient term is fitted on the scenes the models trained on: train/ without the
  // validation scenes the first model's run carved out (the models of one table are
  // trained on the same data, so they share them).
  const EvalSplits e = open_eval_splits(o, generators.front().inputs.validation_fraction);
  std::vector<EvalRow> rows;
  std::string frames_csv =
      "model,mode,frame,scene,front_direct_share,offscreen_lit,mse,psnr,ssim,mse_linear,psnr_linear,ssim_linear,flip,"
      "grad_error\n";
  size_t unlit_frames = 0;
  // One mapping scores every row, or mapped-space numbers would not compare: the first
  // model's (models trained on the same split fit the same scale).
  const gi::HdrMapping hdr(generators.front().inputs.norm.hdr_scale);
  for (size_t m = 0; m < o.models.size(); ++m) {
    const gi::GiInputConfig& cfg = generators[m].inputs;
    const GiItemReader rd{cfg.mode, o.size > 0 ? o.size : cfg.size};
    auto frames = load_samples(*e.scored, rd, cfg, o.max_frames, "eval-gi " + detail::label_of(o.models[m]), o.quiet);
    unlit_frames = set_aside_unlit(frames, o);
    // The references use the first model's data (same frames and size).
    std::optional<LowFrames> low;
    if (o.upsample_from > 0) low = load_low_frames(e, cfg, o);
    if (m == 0) {
      score_references(e, rd, cfg, frames, hdr, o, rows, frames_csv);
      if (low) rows.push_back(score_upsampled_truth(*low, frames, hdr, o, frames_csv));
      if (second) score_second_render(*second, rd, cfg, low ? &*low : nullptr, frames, hdr, o, rows, frames_csv);
    }
    rows.push_back(score_model(o.models[m], generators[m], low ? &*low : nullptr, frames, hdr, o, frames_csv));
    if (o.best_gain)
      rows.push_back(score_model(o.models[m], generators[m], low ? &*low : nullptr, frames, hdr, o, frames_csv,
                                 /*best_gain=*/true));
  }
  write_eval_report(rows, o, e.scored->size(), unlit_frames, frames_csv);
  return rows;
}

}  // namespace nns::runs