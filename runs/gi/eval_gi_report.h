#pragma once
// eval-gi's files: the result tables as CSV and as report tables (all frames, off-screen-lit
// frames, per family, by distance to a surface break), the speed-against-accuracy charts
// and report.md / report.html. The rows come from eval_gi.h.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "report/chart.h"
#include "report/csv_field.h"
#include "runs/gi/eval_gi_rows.h"
#include "runs/gi/gi_previews.h"

namespace nns::runs {

inline std::string results_csv(const std::vector<EvalRow>& rows, bool offscreen) {
  std::string s =
      "model,mode,ms_per_frame,mse,psnr,ssim,mse_linear,psnr_linear,ssim_linear,frames,flicker,"
      "flicker_truth,flicker_ratio,temporal_error,path_pairs,flip,grad_error\n";
  for (auto& r : rows) {
    const LightMetrics& m = offscreen ? r.offscreen : r.all;
    s += report::csv_field(r.model) + "," + report::csv_field(r.mode) + "," + detail::fmt(r.ms_per_frame, "%.3f") +
         "," + detail::fmt(m.mse) + "," + detail::fmt(m.psnr) + "," + detail::fmt(m.ssim) + "," +
         detail::fmt(m.mse_linear) + "," + detail::fmt(m.psnr_linear) + "," + detail::fmt(m.ssim_linear) + "," +
         std::to_string(offscreen ? r.offscreen_frames : r.frames) + "," + detail::fmt(r.flicker) + "," +
         detail::fmt(r.flicker_truth) + "," + detail::fmt(r.flicker / r.flicker_truth) + "," +
         detail::fmt(r.temporal_error) + "," + std::to_string(r.flicker_pairs) + "," + detail::fmt(m.flip) + "," +
         detail::fmt(m.grad_error) + "\n";
  }
  return s;
}

// A table cell: the number, or a dash where there is none (no path pairs for the
// flicker, no frame in a family).
inline std::string cell(double v, const char* f) { return std::isfinite(v) ? detail::fmt(v, f) : "–"; }

inline report::Table results_table(const std::vector<EvalRow>& rows, bool offscreen) {
  report::Table t{{"model", "mode", "ms/frame", "MSE", "PSNR", "SSIM", "MSE (linear)", "frames", "flicker (x truth)",
                   "temporal error", "FLIP", "gradient error"},
                  {}};
  for (auto& r : rows) {
    const LightMetrics& m = offscreen ? r.offscreen : r.all;
    t.rows.push_back({r.model, r.mode, cell(r.ms_per_frame, "%.2f"), cell(m.mse, "%.5f"), cell(m.psnr, "%.2f"),
                      cell(m.ssim, "%.4f"), cell(m.mse_linear, "%.4g"),
                      std::to_string(offscreen ? r.offscreen_frames : r.frames),
                      cell(r.flicker / r.flicker_truth, "%.3f"), cell(r.temporal_error, "%.4f"), cell(m.flip, "%.4f"),
                      cell(m.grad_error, "%.5f")});
  }
  return t;
}

// Per scene family, each row's SSIM and linear MSE: where a model wins and where the
// constant ambient term already explains the light.
inline std::string family_csv(const std::vector<EvalRow>& rows) {
  std::string s = "model,family,frames,mse,psnr,ssim,mse_linear,flip,grad_error\n";
  for (auto& r : rows)
    for (auto& [family, mm] : r.by_family) {
      const LightMetrics m = mm.mean();
      s += report::csv_field(r.model) + "," + report::csv_field(family) + "," + std::to_string(mm.frames) + "," +
           detail::fmt(m.mse) + "," + detail::fmt(m.psnr) + "," + detail::fmt(m.ssim) + "," +
           detail::fmt(m.mse_linear) + "," + detail::fmt(m.flip) + "," + detail::fmt(m.grad_error) + "\n";
    }
  return s;
}

inline report::Table family_table(const std::vector<EvalRow>& rows) {
  report::Table t{{"family", "frames"}, {}};
  if (rows.empty()) return t;
  for (auto& r : rows) t.header.push_back(r.model + " SSIM / MSE lin");
  for (auto& [family, mm0] : rows.front().by_family) {
    t.rows.push_back({family, std::to_string(mm0.frames)});
    for (auto& r : rows) {
      auto it = r.by_family.find(family);
      const LightMetrics m = it == r.by_family.end() ? LightMetrics{} : it->second.mean();
      t.rows.back().push_back(cell(m.ssim, "%.3f") + " / " + cell(m.mse_linear, "%.4f"));
    }
  }
  return t;
}

// Per row and distance band (gi_scores.h's DistanceBands): the band's share of the
// geometry pixels, its mapped MSE and its mean FLIP.
inline std::string distance_csv(const std::vector<EvalRow>& rows) {
  std::string s = "model,mode,band,pixels,share,mse,flip\n";
  for (auto& r : rows)
    for (int b = 0; b < DistanceBands::kCount; ++b)
      s += report::csv_field(r.model) + "," + report::csv_field(r.mode) + "," + DistanceBands::name(b) + "," +
           std::to_string(r.bands.pixels[size_t(b)]) + "," + detail::fmt(r.bands.share(b)) + "," +
           detail::fmt(r.bands.mse(b)) + "," + detail::fmt(r.bands.mean_flip(b)) + "\n";
  return s;
}

inline report::Table distance_table(const std::vector<EvalRow>& rows) {
  report::Table t{{"model"}, {}};
  if (rows.empty()) return t;
  for (int b = 0; b < DistanceBands::kCount; ++b)
    t.header.push_back(DistanceBands::name(b) + " px (" + cell(100 * rows.front().bands.share(b), "%.0f") + "%)");
  for (auto& r : rows) {
    t.rows.push_back({r.model});
    for (int b = 0; b < DistanceBands::kCount; ++b)
      t.rows.back().push_back(cell(r.bands.mse(b), "%.5f") + " / " + cell(r.bands.mean_flip(b), "%.3f"));
  }
  return t;
}

// Speed against accuracy, one point per row: ms per frame (log axis) against mapped SSIM
// and against linear MSE, added to the report.
inline void write_speed_charts(const std::vector<EvalRow>& rows, const EvalOptions& o, report::Report& report) {
  struct Axis {
    const char* name;  // the file
    const char* title;
    const char* label;
    double LightMetrics::*value;
  };
  const Axis axes[] = {
      {"speed_vs_ssim", "SSIM (mapped)", "SSIM, mapped (higher is better)", &LightMetrics::ssim},
      {"speed_vs_mse_linear", "MSE (linear)", "MSE, linear HDR (lower is better)", &LightMetrics::mse_linear},
      {"speed_vs_flip", "FLIP (mapped)", "mean FLIP, mapped, 67 ppd (lower is better)", &LightMetrics::flip}};
  for (const Axis& axis : axes) {
    std::vector<report::ChartSeries> series;
    for (auto& r : rows) {
      if (r.ceiling) continue;
      report::ChartSeries c;
      c.name = r.model;
      c.x = {std::max(r.ms_per_frame, 1e-3)};
      c.y = {r.all.*axis.value};
      series.push_back(c);
    }
    report::ChartOptions co;
    co.title = std::string("GI, ") + o.split + " split: " + axis.title + " against time";
    co.x_label = "ms per frame (generator forward; references ~0)";
    co.y_label = axis.label;
    co.log_x = true;
    const std::string name = axis.name;
    const std::string note = report::write_chart(o.out + "/" + name + ".svg", series, co);
    report.chart(name + ".svg", co.title, note);
  }
}

inline void write_eval_report(const std::vector<EvalRow>& rows, const EvalOptions& o, size_t scored_frames,
                              size_t unlit_frames, const std::string& frames_csv) {
  write_file_atomic(o.out + "/results.csv", results_csv(rows, false));
  write_file_atomic(o.out + "/results_offscreen.csv", results_csv(rows, true));
  write_file_atomic(o.out + "/frames.csv", frames_csv);
  write_file_atomic(o.out + "/results_by_family.csv", family_csv(rows));
  write_file_atomic(o.out + "/results_by_distance.csv", distance_csv(rows));
  report::Report report("eval-gi");
  report.text(
      "Data: `" + o.data + "`, split " + o.split + " (" + std::to_string(scored_frames) + " frames, of which " +
      std::to_string(unlit_frames) + " unlit ones set aside: no light on the front view), test-time BatchNorm: " +
      (o.bn_batch_stats ? "batch statistics" : "running statistics") + ", dropout: " + (o.dropout_on ? "on" : "off") +
      (o.size > 0 ? ", scored at face " + std::to_string(o.size) : std::string()) +
      (o.upsample_from > 0 ? ", models run at face " + std::to_string(o.upsample_from) +
                                 " and their indirect light upsampled, guided by depth and normals (the row `truth @" +
                                 std::to_string(o.upsample_from) +
                                 " guided` is the true light put through the same reduction and upsample: the score "
                                 "of a model that predicted the reduced frames' light exactly)"
                           : std::string()) +
      ". Metrics in mapped space (Reinhard x/(x+k), [0,1]) over geometry pixels of the "
      "front view; MSE (linear) in HDR units. Flicker: on camera paths, each frame reprojected onto the one before "
      "(disocclusions skipped), the mean frame-to-frame change in mapped space, relative to the ground truth's "
      "on the same pixels (1 = as stable as the truth); temporal error: mean |predicted - true| change. "
      "FLIP: the perceptual difference of Andersson et al. 2020 (LDR, 67 pixels per degree) between the "
      "mapped images shown as the previews show them, mean over geometry pixels, in [0,1]; gradient error: "
      "mean |difference of neighbouring pixels' differences| in mapped space, blind to uniform offsets, "
      "sensitive to moved or missing edges (contact shadows, creases).");
  std::vector<EvalPreview> previews;
  for (auto& r : rows) previews.insert(previews.end(), r.previews.begin(), r.previews.end());
  add_eval_previews(report, previews);
  report.heading("All " + o.split + " frames").table(results_table(rows, false));
  report.heading("Off-screen-lit frames (front face holds < " + detail::fmt(100 * o.offscreen_share, "%.1f") +
                 "% of the frame's direct light)");
  int64_t offscreen_frames = 0;
  for (auto& r : rows) offscreen_frames += r.offscreen_frames;
  if (offscreen_frames == 0) report.text("No frame of this split is lit mostly from off the screen.");
  else report.table(results_table(rows, true));
  report.heading("Per scene family (SSIM mapped / MSE linear)").table(family_table(rows));
  report.heading("By distance to the nearest surface break (MSE mapped / FLIP)")
      .text(
          "Each geometry pixel of the front view by its distance (Chebyshev, pixels) to the nearest depth jump "
          "(more than 10% of the nearer depth), crease (normals more than 30 degrees apart) or sky edge; in brackets "
          "the band's share of the pixels. Contact shadows and creases sit in the first bands. Pooled over all "
          "frames' pixels. See results_by_distance.csv.")
      .table(distance_table(rows));
  report.heading("Speed against accuracy");
  write_speed_charts(rows, o, report);
  report.write(o.out);
}

}  // namespace nns::runs
