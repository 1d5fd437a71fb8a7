#pragma once
// PNG previews of GI samples and predictions, contact sheets of a dataset's ground
// truth, and the loss chart of a training run. Light is tone-mapped with exposure 1/k
// (k = the HDR scale), so the data set's median light shows mid-grey whatever the
// scene's units.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "report/chart.h"
#include "report/html_report.h"
#include "data/dataset.h"
#include "data/exr_io.h"
#include "report/image_write.h"
#include "runs/gi/gi_scores.h"
#include "runs/metrics_log.h"
#include "models/gi/gi_inputs.h"

namespace nns::runs {

inline void write_light_png(const std::string& path, const float* rgb, int w, int h, const gi::HdrMapping& hdr) {
  const int64_t n = int64_t(w) * h;
  report::write_png_rgb(path, rgb, rgb + n, rgb + 2 * n, w, h, {.exposure = 1.0f / hdr.scale});
}

// prefix_{prediction,truth,error}.png; the error is |mapped difference| averaged over
// the channels on the geometry the metrics score (sky black), the heat map saturating
// at 0.25.
inline void write_eval_pngs(const std::string& prefix, const Tensor<float>& pred, const Tensor<float>& truth,
                            const gi::HdrMapping& hdr, const std::vector<uint8_t>& geometry) {
  const int h = int(truth.size(1)), w = int(truth.size(2));
  const int64_t n = int64_t(w) * h;
  std::vector<float> err(size_t(n), 0.0f);
  for (int c = 0; c < 3; ++c)
    for (int64_t i = 0; i < n; ++i)
      if (geometry[size_t(i)])
        err[size_t(i)] += std::abs(hdr.to_unit(pred[c * n + i]) - hdr.to_unit(truth[c * n + i])) / 3;
  write_light_png(prefix + "_prediction.png", pred.data(), w, h, hdr);
  write_light_png(prefix + "_truth.png", truth.data(), w, h, hdr);
  report::write_png_heatmap(prefix + "_error.png", err.data(), w, h, 0.25f);
}

// prefix_{input,prediction,truth,error,shaded}.png: the input's lumination (direct +
// emission + env) of the front region, the predicted and true light and the error
// (write_eval_pngs), and albedo * prediction + emission, the shaded image the screen
// would show.
inline void write_sample_pngs(const std::string& prefix, const gi::GiSample& s, const Tensor<float>& pred_tanh,
                              const gi::HdrMapping& hdr) {
  const int h = int(s.front.h), w = int(s.front.w);
  const int64_t n = int64_t(w) * h;
  std::vector<float> input(size_t(3 * n)), shaded(size_t(3 * n));
  Tensor<float> pred({3, h, w});
  const int64_t H = s.input.size(2), W = s.input.size(3);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int64_t i = c * n + y * w + x;
        input[size_t(i)] = hdr.from_tanh(s.input[((7 + c) * H + s.front.y0 + y) * W + s.front.x0 + x]);
        pred[i] = hdr.from_tanh(pred_tanh[i]);
        shaded[size_t(i)] = s.albedo[i] * pred[i] + s.emission[i];
      }
  write_light_png(prefix + "_input.png", input.data(), w, h, hdr);
  write_eval_pngs(prefix, pred, s.target_linear, hdr, s.geometry);
  write_light_png(prefix + "_shaded.png", shaded.data(), w, h, hdr);
}

// A frame eval-gi wrote previews of (write_eval_pngs) for one row of its table.
struct EvalPreview {
  std::string model, frame;  // the row's label, the frame's
  std::string prefix;        // "previews/<model>_<frame>", relative to the report
  LightMetrics metrics;      // this frame's
};

// One image comparison per frame, in the order the frames were scored: the truth, then
// each row's prediction and its error heat-map, with the frame's numbers.
inline void add_eval_previews(report::Report& report, const std::vector<EvalPreview>& previews) {
  std::vector<report::Comparison> frames;
  for (auto& p : previews) {
    auto c =
        std::find_if(frames.begin(), frames.end(), [&](const report::Comparison& f) { return f.title == p.frame; });
    if (c == frames.end()) {
      frames.push_back({p.frame, {{"ray-traced light (truth)", p.prefix + "_truth.png", ""}}});
      c = frames.end() - 1;
    }
    char numbers[96];
    std::snprintf(numbers, sizeof numbers, "SSIM %.3f, MSE %.4f (mapped), MSE %.4g (linear)", p.metrics.ssim,
                  p.metrics.mse, p.metrics.mse_linear);
    c->images.push_back({p.model, p.prefix + "_prediction.png", numbers});
    c->images.push_back({p.model + ": error", p.prefix + "_error.png",
                         std::string(numbers) + "; |mapped difference| black 0, white 0.25"});
  }
  if (frames.empty()) return;
  report.heading("Previews")
      .text(
          "The ray-traced light (truth), each row's prediction and its error heat-map "
          "(|difference| in mapped space, averaged over the channels), tone-mapped with exposure 1/k (k = the HDR "
          "scale). PNGs in previews/.");
  for (auto& f : frames) report.comparison(std::move(f));
}

// train-gan's samples on its report: the first and the last step that wrote them (a
// resumed run's earlier samples included), each a comparison of its five images.
inline void add_sample_comparisons(report::Report& report, const std::string& out, int sample_every, int64_t steps) {
  if (sample_every <= 0 || steps < sample_every) return;
  std::vector<int64_t> shown = {sample_every};
  if (steps / sample_every > 1) shown.push_back(steps / sample_every * sample_every);
  bool heading = false;
  for (int64_t step : shown) {
    const std::string prefix = "samples/step" + std::to_string(step);
    if (!std::filesystem::exists(out + "/" + prefix + "_error.png")) continue;
    if (!heading)
      report.heading("Samples").text(
          "A training frame at the first and the last step that drew one: the "
          "ray-traced light, the generator's prediction and its error (|mapped "
          "difference|, black 0, white 0.25), the input's direct light and the shaded "
          "image (albedo x prediction + emission). More in samples/.");
    heading = true;
    report.comparison({"step " + std::to_string(step),
                       {{"ray-traced light (truth)", prefix + "_truth.png", ""},
                        {"prediction", prefix + "_prediction.png", ""},
                        {"error", prefix + "_error.png", ""},
                        {"input: direct + emission + env", prefix + "_input.png", ""},
                        {"shaded: albedo x prediction + emission", prefix + "_shaded.png", ""}}});
  }
}

// A contact sheet of a split's ground truth, for people to see what the scenes look
// like: the front views of up to `max_frames` views or frames (those of scenes
// "<family>-<instance>" when `family` is given), each as three tiles side by side —
// albedo, the shaded image albedo x (direct + env + indirect) + emission, and the
// indirect light alone — `per_row` of them to a row, 4-pixel gaps. Light is tone-mapped
// with exposure 1/k, k the median of direct + env + indirect over the sheet's geometry
// pixels; the indirect with 1/(its own median), being the dimmer part. At most
// `per_scene` items of one scene (the frames of a camera path look alike); items without
// indirect.* or of another size than the first are skipped. Returns the frames drawn.
inline int write_contact_sheet(const std::string& path, const data::SplitListing& split, const std::string& family,
                               int max_frames, int per_scene = 1, int per_row = 4) {
  std::vector<std::string> paths = split.views;
  for (auto& f : split.frames) paths.push_back(f.faces[size_t(data::Face::front)]);
  std::vector<data::View> views;
  std::map<std::string, int> drawn;  // per scene
  for (const std::string& p : paths) {
    if (int(views.size()) >= max_frames || p.empty()) continue;
    const std::string scene = data::scene_of(p);
    if (!family.empty() && (scene.rfind(family + "-", 0) != 0 ||
                            scene.find_first_not_of("0123456789", family.size() + 1) != std::string::npos))
      continue;
    if (drawn[scene] >= per_scene) continue;
    ++drawn[scene];
    data::View v = data::read_view(p);
    if (!v.has("indirect.R") || (!views.empty() && (v.width != views[0].width || v.height != views[0].height)))
      continue;
    views.push_back(std::move(v));
  }
  if (views.empty()) return 0;
  const int w = views[0].width, h = views[0].height, gap = 4, n = int(views.size());
  const int cols = std::min(per_row, n), rows = (n + cols - 1) / cols;
  const int W = cols * (3 * w + 2 * gap) + (cols + 1) * gap * 2, H = rows * h + (rows + 1) * gap;
  auto light = [](const data::View& v, int c, size_t i, bool indirect_only) {
    const char* rgb[3] = {".R", ".G", ".B"};
    float x = v.channel(std::string("indirect") + rgb[c])[i];
    if (indirect_only) return x;
    for (const char* base : {"direct", "env"})
      if (v.has(std::string(base) + rgb[c])) x += v.channel(std::string(base) + rgb[c])[i];
    return x;
  };
  auto median = [&](bool indirect_only) {
    std::vector<float> all;
    for (auto& v : views)
      for (size_t i = 0; i < v.channel("Z").size(); i += 3)
        if (!data::is_sky(v.channel("Z")[i])) all.push_back(light(v, 1, i, indirect_only));
    if (all.empty()) return 1.0f;
    std::nth_element(all.begin(), all.begin() + std::ptrdiff_t(all.size() / 2), all.end());
    return all[all.size() / 2] > 1e-6f ? all[all.size() / 2] : 1.0f;
  };
  const float k_light = median(false), k_ind = median(true);
  std::vector<uint8_t> img(size_t(W) * size_t(H) * 3, 40);
  auto tone = [](float x) {
    x = std::max(x, 0.0f);
    return report::srgb_encode(x / (1 + x));
  };
  for (int f = 0; f < n; ++f) {
    const data::View& v = views[size_t(f)];
    const int x0 = 2 * gap + (f % cols) * (3 * w + 4 * gap), y0 = gap + (f / cols) * (h + gap);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        for (int c = 0; c < 3; ++c) {
          const float a = v.channel(std::string("albedo.") + "RGB"[c])[i];
          const float e =
              v.has(std::string("emission.") + "RGB"[c]) ? v.channel(std::string("emission.") + "RGB"[c])[i] : 0.0f;
          const uint8_t tiles[3] = {report::srgb_encode(std::clamp(a, 0.0f, 1.0f)),
                                    tone((a * light(v, c, i, false) + e) / k_light),
                                    tone(light(v, c, i, true) / k_ind)};
          for (int t = 0; t < 3; ++t)
            img[(size_t(y0 + y) * size_t(W) + size_t(x0 + t * (w + gap) + x)) * 3 + size_t(c)] = tiles[t];
        }
      }
  }
  report::write_png_rgb8(path, img.data(), W, H);
  return n;
}

// OUT/loss.svg and .png from the run's metrics log: the D loss, G's adversarial loss and
// its reconstruction (L1 / DSSIM) term against the step.
inline void write_loss_chart(const runs::MetricsLog& log, const std::string& svg_path) {
  std::vector<report::ChartSeries> series;
  const std::pair<const char*, const char*> keys[] = {
      {"d", "D loss"}, {"g_adv", "G adversarial"}, {"g_rec", "G reconstruction (L1 or DSSIM)"}};
  for (auto& [key, name] : keys) {
    report::ChartSeries se{name, {}, {}, {}};
    for (auto& r : log.records())
      if (r.get(key) > 0) se.x.push_back(double(r.step)), se.y.push_back(r.get(key));
    if (!se.x.empty()) series.push_back(se);
  }
  if (series.empty()) return;
  report::ChartOptions o;
  o.title = "train-gan losses";
  o.x_label = "step";
  o.y_label = "loss";
  o.log_y = true;
  report::write_chart(svg_path, series, o);
}

}  // namespace nns::runs
