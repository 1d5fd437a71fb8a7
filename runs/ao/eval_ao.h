#pragma once
// eval-ao's job: every AO method at every sample count on every view of a dataset, timed
// and scored against the ray-traced AO — the paper's Table 1 and Figure 4 for this data.
//
//   eval-ao --data DIR --model nnao.blob --out DIR [--methods NNAO,SSAO,...] [--threads 2]
//
// DIR is a split folder or a flat folder; a dataset root with train/ + test/ means its
// test/ split. Writes results.csv, results_by_scene.csv, failure_bands.csv,
// temporal.csv, timing.csv, speed_vs_accuracy.svg/.png, previews/, report.md and report.html.
// Temporal stability is measured on camera-path frames (files "<scene>-pNN-fNNN.exr", or
// surround frame folders of that name, as render-dataset --path-frames writes them),
// reprojected: classical_ao/temporal.h.
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
#include "data/dataset.h"
#include "data/exr_io.h"
#include "report/image_metrics.h"
#include "report/image_write.h"
#include "report/html_report.h"
#include "runs/ao/ao_previews.h"
#include "classical_ao/failure_bands.h"
#include "classical_ao/methods.h"
#include "classical_ao/params.h"
#include "classical_ao/temporal.h"
#include "models/nnao/nnao_inference.h"
#include "models/nnao/nnao_inference_reference.h"

namespace nns::ao_eval {

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
  std::vector<double> ms, cpu_ms;  // wall and process CPU time (all threads) per view
  Score all;
  std::map<std::string, Score> by_scene, by_family;
  std::map<std::string, ao::TemporalStats> temporal_by_family;
  std::vector<Score> bands;
  ao::TemporalStats temporal;
  std::vector<float> previous;  // this method's AO on the previous view
};

// CPU time of the whole process (every worker thread): on a shared machine the wall
// time of a 2-thread call also counts time spent waiting for a core.
double process_cpu_ms() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

// A scene's family: the procedural scenes are named "<family>-<instance>"; other names
// are their own family.
std::string family_of(const std::string& scene) {
  const auto dash = scene.rfind('-');
  if (dash == std::string::npos || dash + 1 == scene.size() ||
      scene.find_first_not_of("0123456789", dash + 1) != std::string::npos)
    return scene;
  return scene.substr(0, dash);
}


struct EvalAoOptions {
  std::string data_dir;         // a split folder, a flat folder, or a root with test/
  std::string model;            // nnao.blob; empty: classical methods only
  std::string out = "eval-out";
  std::string methods = "NNAO-exact,NNAO,SSAO,SSAO+,HBAO,Alchemy,GTAO";
  std::vector<int> nnao_samples = {16, 32, 64, 128, 256};
  int threads = 2, previews = 3, max_views = 0, repeat = 3;
  std::string params_file;      // tune-classical-ao's output; empty: built-in parameters
  bool scalar = false;          // the scalar reference loops instead of the vectorised ones
  std::string split = "test";   // "test", or "holdout": the families render-dataset held out
  // > 0: every method also runs with temporal accumulation ("<method>+TA"): on a camera
  // path, out_t = a * m_t + (1 - a) * out_t-1 reprojected (temporal.h), the raw m_t where
  // the previous frame does not see the point — the history blend engines run with TAA.
  double temporal_blend = 0;
  // Shader-style NNAO's jitter pattern changes with the frame number of a camera-path
  // frame (as engines vary their noise per frame under TAA); off: one fixed pattern.
  bool vary_pattern = false;
};

inline void evaluate_ao(const EvalAoOptions& o) {
  const std::string &data_dir = o.data_dir, &model = o.model, &out = o.out, &methods_flag = o.methods,
                    &params_file = o.params_file;
  const std::vector<int>& nnao_samples = o.nnao_samples;
  const int threads = o.threads, previews = o.previews, max_views = o.max_views, repeat = o.repeat;
  const bool scalar = o.scalar;

  data::DatasetListing d = data::list_dataset(data_dir);
  if (o.split == "holdout" && !d.has_holdout)
    throw std::runtime_error(data_dir + ": no holdout/ split (render-dataset --holdout-families makes one)");
  const data::SplitListing& split = o.split == "holdout" ? d.holdout : d.flat ? d.train : d.test;
  std::vector<std::string> views = split.views;
  std::string split_note = o.split == "holdout" ? d.holdout.dir + " (the held-out families: never in train/ or test/)"
                           : d.flat ? data_dir : (d.test.dir + " (the test split)");
  // Surround (cube) frames: their front faces, in path order — camera-path data, where
  // the temporal check means something.
  for (auto& f : split.frames)
    if (!f.faces[size_t(data::Face::front)].empty()) views.push_back(f.faces[size_t(data::Face::front)]);
  if (views.size() > split.views.size()) split_note += ", front faces of surround frames";
  if (views.empty()) throw std::runtime_error(data_dir + ": no views (*.exr) to evaluate");
  if (max_views > 0 && int(views.size()) > max_views) views.resize(size_t(max_views));

  std::vector<Method> methods;
  std::set<std::string> wanted;
  for (auto& m : split_commas(methods_flag)) wanted.insert(m);
  nnao::NnaoWeights weights;
  bool have_model = !model.empty();
  if (have_model) weights = nnao::NnaoWeights::load(model);
  for (auto& w : wanted) {
    bool known = w == "NNAO" || w == "NNAO-exact";
    for (auto& c : ao::classical_methods()) known |= c.name == w;
    if (!known) throw std::invalid_argument("--methods: unknown method '" + w + "' (known: NNAO-exact, NNAO, SSAO, SSAO+, HBAO, Alchemy, GTAO)");
    if ((w == "NNAO" || w == "NNAO-exact") && !have_model)
      throw std::invalid_argument("--methods " + w + " needs --model nnao.blob");
  }
  if (wanted.count("NNAO-exact"))
    methods.push_back({"NNAO-exact", weights.input.samples(),
                       [&, scalar](const ao::GBuffer& g, float* o) {
                         if (scalar) nnao::infer_exact_reference(weights, g, o);
                         else nnao::infer_exact(weights, g, o);
                       }});
  // A horizon model has no shader-style form (nnao_inference.h): its exact form is all
  // there is, so "NNAO" adds nothing for it.
  uint32_t pattern_seed = 0;  // the current view's jitter seed (vary_pattern)
  if (wanted.count("NNAO") && !weights.input.is_horizon())
    for (int n : nnao_samples) {
      nnao::check_sample_count(n, weights.input);
      methods.push_back({"NNAO", n, [&weights, &pattern_seed, n, scalar](const ao::GBuffer& g, float* o) {
                           if (scalar) nnao::infer_shader_style_reference(weights, g, n, o, true, pattern_seed);
                           else nnao::infer_shader_style(weights, g, n, o, true, pattern_seed);
                         }});
    }
  const ao::ClassicalParams cparams = params_file.empty() ? ao::ClassicalParams{} : ao::read_classical_params(params_file);
  for (auto& c : ao::classical_methods())
    if (wanted.count(c.name))
      for (int n : c.sample_counts)
        methods.push_back({c.name, n, [&c, &cparams, n, scalar](const ao::GBuffer& g, float* o) {
                             ao::run_classical(c.name, cparams, g, n, o, scalar);
                           }});
  // The accumulated forms: scored from their method's output, frame by frame (no run of
  // their own); accumulated[m] is the index of method m's "+TA" row, or -1.
  if (!(o.temporal_blend >= 0 && o.temporal_blend <= 1))
    throw std::invalid_argument("--temporal-blend must be in [0, 1] (0: off)");
  std::vector<int> accumulated(methods.size(), -1);
  if (o.temporal_blend > 0) {
    const size_t n = methods.size();
    for (size_t m = 0; m < n; ++m) {
      accumulated[m] = int(methods.size());
      methods.push_back({methods[m].name + "+TA", methods[m].samples, nullptr});
    }
  }

  fs::create_directories(fs::path(out) / "previews");
  std::vector<MethodStats> stats(methods.size());
  for (auto& s : stats) s.bands.resize(3);
  std::vector<std::string> band_names;
  ao::TemporalStats gt_temporal;
  std::map<std::string, ao::TemporalStats> gt_temporal_by_family;
  data::View prev_view;  // the previous view, while it is a frame of a camera path
  std::string prev_path;
  int prev_frame = -2;
  int width = 0, height = 0;
  Progress bar("eval-ao", int64_t(views.size() * (o.temporal_blend > 0 ? methods.size() / 2 : methods.size())));
  int64_t done = 0;
  for (size_t v = 0; v < views.size(); ++v) {
    data::View view = data::read_view(views[v]);
    if (!view.has("AO"))
      throw std::runtime_error(views[v] + ": missing channel 'AO' (eval-ao scores against ground-truth AO)");
    ao::GBuffer g = ao::gbuffer_from_view(view);
    width = g.width, height = g.height;
    const auto& gt = view.channel("AO");
    std::vector<uint8_t> mask(size_t(g.pixels()));
    for (int64_t i = 0; i < g.pixels(); ++i) mask[size_t(i)] = !g.sky(i);
    ao::FailureBands bands = ao::failure_bands(g);
    band_names = bands.names;
    int frame = -1;
    const std::string path = camera_path_of(views[v], frame);
    const bool same_path = !path.empty() && path == prev_path && frame == prev_frame + 1;
    pattern_seed = o.vary_pattern && !path.empty() ? uint32_t(frame) : 0u;
    std::vector<int64_t> to_prev;
    const float* prev_gt = nullptr;
    if (same_path) {
      to_prev = ao::reproject_to_previous(g, view.world_to_camera, ao::gbuffer_from_view(prev_view),
                                          prev_view.world_to_camera);
      prev_gt = prev_view.channel("AO").data();
      gt_temporal.add_pair(to_prev, gt.data(), prev_gt, gt.data(), prev_gt);
      gt_temporal_by_family[family_of(view.scene)].add_pair(to_prev, gt.data(), prev_gt, gt.data(), prev_gt);
    }
    std::vector<float> result(size_t(g.pixels())), history(result.size());
    const int64_t px = std::count(mask.begin(), mask.end(), uint8_t(1));
    std::vector<int64_t> band_pixels;  // per failure band, counted once per view
    for (auto& bm : bands.masks) band_pixels.push_back(std::count(bm.begin(), bm.end(), uint8_t(1)));
    // One output of a method (or of its accumulated form) on this view: its scores, its
    // flicker against the previous frame, and the frame kept for the next.
    auto score = [&](size_t m, const std::vector<float>& res) {
      MethodStats& st = stats[m];
      double mse = data::masked_mse(res.data(), gt.data(), mask.data(), g.pixels());
      double ssim = data::masked_ssim(res.data(), gt.data(), mask.data(), g.width, g.height);
      if (px > 0) {
        st.all.add(mse, px, ssim);
        st.by_scene[view.scene].add(mse, px, ssim);
        st.by_family[family_of(view.scene)].add(mse, px, ssim);
      }
      for (size_t b = 0; b < bands.masks.size(); ++b)
        if (band_pixels[b]) st.bands[b].add(data::masked_mse(res.data(), gt.data(), bands.masks[b].data(), g.pixels()), band_pixels[b], 0);
      if (same_path && !st.previous.empty()) {
        st.temporal.add_pair(to_prev, res.data(), st.previous.data(), gt.data(), prev_gt);
        st.temporal_by_family[family_of(view.scene)].add_pair(to_prev, res.data(), st.previous.data(), gt.data(), prev_gt);
      }
      if (!path.empty()) st.previous = res;
    };
    for (size_t m = 0; m < methods.size(); ++m) {
      if (!methods[m].run) continue;  // an accumulated form: scored with its method below
      // The fastest of `repeat` runs: the one least disturbed by other processes (the
      // output is the same every time).
      double ms = 1e300, cpu = 1e300;
      for (int k = 0; k < repeat; ++k) {
        const double c0 = process_cpu_ms();
        auto t0 = std::chrono::steady_clock::now();
        methods[m].run(g, result.data());
        ms = std::min(ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        cpu = std::min(cpu, process_cpu_ms() - c0);
      }
      MethodStats& st = stats[m];
      st.ms.push_back(ms);
      st.cpu_ms.push_back(cpu);
      score(m, result);
      if (accumulated[m] >= 0) {
        MethodStats& ta = stats[size_t(accumulated[m])];
        const auto t0 = std::chrono::steady_clock::now();
        const bool blend = same_path && !ta.previous.empty();
        const float a = float(o.temporal_blend);
        for (size_t i = 0; i < result.size(); ++i) {
          const int64_t j = blend ? to_prev[i] : -1;
          history[i] = j >= 0 ? a * result[i] + (1 - a) * ta.previous[size_t(j)] : result[i];
        }
        const double blend_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        ta.ms.push_back(ms + blend_ms);
        ta.cpu_ms.push_back(cpu + blend_ms);
        score(size_t(accumulated[m]), history);
      }
      bar.update(++done, methods[m].name + "@" + std::to_string(methods[m].samples));
    }
    if (!path.empty()) prev_view = std::move(view);
    prev_path = path;
    prev_frame = frame;
  }
  bar.finish();

  std::string csv = "method,samples,ms_per_frame,mse,ssim,psnr\n", by_scene = "method,samples,scene,views,mse,ssim,psnr\n";
  std::string band_csv = "method,samples,band,pixels,mse\n", temporal = "method,samples,flicker,ground_truth_flicker,flicker_relative_to_ground_truth,temporal_error,pairs,coverage\n";
  std::string timing = "method,samples,wall_ms_median,cpu_ms_median,threads\n";
  std::map<std::string, data::ChartSeries> series, flicker_series;
  std::vector<std::string> order;
  for (size_t m = 0; m < methods.size(); ++m) {
    const auto& st = stats[m];
    const std::string nm = methods[m].name, ns = std::to_string(methods[m].samples);
    const double ms = median(st.ms), mse = st.all.mse();
    csv += nm + "," + ns + "," + fmt(ms, 5) + "," + fmt(mse) + "," + fmt(st.all.ssim()) + "," + fmt(data::psnr_from_mse(mse), 5) + "\n";
    for (auto& [scene, sc] : st.by_scene)
      by_scene += nm + "," + ns + "," + scene + "," + std::to_string(sc.views) + "," + fmt(sc.mse()) + "," + fmt(sc.ssim()) + "," + fmt(data::psnr_from_mse(sc.mse()), 5) + "\n";
    for (size_t b = 0; b < st.bands.size(); ++b)
      band_csv += nm + "," + ns + "," + band_names[b] + "," + std::to_string(st.bands[b].pixels) + "," + fmt(st.bands[b].mse()) + "\n";
    if (st.temporal.pairs) {
      const double f = st.temporal.flicker(), gf = gt_temporal.flicker();
      temporal += nm + "," + ns + "," + fmt(f) + "," + fmt(gf) + "," + (gf > 0 ? fmt(f / gf, 4) : std::string("nan")) + "," +
                  fmt(st.temporal.error()) + "," + std::to_string(st.temporal.pairs) + "," + fmt(st.temporal.coverage(), 4) + "\n";
    }
    timing += nm + "," + ns + "," + fmt(ms, 5) + "," + fmt(median(st.cpu_ms), 5) + "," + std::to_string(threads) + "\n";
    if (!series.count(nm)) order.push_back(nm), series[nm].name = nm;
    series[nm].x.push_back(ms);
    series[nm].y.push_back(mse);
    series[nm].point_labels.push_back(ns);
    if (st.temporal.pairs && gt_temporal.flicker() > 0) {
      auto& fs_ = flicker_series[nm];
      fs_.name = nm;
      fs_.x.push_back(ms);
      fs_.y.push_back(st.temporal.flicker() / gt_temporal.flicker());
      fs_.point_labels.push_back(ns);
    }
  }
  write_file_atomic((fs::path(out) / "results.csv").string(), csv);
  write_file_atomic((fs::path(out) / "results_by_scene.csv").string(), by_scene);
  write_file_atomic((fs::path(out) / "failure_bands.csv").string(), band_csv);
  write_file_atomic((fs::path(out) / "temporal.csv").string(), temporal);
  write_file_atomic((fs::path(out) / "timing.csv").string(), timing);
  // Per family, each method at its setting of lowest MSE over all views.
  std::map<std::string, size_t> best_setting;
  for (size_t m = 0; m < methods.size(); ++m) {
    auto it = best_setting.find(methods[m].name);
    if (it == best_setting.end() || stats[m].all.mse() < stats[it->second].all.mse()) best_setting[methods[m].name] = m;
  }
  std::string by_family = "family,method,samples,views,mse,ssim,flicker,ground_truth_flicker\n";
  data::Table family_table{{"family", "method", "samples", "MSE", "SSIM", "flicker (x ground truth)"}, {}};
  std::set<std::string> families;
  for (auto& st : stats)
    for (auto& [fam, sc] : st.by_family) families.insert(fam);
  for (auto& fam : families)
    for (auto& n : order) {
      const size_t m = best_setting[n];
      auto sc = stats[m].by_family.find(fam);
      if (sc == stats[m].by_family.end()) continue;
      auto t = stats[m].temporal_by_family.find(fam);
      auto gt = gt_temporal_by_family.find(fam);
      const bool has_t = t != stats[m].temporal_by_family.end() && t->second.pairs && gt != gt_temporal_by_family.end();
      const double f = has_t ? t->second.flicker() : std::nan(""), gf = has_t ? gt->second.flicker() : std::nan("");
      by_family += fam + "," + n + "," + std::to_string(methods[m].samples) + "," + std::to_string(sc->second.views) + "," +
                   fmt(sc->second.mse()) + "," + fmt(sc->second.ssim()) + "," + fmt(f) + "," + fmt(gf) + "\n";
      family_table.rows.push_back({fam, n, std::to_string(methods[m].samples), fmt(sc->second.mse(), 4),
                                   fmt(sc->second.ssim(), 4), has_t ? fmt(f / gf, 3) : std::string("-")});
    }
  write_file_atomic((fs::path(out) / "results_by_family.csv").string(), by_family);
  // A method's accumulated form ("+TA") is drawn dashed in the method's own colour.
  for (size_t m = 0; m < accumulated.size(); ++m) {  // the methods that run (the +TA rows follow)
    if (accumulated[m] < 0) continue;
    const std::string& ta = methods[size_t(accumulated[m])].name;
    const int colour = int(std::find(order.begin(), order.end(), methods[m].name) - order.begin());
    for (auto* s : {&series, &flicker_series})
      if (s->count(ta)) (*s)[ta].colour = colour, (*s)[ta].dashed = true;
  }
  std::vector<data::ChartSeries> chart;
  for (auto& n : order) chart.push_back(series[n]);
  data::ChartOptions co;
  co.title = "AO: error against time (" + std::to_string(width) + "x" + std::to_string(height) + ", " + std::to_string(threads) + " threads)";
  co.x_label = "ms per frame (median over views)";
  co.y_label = "MSE vs ray-traced AO (non-sky pixels)";
  co.log_x = true;
  const std::string chart_path = (fs::path(out) / "speed_vs_accuracy.svg").string();
  std::string note = data::write_chart(chart_path, chart, co);
  if (!note.empty()) std::fprintf(stderr, "eval-ao: note: %s\n", note.c_str());
  // The second chart: flicker (relative to the ground truth's, 1 = as stable as the
  // truth) against the same time axis, for the methods measured on camera paths.
  std::vector<data::ChartSeries> flicker_chart;
  for (auto& n : order)
    if (flicker_series.count(n)) flicker_chart.push_back(flicker_series[n]);
  const std::string flicker_path = (fs::path(out) / "flicker_vs_time.svg").string();
  if (!flicker_chart.empty()) {
    data::ChartOptions fo = co;
    fo.title = "AO: flicker against time (camera paths, reprojected)";
    fo.y_label = "flicker / ground truth's flicker";
    const std::string fnote = data::write_chart(flicker_path, flicker_chart, fo);
    if (!fnote.empty()) std::fprintf(stderr, "eval-ao: note: %s\n", fnote.c_str());
  }

  // report.md and report.html: the table, the paper's two claims checked, the bands, the
  // charts, and the previews of each method at its best setting.
  auto find = [&](const std::string& n, int s) -> int {
    for (size_t m = 0; m < methods.size(); ++m)
      if (methods[m].name == n && methods[m].samples == s) return int(m);
    return -1;
  };
  std::vector<Method> shown;  // each method at its best setting; the accumulated forms need a path's history
  for (auto& n : order)
    if (methods[best_setting[n]].run) shown.push_back(methods[best_setting[n]]);
  const auto comparisons = write_ao_previews(views, previews, shown, out, [&](const std::string& view_file) {
    int frame = -1;
    const bool on_path = !camera_path_of(view_file, frame).empty();
    pattern_seed = o.vary_pattern && on_path ? uint32_t(frame) : 0u;
  });
  data::Report r("AO evaluation");
  r.text("Data: " + split_note + " — " + std::to_string(views.size()) + " views at " + std::to_string(width) + "x" +
         std::to_string(height) + ", " + std::to_string(threads) + " threads, classical parameters: " +
         (params_file.empty() ? std::string("built-in") : params_file) +
         ". Errors over non-sky pixels against the ray-traced `AO` channel; ms per frame is the median over views of "
         "the fastest of " + std::to_string(repeat) + " runs per view.");
  if (!comparisons.empty()) {
    r.heading("Previews").text("The ray-traced AO, each method at its best setting (lowest MSE over all views; the "
                               "+TA forms are left out: they need a camera path's history) and its error heat-map "
                               "(black 0, white 0.5), with the view's MSE and SSIM. PNGs in previews/.");
    for (auto& c : comparisons) r.comparison(c);
  }
  r.heading("Speed against accuracy");
  r.chart("speed_vs_accuracy.svg", "speed vs accuracy", note);
  data::Table results{{"method", "samples", "ms/frame", "CPU ms/frame", "MSE", "SSIM", "PSNR"}, {}};
  for (size_t m = 0; m < methods.size(); ++m)
    results.rows.push_back({methods[m].name, std::to_string(methods[m].samples), fmt(median(stats[m].ms), 4),
                            fmt(median(stats[m].cpu_ms), 4), fmt(stats[m].all.mse(), 4), fmt(stats[m].all.ssim(), 4),
                            fmt(data::psnr_from_mse(stats[m].all.mse()), 4)});
  r.table(results).heading("The paper's claims on this data");
  std::vector<std::string> claims;
  int ex = find("NNAO-exact", weights.input.samples());
  if (ex >= 0) {
    std::string beaten_by;
    for (size_t m = 0; m < methods.size(); ++m)
      if (methods[m].name.rfind("NNAO", 0) != 0 && stats[m].all.mse() <= stats[size_t(ex)].all.mse())
        beaten_by += " " + methods[m].name + "@" + std::to_string(methods[m].samples);
    claims.push_back("NNAO (exact, MSE " + fmt(stats[size_t(ex)].all.mse(), 4) +
                     ") has lower MSE than every classical method at every sample count: **" +
                     (beaten_by.empty() ? "holds**." : "does not hold** (not lower than:" + beaten_by + ")."));
  }
  int n64 = find("NNAO", 64), h64 = find("HBAO", 64);
  if (n64 >= 0 && h64 >= 0) {
    double nm = median(stats[size_t(n64)].ms), hm = median(stats[size_t(h64)].ms);
    double ne = stats[size_t(n64)].all.mse(), he = stats[size_t(h64)].all.mse();
    claims.push_back("Shader-style NNAO at 64 samples (" + fmt(nm, 4) + " ms, MSE " + fmt(ne, 4) + ") vs HBAO at 64 (" +
                     fmt(hm, 4) + " ms, MSE " + fmt(he, 4) + "): faster **" + (nm < hm ? "yes" : "no") +
                     "**, more accurate **" + (ne < he ? "yes" : "no") + "**.");
  }
  if (claims.empty()) r.text("Not checked: they need NNAO-exact, or NNAO and HBAO at 64 samples.");
  else r.list(claims);
  r.heading("Failure bands (MSE)")
      .text("halo: within 3 px of a depth discontinuity; border: within 8% of the width of the screen edge; thin: "
            "surfaces under 6 px across. See failure_bands.csv.");
  data::Table band_table{{"method", "samples"}, {}};
  for (auto& b : band_names) band_table.header.push_back(b);
  for (size_t m = 0; m < methods.size(); ++m) {
    band_table.rows.push_back({methods[m].name, std::to_string(methods[m].samples)});
    for (auto& b : stats[m].bands) band_table.rows.back().push_back(fmt(b.mse(), 4));
  }
  r.table(band_table).heading("Per family");
  r.text("Each method at its setting of lowest MSE over all views; flicker relative to the ground truth's on the "
         "family's camera-path frames. See results_by_family.csv.");
  r.table(family_table);
  r.text("Per scene: results_by_scene.csv. CPU ms (process CPU time over all threads, median over views): timing.csv.");
  r.heading("Temporal stability")
      .text("On camera-path frames (files `<scene>-pNN-fNNN.exr`), each frame reprojected to the one before it "
            "(worldToCamera; disocclusions and off-screen points skipped). flicker = mean |m_t - m_t-1| over the mapped "
            "pixels; temporal error = mean |(m_t - m_t-1) - (g_t - g_t-1)| against the ground truth g. See temporal.csv.");
  if (gt_temporal.pairs) {
    r.text("Ground truth flicker " + fmt(gt_temporal.flicker(), 4) + " over " + std::to_string(gt_temporal.pairs) +
           " frame pairs (" + fmt(100 * gt_temporal.coverage(), 3) + "% of pixels mapped).");
    r.chart("flicker_vs_time.svg", "flicker vs time");
    data::Table t_table{{"method", "samples", "flicker", "relative to ground truth", "temporal error"}, {}};
    for (size_t m = 0; m < methods.size(); ++m) {
      const auto& t = stats[m].temporal;
      if (t.pairs)
        t_table.rows.push_back({methods[m].name, std::to_string(methods[m].samples), fmt(t.flicker(), 4),
                                fmt(t.flicker() / gt_temporal.flicker(), 4), fmt(t.error(), 4)});
    }
    r.table(t_table);
  } else {
    r.text("No camera-path frames in this data, so there is nothing to report (temporal.csv is empty).");
  }
  r.write(out);
  std::printf("%s", csv.c_str());
  std::printf("chart: %s%s\nreport: %s (and report.md)\n", chart_path.c_str(), note.empty() ? " (+ .png)" : "", (fs::path(out) / "report.html").string().c_str());
}

}  // namespace nns::ao_eval
