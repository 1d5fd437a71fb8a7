#pragma once
// eval-ao's files from one evaluation (eval_ao_evaluation.h): results*.csv, failure_bands.csv,
// temporal.csv, timing.csv, the speed-against-accuracy charts, pareto.csv, previews/ and
// report.md / report.html.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "report/chart.h"
#include "report/csv_field.h"
#include "report/html_report.h"
#include "report/image_write.h"
#include "runs/ao/ao_pareto.h"
#include "runs/ao/ao_previews.h"
#include "runs/ao/eval_ao_evaluation.h"

namespace nns::runs {

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

}  // namespace nns::runs
