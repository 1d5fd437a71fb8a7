#pragma once
// eval-ao's job: every AO method at every sample count on every view of a dataset, timed
// and scored against the ray-traced AO — the paper's Table 1 and Figure 4 for this data.
//
//   eval-ao --data DIR --model nnao.blob --out DIR [--methods NNAO,SSAO,...] [--threads 2]
//   eval-ao --data DIR --ladder LADDER --out DIR     (every rung of a trained NNAO ladder)
//
// DIR is a split folder or a flat folder; a dataset root with train/ + test/ means its
// test/ split. Writes results.csv, results_by_scene.csv, results_by_family.csv,
// failure_bands.csv, temporal.csv, timing.csv, pareto.csv, speed_vs_accuracy.svg/.png,
// flicker_vs_time.svg, previews/, report.md and report.html.
// Temporal stability is measured on camera-path frames (files "<scene>-pNN-fNNN.exr", or
// surround frame folders of that name, as render-dataset --path-frames writes them),
// reprojected: classical_ao/temporal.h.
//
// Timing is the same for every method: the same frames, the same thread pool, the same
// loop; each method's wall time and the CPU time of the caller and the pool's workers
// (pool_cpu_ms) are kept per view, and their ratio (the threads a method really kept
// busy) is in timing.csv and the report.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/atomic_file.h"
#include "core/progress.h"
#include "core/thread_pool.h"
#include "report/chart.h"
#include "report/csv_field.h"
#include "data/dataset.h"
#include "data/exr_io.h"
#include "data/validate.h"
#include "report/image_metrics.h"
#include "report/image_write.h"
#include "report/html_report.h"
#include "runs/ao/ao_previews.h"
#include "runs/ao/ao_pareto.h"
#include "runs/ao/nnao_ladder.h"
#include "classical_ao/failure_bands.h"
#include "classical_ao/methods.h"
#include "classical_ao/params.h"
#include "classical_ao/temporal.h"
#include "models/nnao/nnao_inference.h"
#include "models/nnao/nnao_inference_reference.h"

namespace nns::runs {

namespace fs = std::filesystem;

struct Score {  // pooled over pixels: squared error sum and count; SSIM summed per view
  double se = 0, ssim_sum = 0;
  int64_t pixels = 0, views = 0;
  void add(double se_view, int64_t px, double ssim) {
    se += se_view * double(px);
    pixels += px;
    ssim_sum += ssim;
    ++views;
  }
  double mse() const { return pixels ? se / double(pixels) : std::nan(""); }
  double ssim() const { return views ? ssim_sum / double(views) : std::nan(""); }
};

struct MethodStats {
  std::vector<double> ms, cpu_ms;  // wall and CPU time (caller and workers, pool_cpu_ms) per view
  Score all;
  std::map<std::string, Score> by_scene, by_family;
  std::map<std::string, classical_ao::TemporalStats> temporal_by_family;
  std::vector<Score> bands;
  classical_ao::TemporalStats temporal;
  std::vector<float> previous;  // this method's AO on the previous view
};

inline double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

inline std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

struct EvalAoOptions {
  std::string data_dir;  // a split folder, a flat folder, or a root with test/
  std::string model;     // nnao.blob; empty: classical methods only
  std::string ladder;    // a trained ladder's folder (train-nnao --ladder): every rung as NNAO-exact
  std::string out = "eval-out";
  std::string methods = "NNAO-exact,NNAO,SSAO,SSAO+,HBAO,Alchemy,GTAO";
  std::vector<int> nnao_samples = {16, 32, 64, 128, 256};
  int threads = 2, previews = 3, max_views = 0, repeat = 3;
  std::string params_file;     // tune-classical-ao's output; empty: built-in parameters
  bool scalar = false;         // the scalar reference loops instead of the vectorised ones
  std::string split = "test";  // "test", or "holdout": the families render-dataset held out
  // > 0: every method also runs with temporal accumulation ("<method>+TA"): on a camera
  // path, out_t = a * m_t + (1 - a) * out_t-1 reprojected (temporal.h), the raw m_t where
  // the previous frame does not see the point — the history blend engines run with TAA.
  double temporal_blend = 0;
  // Shader-style NNAO's jitter pattern changes with the frame number of a camera-path
  // frame (as engines vary their noise per frame under TAA); off: one fixed pattern.
  bool vary_pattern = false;
};

// The views of the split to evaluate and a sentence saying what they are.
struct EvalViews {
  std::vector<std::string> files;
  std::string note;
};

inline EvalViews open_split(const EvalAoOptions& o) {
  data::DatasetListing d = data::list_dataset(o.data_dir);
  if (o.split == "holdout" && !d.has_holdout)
    throw std::runtime_error(o.data_dir + ": no holdout/ split (render-dataset --holdout-families makes one)");
  const data::SplitListing& split = o.split == "holdout" ? d.holdout : d.flat ? d.train : d.test;
  EvalViews v{split.views, o.split == "holdout" ? d.holdout.dir + " (the held-out families: never in train/ or test/)"
                           : d.flat             ? o.data_dir
                                                : (d.test.dir + " (the test split)")};
  // Surround (cube) frames: their front faces, in path order — camera-path data, where
  // the temporal check means something.
  for (auto& f : split.frames)
    if (!f.faces[size_t(data::Face::front)].empty()) v.files.push_back(f.faces[size_t(data::Face::front)]);
  if (v.files.size() > split.views.size()) v.note += ", front faces of surround frames";
  if (v.files.empty()) throw std::runtime_error(o.data_dir + ": no views (*.exr) to evaluate");
  if (o.max_views > 0 && int(v.files.size()) > o.max_views) v.files.resize(size_t(o.max_views));
  return v;
}

// What the methods run with: the NNAO models (one, or a ladder's rungs), the classical
// parameters, and the current view's jitter seed (vary_pattern).
struct MethodInputs {
  std::vector<nnao::NnaoWeights> models;
  std::vector<std::string> model_settings;  // the rungs' names; empty for a single model
  classical_ao::ClassicalParams classical;
  uint32_t pattern_seed = 0;
};

// The methods to run, in order: NNAO (exact, then shader-style), then the classical ones
// at each of their sample counts, then (temporal_blend > 0) every one's "+TA" form;
// accumulated[m] is the index of method m's "+TA" row, or -1.
struct MethodList {
  std::vector<Method> methods;
  std::vector<int> accumulated;
};

inline MethodList build_methods(const EvalAoOptions& o, MethodInputs& in) {
  std::set<std::string> wanted;
  for (auto& m : split_commas(o.methods)) wanted.insert(m);
  const bool have_model = !in.models.empty();
  for (auto& w : wanted) {
    bool known = w == "NNAO" || w == "NNAO-exact";
    for (auto& c : classical_ao::classical_methods()) known |= c.name == w;
    if (!known)
      throw std::invalid_argument("--methods: unknown method '" + w +
                                  "' (known: NNAO-exact, NNAO, SSAO, SSAO+, HBAO, Alchemy, GTAO)");
    if ((w == "NNAO" || w == "NNAO-exact") && !have_model)
      throw std::invalid_argument("--methods " + w + " needs --model nnao.blob or --ladder DIR");
  }
  MethodList list;
  auto& methods = list.methods;
  const bool scalar = o.scalar;
  if (wanted.count("NNAO-exact"))
    for (size_t k = 0; k < in.models.size(); ++k) {
      const nnao::NnaoWeights* w = &in.models[k];
      Method m{"NNAO-exact", w->input.samples(), [w, scalar](const screen_space::GBuffer& g, float* out) {
                 if (scalar) nnao::infer_exact_reference(*w, g, out);
                 else nnao::infer_exact(*w, g, out);
               }};
      if (!in.model_settings.empty()) m.setting = in.model_settings[k];
      methods.push_back(m);
    }
  // A horizon model has no shader-style form (nnao_inference.h): its exact form is all
  // there is, so "NNAO" adds nothing for it.
  if (wanted.count("NNAO") && in.models.size() == 1 && !in.models[0].input.is_horizon())
    for (int n : o.nnao_samples) {
      const nnao::NnaoWeights* w = &in.models[0];
      nnao::check_sample_count(n, w->input);
      uint32_t* seed = &in.pattern_seed;
      methods.push_back({"NNAO", n, [w, seed, n, scalar](const screen_space::GBuffer& g, float* out) {
                           if (scalar) nnao::infer_shader_style_reference(*w, g, n, out, true, *seed);
                           else nnao::infer_shader_style(*w, g, n, out, true, *seed);
                         }});
    }
  for (auto& c : classical_ao::classical_methods())
    if (wanted.count(c.name))
      for (int n : c.sample_counts) {
        const classical_ao::ClassicalParams* p = &in.classical;
        methods.push_back({c.name, n, [&c, p, n, scalar](const screen_space::GBuffer& g, float* out) {
                             classical_ao::run_classical(c.name, *p, g, n, out, scalar);
                           }});
      }
  // The accumulated forms: scored from their method's output, frame by frame (no run of
  // their own).
  if (!(o.temporal_blend >= 0 && o.temporal_blend <= 1))
    throw std::invalid_argument("--temporal-blend must be in [0, 1] (0: off)");
  list.accumulated.assign(methods.size(), -1);
  if (o.temporal_blend > 0) {
    const size_t n = methods.size();
    for (size_t m = 0; m < n; ++m) {
      list.accumulated[m] = int(methods.size());
      methods.push_back({methods[m].name + "+TA", methods[m].samples, nullptr, methods[m].setting});
    }
  }
  return list;
}

// Everything measured over the views: per method its times and scores; the ground
// truth's own flicker; the failure bands' names and the frame size.
struct Evaluation {
  MethodList list;
  std::vector<MethodStats> stats;
  std::vector<std::string> band_names;
  classical_ao::TemporalStats gt_temporal;
  std::map<std::string, classical_ao::TemporalStats> gt_temporal_by_family;
  int width = 0, height = 0;
};

// One view's ground truth, masks and camera-path link, shared by every method's score.
struct ViewScoring {
  const data::View& view;
  const screen_space::GBuffer& g;
  const std::vector<float>& gt;
  std::vector<uint8_t> mask;
  classical_ao::FailureBands bands;
  std::vector<int64_t> band_pixels;  // per failure band, counted once per view
  int64_t px = 0;                    // non-sky pixels
  bool on_path = false, same_path = false;
  std::vector<int64_t> to_prev;
  const float* prev_gt = nullptr;

  // One output of a method (or of its accumulated form) on this view: its scores, its
  // flicker against the previous frame, and the frame kept for the next.
  void score(MethodStats& st, const std::vector<float>& res) const {
    const std::string family = data::scene_family_of(view.scene);
    const double mse = report::masked_mse(res.data(), gt.data(), mask.data(), g.pixels());
    const double ssim = report::masked_ssim(res.data(), gt.data(), mask.data(), g.width, g.height);
    if (px > 0) {
      st.all.add(mse, px, ssim);
      st.by_scene[view.scene].add(mse, px, ssim);
      st.by_family[family].add(mse, px, ssim);
    }
    for (size_t b = 0; b < bands.masks.size(); ++b)
      if (band_pixels[b])
        st.bands[b].add(report::masked_mse(res.data(), gt.data(), bands.masks[b].data(), g.pixels()), band_pixels[b],
                        0);
    if (same_path && !st.previous.empty()) {
      st.temporal.add_pair(to_prev, res.data(), st.previous.data(), gt.data(), prev_gt);
      st.temporal_by_family[family].add_pair(to_prev, res.data(), st.previous.data(), gt.data(), prev_gt);
    }
  }
};

// Runs method m `repeat` times on g and keeps the fastest wall and CPU time (the run
// least disturbed by other processes; the output is the same every time).
inline void timed_run(const Method& m, const screen_space::GBuffer& g, int repeat, float* out, double& ms,
                      double& cpu) {
  ms = 1e300, cpu = 1e300;
  for (int k = 0; k < repeat; ++k) {
    const double c0 = pool_cpu_ms();
    const auto t0 = std::chrono::steady_clock::now();
    m.run(g, out);
    ms = std::min(ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    cpu = std::min(cpu, pool_cpu_ms() - c0);
  }
}

inline Evaluation evaluate_views(const EvalAoOptions& o, const std::vector<std::string>& views, MethodInputs& in) {
  Evaluation ev;
  ev.list = build_methods(o, in);
  const std::vector<Method>& methods = ev.list.methods;
  ev.stats.resize(methods.size());
  for (auto& s : ev.stats) s.bands.resize(3);
  data::View prev_view;  // the previous view, while it is a frame of a camera path
  std::string prev_path;
  int prev_frame = -2;
  Progress bar("eval-ao", int64_t(views.size() * (o.temporal_blend > 0 ? methods.size() / 2 : methods.size())));
  int64_t done = 0;
  for (size_t v = 0; v < views.size(); ++v) {
    data::View view = data::read_view(views[v]);
    if (!view.has("AO"))
      throw std::runtime_error(views[v] + ": missing channel 'AO' (eval-ao scores against ground-truth AO)");
    const screen_space::GBuffer g = screen_space::gbuffer_from_view(view);
    ev.width = g.width, ev.height = g.height;
    ViewScoring sc{view, g, view.channel("AO"), std::vector<uint8_t>(size_t(g.pixels())),
                   classical_ao::failure_bands(g)};
    for (int64_t i = 0; i < g.pixels(); ++i) sc.mask[size_t(i)] = !g.sky(i);
    sc.px = std::count(sc.mask.begin(), sc.mask.end(), uint8_t(1));
    ev.band_names = sc.bands.names;
    for (auto& bm : sc.bands.masks) sc.band_pixels.push_back(std::count(bm.begin(), bm.end(), uint8_t(1)));
    int frame = -1;
    const std::string path = camera_path_of(views[v], frame);
    sc.on_path = !path.empty();
    sc.same_path = sc.on_path && path == prev_path && frame == prev_frame + 1;
    in.pattern_seed = o.vary_pattern && sc.on_path ? uint32_t(frame) : 0u;
    if (sc.same_path) {
      sc.to_prev = classical_ao::reproject_to_previous(
          g, view.world_to_camera, screen_space::gbuffer_from_view(prev_view), prev_view.world_to_camera);
      sc.prev_gt = prev_view.channel("AO").data();
      const float* gt = sc.gt.data();
      ev.gt_temporal.add_pair(sc.to_prev, gt, sc.prev_gt, gt, sc.prev_gt);
      ev.gt_temporal_by_family[data::scene_family_of(view.scene)].add_pair(sc.to_prev, gt, sc.prev_gt, gt, sc.prev_gt);
    }
    std::vector<float> result(size_t(g.pixels())), history(result.size());
    for (size_t m = 0; m < methods.size(); ++m) {
      if (!methods[m].run) continue;  // an accumulated form: scored with its method below
      double ms, cpu;
      timed_run(methods[m], g, o.repeat, result.data(), ms, cpu);
      MethodStats& st = ev.stats[m];
      st.ms.push_back(ms);
      st.cpu_ms.push_back(cpu);
      sc.score(st, result);
      if (sc.on_path) st.previous = result;
      if (const int a = ev.list.accumulated[m]; a >= 0) {
        MethodStats& ta = ev.stats[size_t(a)];
        const auto t0 = std::chrono::steady_clock::now();
        const bool blend = sc.same_path && !ta.previous.empty();
        const float w = float(o.temporal_blend);
        for (size_t i = 0; i < result.size(); ++i) {
          const int64_t j = blend ? sc.to_prev[i] : -1;
          history[i] = j >= 0 ? w * result[i] + (1 - w) * ta.previous[size_t(j)] : result[i];
        }
        const double blend_ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        ta.ms.push_back(ms + blend_ms);
        ta.cpu_ms.push_back(cpu + blend_ms);
        sc.score(ta, history);
        if (sc.on_path) ta.previous = history;
      }
      bar.update(++done, methods[m].name + "@" + methods[m].label());
    }
    if (sc.on_path) prev_view = std::move(view);
    prev_path = path;
    prev_frame = frame;
  }
  bar.finish();
  return ev;
}

// Each method's setting of lowest MSE over all views (by method name).
inline std::map<std::string, size_t> best_settings(const Evaluation& ev) {
  std::map<std::string, size_t> best;
  const auto& methods = ev.list.methods;
  for (size_t m = 0; m < methods.size(); ++m) {
    auto it = best.find(methods[m].name);
    if (it == best.end() || ev.stats[m].all.mse() < ev.stats[it->second].all.mse()) best[methods[m].name] = m;
  }
  return best;
}

// The method names in the order they first appear.
inline std::vector<std::string> method_order(const Evaluation& ev) {
  std::vector<std::string> order;
  for (auto& m : ev.list.methods)
    if (std::find(order.begin(), order.end(), m.name) == order.end()) order.push_back(m.name);
  return order;
}

// results*.csv, failure_bands.csv, temporal.csv, timing.csv; returns results.csv's text.
inline std::string write_tables(const EvalAoOptions& o, const Evaluation& ev) {
  const auto& methods = ev.list.methods;
  std::string csv = "method,samples,ms_per_frame,mse,ssim,psnr,setting\n",
              by_scene = "method,samples,scene,views,mse,ssim,psnr\n";
  std::string band_csv = "method,samples,band,pixels,mse\n",
              temporal =
                  "method,samples,flicker,ground_truth_flicker,flicker_relative_to_ground_truth,temporal_error,pairs,"
                  "coverage\n";
  // threads_used: CPU time over wall time, the cores a method kept busy (timing is fair
  // only if every method uses the threads it is given).
  std::string timing = "method,samples,wall_ms_median,cpu_ms_median,threads,threads_used,setting\n";
  for (size_t m = 0; m < methods.size(); ++m) {
    const auto& st = ev.stats[m];
    const std::string nm = report::csv_field(methods[m].name), ns = std::to_string(methods[m].samples);
    const double ms = median(st.ms), mse = st.all.mse();
    csv += nm + "," + ns + "," + fmt(ms, 5) + "," + fmt(mse) + "," + fmt(st.all.ssim()) + "," +
           fmt(report::psnr_from_mse(mse), 5) + "," + report::csv_field(methods[m].setting) + "\n";
    for (auto& [scene, sc] : st.by_scene)
      by_scene += nm + "," + ns + "," + report::csv_field(scene) + "," + std::to_string(sc.views) + "," +
                  fmt(sc.mse()) + "," + fmt(sc.ssim()) + "," + fmt(report::psnr_from_mse(sc.mse()), 5) + "\n";
    for (size_t b = 0; b < st.bands.size(); ++b)
      band_csv += nm + "," + ns + "," + ev.band_names[b] + "," + std::to_string(st.bands[b].pixels) + "," +
                  fmt(st.bands[b].mse()) + "\n";
    if (st.temporal.pairs) {
      const double f = st.temporal.flicker(), gf = ev.gt_temporal.flicker();
      temporal += nm + "," + ns + "," + fmt(f) + "," + fmt(gf) + "," + (gf > 0 ? fmt(f / gf, 4) : std::string("nan")) +
                  "," + fmt(st.temporal.error()) + "," + std::to_string(st.temporal.pairs) + "," +
                  fmt(st.temporal.coverage(), 4) + "\n";
    }
    const double cpu = median(st.cpu_ms);
    timing += nm + "," + ns + "," + fmt(ms, 5) + "," + fmt(cpu, 5) + "," + std::to_string(o.threads) + "," +
              fmt(cpu / ms, 3) + "," + report::csv_field(methods[m].setting) + "\n";
  }
  write_file_atomic((fs::path(o.out) / "results.csv").string(), csv);
  write_file_atomic((fs::path(o.out) / "results_by_scene.csv").string(), by_scene);
  write_file_atomic((fs::path(o.out) / "failure_bands.csv").string(), band_csv);
  write_file_atomic((fs::path(o.out) / "temporal.csv").string(), temporal);
  write_file_atomic((fs::path(o.out) / "timing.csv").string(), timing);
  return csv;
}

// results_by_family.csv and its table for the report: each method at its best setting.
inline report::Table write_family_table(const EvalAoOptions& o, const Evaluation& ev) {
  const auto best = best_settings(ev);
  std::string by_family = "family,method,samples,views,mse,ssim,flicker,ground_truth_flicker\n";
  report::Table table{{"family", "method", "samples", "MSE", "SSIM", "flicker (x ground truth)"}, {}};
  std::set<std::string> families;
  for (auto& st : ev.stats)
    for (auto& [fam, sc] : st.by_family) families.insert(fam);
  for (auto& fam : families)
    for (auto& n : method_order(ev)) {
      const size_t m = best.at(n);
      const MethodStats& st = ev.stats[m];
      auto sc = st.by_family.find(fam);
      if (sc == st.by_family.end()) continue;
      auto t = st.temporal_by_family.find(fam);
      auto gt = ev.gt_temporal_by_family.find(fam);
      const bool has_t = t != st.temporal_by_family.end() && t->second.pairs && gt != ev.gt_temporal_by_family.end();
      const double f = has_t ? t->second.flicker() : std::nan(""), gf = has_t ? gt->second.flicker() : std::nan("");
      const std::string label = ev.list.methods[m].label();
      by_family += fam + "," + n + "," + std::to_string(ev.list.methods[m].samples) + "," +
                   std::to_string(sc->second.views) + "," + fmt(sc->second.mse()) + "," + fmt(sc->second.ssim()) + "," +
                   fmt(f) + "," + fmt(gf) + "\n";
      table.rows.push_back({fam, n, label, fmt(sc->second.mse(), 4), fmt(sc->second.ssim(), 4),
                            has_t ? fmt(f / gf, 3) : std::string("-")});
    }
  write_file_atomic((fs::path(o.out) / "results_by_family.csv").string(), by_family);
  return table;
}

// speed_vs_accuracy.svg and flicker_vs_time.svg: a method's settings as one curve (an
// NNAO ladder's rungs too), its "+TA" form dashed in its colour. Returns the charts'
// notes (empty when rasterised).
struct ChartNotes {
  std::string accuracy, flicker;
  bool has_flicker = false;
};

inline ChartNotes write_charts(const EvalAoOptions& o, const Evaluation& ev) {
  const auto& methods = ev.list.methods;
  std::map<std::string, report::ChartSeries> series, flicker_series;
  const std::vector<std::string> order = method_order(ev);
  // Each method's points in order of time, so that a curve (an NNAO ladder too) reads
  // left to right.
  std::vector<size_t> by_time(methods.size());
  for (size_t m = 0; m < methods.size(); ++m) by_time[m] = m;
  std::stable_sort(by_time.begin(), by_time.end(),
                   [&](size_t a, size_t b) { return median(ev.stats[a].ms) < median(ev.stats[b].ms); });
  for (size_t m : by_time) {
    const auto& st = ev.stats[m];
    const std::string& nm = methods[m].name;
    series[nm].name = nm;
    series[nm].x.push_back(median(st.ms));
    series[nm].y.push_back(st.all.mse());
    series[nm].point_labels.push_back(methods[m].label());
    if (st.temporal.pairs && ev.gt_temporal.flicker() > 0) {
      auto& fs_ = flicker_series[nm];
      fs_.name = nm;
      fs_.x.push_back(median(st.ms));
      fs_.y.push_back(st.temporal.flicker() / ev.gt_temporal.flicker());
      fs_.point_labels.push_back(methods[m].label());
    }
  }
  for (size_t m = 0; m < ev.list.accumulated.size(); ++m) {  // the methods that run (the +TA rows follow)
    if (ev.list.accumulated[m] < 0) continue;
    const std::string& ta = methods[size_t(ev.list.accumulated[m])].name;
    const int colour = int(std::find(order.begin(), order.end(), methods[m].name) - order.begin());
    // Dashed in the method's colour, without point labels: its settings are the solid
    // curve's, and a ladder's names printed twice crowded the chart.
    for (auto* s : {&series, &flicker_series})
      if (s->count(ta)) (*s)[ta].colour = colour, (*s)[ta].dashed = true, (*s)[ta].point_labels.clear();
  }
  std::vector<report::ChartSeries> chart, flicker_chart;
  for (auto& n : order) {
    chart.push_back(series[n]);
    if (flicker_series.count(n)) flicker_chart.push_back(flicker_series[n]);
  }
  report::ChartOptions co;
  co.title = "AO: error against time (" + std::to_string(ev.width) + "x" + std::to_string(ev.height) + ", " +
             std::to_string(o.threads) + " threads)";
  co.x_label = "ms per frame (median over views)";
  co.y_label = "MSE vs ray-traced AO (non-sky pixels)";
  co.log_x = true;
  ChartNotes notes;
  notes.accuracy = report::write_chart((fs::path(o.out) / "speed_vs_accuracy.svg").string(), chart, co);
  if (!notes.accuracy.empty()) std::fprintf(stderr, "eval-ao: note: %s\n", notes.accuracy.c_str());
  // The second chart: flicker (relative to the ground truth's, 1 = as stable as the
  // truth) against the same time axis, for the methods measured on camera paths.
  if (!flicker_chart.empty()) {
    notes.has_flicker = true;
    report::ChartOptions fo = co;
    fo.title = "AO: flicker against time (camera paths, reprojected)";
    fo.y_label = "flicker / ground truth's flicker";
    notes.flicker = report::write_chart((fs::path(o.out) / "flicker_vs_time.svg").string(), flicker_chart, fo);
    if (!notes.flicker.empty()) std::fprintf(stderr, "eval-ao: note: %s\n", notes.flicker.c_str());
  }
  return notes;
}

// pareto.csv and its report section: every method's every setting (the "+TA" forms
// aside) on the speed/accuracy front or not, and which NNAO setting beats each
// classical setting at no more wall time (runs/ao/ao_pareto.h).
inline std::vector<ParetoRow> write_pareto(const EvalAoOptions& o, const Evaluation& ev) {
  std::vector<ParetoRow> rows;
  const auto& methods = ev.list.methods;
  for (size_t m = 0; m < methods.size(); ++m) {
    if (!methods[m].run) continue;
    const auto& st = ev.stats[m];
    rows.push_back({methods[m].name, methods[m].label(), median(st.ms), median(st.cpu_ms), st.all.mse(), st.all.ssim(),
                    st.temporal.pairs && ev.gt_temporal.flicker() > 0 ? st.temporal.flicker() / ev.gt_temporal.flicker()
                                                                      : std::nan("")});
  }
  mark_front_and_wins(rows);
  write_file_atomic((fs::path(o.out) / "pareto.csv").string(), pareto_csv(rows));
  return rows;
}

// The claims of the paper on this data, checked: NNAO's error below every classical
// method's (its most accurate setting), and shader-style NNAO-64 against HBAO-64.
inline std::vector<std::string> paper_claims(const Evaluation& ev) {
  const auto& methods = ev.list.methods;
  auto find = [&](const std::string& n, int s) -> int {
    for (size_t m = 0; m < methods.size(); ++m)
      if (methods[m].name == n && methods[m].samples == s) return int(m);
    return -1;
  };
  std::vector<std::string> claims;
  const auto best = best_settings(ev);
  if (auto ex = best.find("NNAO-exact"); ex != best.end()) {
    const double nnao_mse = ev.stats[ex->second].all.mse();
    std::string beaten_by;
    for (size_t m = 0; m < methods.size(); ++m)
      if (methods[m].name.rfind("NNAO", 0) != 0 && ev.stats[m].all.mse() <= nnao_mse)
        beaten_by += " " + methods[m].name + "@" + methods[m].label();
    claims.push_back(
        "NNAO (exact" + (methods[ex->second].setting.empty() ? std::string() : ", " + methods[ex->second].setting) +
        ", MSE " + fmt(nnao_mse, 4) + ") has lower MSE than every classical method at every sample count: **" +
        (beaten_by.empty() ? "holds**." : "does not hold** (not lower than:" + beaten_by + ")."));
  }
  int n64 = find("NNAO", 64), h64 = find("HBAO", 64);
  if (n64 >= 0 && h64 >= 0) {
    double nm = median(ev.stats[size_t(n64)].ms), hm = median(ev.stats[size_t(h64)].ms);
    double ne = ev.stats[size_t(n64)].all.mse(), he = ev.stats[size_t(h64)].all.mse();
    claims.push_back("Shader-style NNAO at 64 samples (" + fmt(nm, 4) + " ms, MSE " + fmt(ne, 4) + ") vs HBAO at 64 (" +
                     fmt(hm, 4) + " ms, MSE " + fmt(he, 4) + "): faster **" + (nm < hm ? "yes" : "no") +
                     "**, more accurate **" + (ne < he ? "yes" : "no") + "**.");
  }
  return claims;
}

// report.md and report.html: the previews, the charts, the tables, the claims checked,
// the front, the bands, the families and the temporal stability.
inline void write_report(const EvalAoOptions& o, const Evaluation& ev, const EvalViews& views, MethodInputs& in,
                         const ChartNotes& notes, const std::vector<ParetoRow>& front) {
  const auto& methods = ev.list.methods;
  std::vector<Method> shown;  // each method at its best setting; the accumulated forms need a path's history
  const auto best = best_settings(ev);
  for (auto& n : method_order(ev))
    if (methods[best.at(n)].run) shown.push_back(methods[best.at(n)]);
  const auto comparisons = write_ao_previews(views.files, o.previews, shown, o.out, [&](const std::string& view_file) {
    int frame = -1;
    const bool on_path = !camera_path_of(view_file, frame).empty();
    in.pattern_seed = o.vary_pattern && on_path ? uint32_t(frame) : 0u;
  });
  report::Report r("AO evaluation");
  r.text("Data: " + views.note + " — " + std::to_string(views.files.size()) + " views at " + std::to_string(ev.width) +
         "x" + std::to_string(ev.height) + ", " + std::to_string(o.threads) +
         " threads, classical parameters: " + (o.params_file.empty() ? std::string("built-in") : o.params_file) +
         ". Errors over non-sky pixels against the ray-traced `AO` channel; ms per frame is the median over views of "
         "the fastest of " +
         std::to_string(o.repeat) +
         " runs per view, every method on the same frames through the "
         "same thread pool.");
  if (!comparisons.empty()) {
    r.heading("Previews")
        .text(
            "The ray-traced AO, each method at its best setting (lowest MSE over all views; the "
            "+TA forms are left out: they need a camera path's history) and its error heat-map "
            "(black 0, white 0.5), with the view's MSE and SSIM. PNGs in previews/.");
    for (auto& c : comparisons) r.comparison(c);
  }
  r.heading("Speed against accuracy");
  r.chart("speed_vs_accuracy.svg", "speed vs accuracy", notes.accuracy);
  report::Table results{{"method", "setting", "ms/frame", "CPU ms/frame", "threads used", "MSE", "SSIM", "PSNR"}, {}};
  for (size_t m = 0; m < methods.size(); ++m) {
    const double ms = median(ev.stats[m].ms), cpu = median(ev.stats[m].cpu_ms);
    results.rows.push_back({methods[m].name, methods[m].label(), fmt(ms, 4), fmt(cpu, 4), fmt(cpu / ms, 3),
                            fmt(ev.stats[m].all.mse(), 4), fmt(ev.stats[m].all.ssim(), 4),
                            fmt(report::psnr_from_mse(ev.stats[m].all.mse()), 4)});
  }
  r.table(results);
  add_pareto_section(r, front);
  r.heading("The paper's claims on this data");
  const auto claims = paper_claims(ev);
  if (claims.empty()) r.text("Not checked: they need NNAO-exact, or NNAO and HBAO at 64 samples.");
  else r.list(claims);
  r.heading("Failure bands (MSE)")
      .text(
          "halo: within 3 px of a depth discontinuity; border: within 8% of the width of the screen edge; thin: "
          "surfaces under 6 px across. See failure_bands.csv.");
  report::Table band_table{{"method", "setting"}, {}};
  for (auto& b : ev.band_names) band_table.header.push_back(b);
  for (size_t m = 0; m < methods.size(); ++m) {
    band_table.rows.push_back({methods[m].name, methods[m].label()});
    for (auto& b : ev.stats[m].bands) band_table.rows.back().push_back(fmt(b.mse(), 4));
  }
  r.table(band_table).heading("Per family");
  r.text(
      "Each method at its setting of lowest MSE over all views; flicker relative to the ground truth's on the "
      "family's camera-path frames. See results_by_family.csv.");
  r.table(write_family_table(o, ev));
  r.text(
      "Per scene: results_by_scene.csv. CPU ms (the CPU time of every thread of the pool, each read from its own "
      "clock, median over views): timing.csv.");
  r.heading("Temporal stability")
      .text(
          "On camera-path frames (files `<scene>-pNN-fNNN.exr`), each frame reprojected to the one before it "
          "(worldToCamera; disocclusions and off-screen points skipped). flicker = mean |m_t - m_t-1| over the mapped "
          "pixels; temporal error = mean |(m_t - m_t-1) - (g_t - g_t-1)| against the ground truth g. See "
          "temporal.csv.");
  if (ev.gt_temporal.pairs) {
    r.text("Ground truth flicker " + fmt(ev.gt_temporal.flicker(), 4) + " over " +
           std::to_string(ev.gt_temporal.pairs) + " frame pairs (" + fmt(100 * ev.gt_temporal.coverage(), 3) +
           "% of pixels mapped).");
    if (notes.has_flicker) r.chart("flicker_vs_time.svg", "flicker vs time", notes.flicker);
    report::Table t_table{{"method", "setting", "flicker", "relative to ground truth", "temporal error"}, {}};
    for (size_t m = 0; m < methods.size(); ++m) {
      const auto& t = ev.stats[m].temporal;
      if (t.pairs)
        t_table.rows.push_back({methods[m].name, methods[m].label(), fmt(t.flicker(), 4),
                                fmt(t.flicker() / ev.gt_temporal.flicker(), 4), fmt(t.error(), 4)});
    }
    r.table(t_table);
  } else {
    r.text("No camera-path frames in this data, so there is nothing to report (temporal.csv is empty).");
  }
  r.write(o.out);
}

// The NNAO models of the options: one blob, or every rung of a ladder.
inline MethodInputs load_method_inputs(const EvalAoOptions& o) {
  MethodInputs in;
  if (!o.model.empty() && !o.ladder.empty()) throw std::invalid_argument("--model and --ladder: give one of them");
  if (!o.model.empty()) in.models.push_back(nnao::NnaoWeights::load(o.model));
  if (!o.ladder.empty())
    for (const auto& e : runs::read_ladder(o.ladder)) {
      in.models.push_back(nnao::NnaoWeights::load(e.blob));
      in.model_settings.push_back(e.name);
    }
  in.classical =
      o.params_file.empty() ? classical_ao::ClassicalParams{} : classical_ao::read_classical_params(o.params_file);
  return in;
}

inline void evaluate_ao(const EvalAoOptions& o) {
  const EvalViews views = open_split(o);
  MethodInputs in = load_method_inputs(o);
  fs::create_directories(fs::path(o.out) / "previews");
  const Evaluation ev = evaluate_views(o, views.files, in);
  const std::string csv = write_tables(o, ev);
  const ChartNotes notes = write_charts(o, ev);
  const std::vector<ParetoRow> front = write_pareto(o, ev);
  write_report(o, ev, views, in, notes, front);
  std::printf("%s", csv.c_str());
  std::printf("chart: %s%s\nreport: %s (and report.md)\n", (fs::path(o.out) / "speed_vs_accuracy.svg").string().c_str(),
              notes.accuracy.empty() ? " (+ .png)" : "", (fs::path(o.out) / "report.html").string().c_str());
}

}  // namespace nns::runs
