#pragma once
// PNG previews of GI samples and predictions, and the loss chart of a training run.
// Light is tone-mapped with exposure 1/k (k = the HDR scale), so the data set's median
// light shows mid-grey whatever the scene's units.
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "report/chart.h"
#include "report/png_io.h"
#include "runs/metrics_log.h"
#include "models/gi/gi_inputs.h"

namespace nns::gi {

inline void write_light_png(const std::string& path, const float* rgb, int w, int h, const HdrMapping& hdr) {
  const int64_t n = int64_t(w) * h;
  data::write_png_rgb(path, rgb, rgb + n, rgb + 2 * n, w, h, {.exposure = 1.0f / hdr.scale});
}

// prefix_{input,prediction,truth,shaded}.png: the input's lumination (direct + emission
// + env) of the front region, the predicted and true light, and albedo * prediction +
// emission, the shaded image the screen would show.
inline void write_sample_pngs(const std::string& prefix, const GiSample& s, const Tensor<float>& pred_tanh,
                              const HdrMapping& hdr) {
  const int h = int(s.front.h), w = int(s.front.w);
  const int64_t n = int64_t(w) * h;
  std::vector<float> input(size_t(3 * n)), pred(size_t(3 * n)), shaded(size_t(3 * n));
  const int64_t H = s.input.size(2), W = s.input.size(3);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int64_t i = c * n + y * w + x;
        input[size_t(i)] = hdr.from_tanh(s.input[((7 + c) * H + s.front.y0 + y) * W + s.front.x0 + x]);
        pred[size_t(i)] = hdr.from_tanh(pred_tanh[i]);
        shaded[size_t(i)] = s.albedo[i] * pred[size_t(i)] + s.emission[i];
      }
  write_light_png(prefix + "_input.png", input.data(), w, h, hdr);
  write_light_png(prefix + "_prediction.png", pred.data(), w, h, hdr);
  write_light_png(prefix + "_truth.png", s.target_linear.data(), w, h, hdr);
  write_light_png(prefix + "_shaded.png", shaded.data(), w, h, hdr);
}

// prefix_{prediction,truth,error}.png; the error is |mapped difference| averaged over
// the channels, the heat map saturating at 0.25.
inline void write_eval_pngs(const std::string& prefix, const Tensor<float>& pred, const Tensor<float>& truth,
                            const HdrMapping& hdr) {
  const int h = int(truth.size(1)), w = int(truth.size(2));
  const int64_t n = int64_t(w) * h;
  std::vector<float> err(size_t(n), 0.0f);
  for (int c = 0; c < 3; ++c)
    for (int64_t i = 0; i < n; ++i)
      err[size_t(i)] += std::abs(hdr.to_unit(pred[c * n + i]) - hdr.to_unit(truth[c * n + i])) / 3;
  write_light_png(prefix + "_prediction.png", pred.data(), w, h, hdr);
  write_light_png(prefix + "_truth.png", truth.data(), w, h, hdr);
  data::write_png_heatmap(prefix + "_error.png", err.data(), w, h, 0.25f);
}

// OUT/loss.svg and .png from the run's metrics log: the D loss, G's adversarial loss and
// its reconstruction (L1 / DSSIM) term against the step.
inline void write_loss_chart(const runs::MetricsLog& log, const std::string& svg_path) {
  std::vector<data::ChartSeries> series;
  const std::pair<const char*, const char*> keys[] = {
      {"d", "D loss"}, {"g_adv", "G adversarial"}, {"g_rec", "G reconstruction (L1 or DSSIM)"}};
  for (auto& [key, name] : keys) {
    data::ChartSeries se{name, {}, {}, {}};
    for (auto& r : log.records())
      if (r.get(key) > 0) se.x.push_back(double(r.step)), se.y.push_back(r.get(key));
    if (!se.x.empty()) series.push_back(se);
  }
  if (series.empty()) return;
  data::ChartOptions o;
  o.title = "train-gan losses";
  o.x_label = "step";
  o.y_label = "loss (log scale)";
  o.log_y = true;
  data::write_chart(svg_path, series, o);
}

}  // namespace nns::gi
