#pragma once
// What eval-ao runs and how it scores: its options, the views of the split, the methods
// at every setting (build_methods) and one pass over the views that times and scores
// them all (evaluate_views). eval_ao_report.h writes what it finds; eval_ao.h is the job.
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

#include "classical_ao/failure_bands.h"
#include "classical_ao/methods.h"
#include "classical_ao/params.h"
#include "classical_ao/temporal.h"
#include "core/progress.h"
#include "core/thread_pool.h"
#include "data/dataset.h"
#include "data/exr_io.h"
#include "data/validate.h"
#include "models/nnao/nnao_inference.h"
#include "models/nnao/nnao_inference_reference.h"
#include "report/image_metrics.h"
#include "runs/ao/ao_previews.h"

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

}  // namespace nns::runs
