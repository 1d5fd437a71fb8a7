#pragma once
// eval-ao's previews: for `count` views spread evenly over the list (so over its scenes,
// which the list keeps together), the ray-traced AO and every method at its best
// setting (the sample count of lowest MSE over all views, known only once every view is
// scored, hence this second pass over a handful of views) with its error heat-map, as
// PNGs in OUT/previews and as one image comparison each for the report.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "data/exr_io.h"
#include "report/html_report.h"
#include "report/image_metrics.h"
#include "report/image_write.h"
#include "classical_ao/temporal.h"
#include "screen_space/gbuffer.h"

namespace nns::runs {

// The camera path a view belongs to and its frame number (-1, "" for a still view): a
// flat view names its frame ("room-1-p00-f003.exr"), a surround frame's folder does
// ("room-1-p00-f003/front.exr").
inline std::string camera_path_of(const std::string& view_file, int& frame) {
  namespace fs = std::filesystem;
  frame = -1;
  std::string path = classical_ao::path_of_frame(fs::path(view_file).stem().string(), frame);
  if (path.empty()) path = classical_ao::path_of_frame(fs::path(view_file).parent_path().filename().string(), frame);
  return path;
}

// A file-name-safe form of a method's name ("SSAO+" -> "SSAOp").
inline std::string safe(std::string s) {
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = c == '+' ? 'p' : '_';
  return s;
}

struct Method {
  std::string name;  // "NNAO-exact", "NNAO", "SSAO", ...; "<method>+TA": accumulated (run is null)
  int samples;
  std::function<void(const screen_space::GBuffer&, float*)> run;
  std::string setting = "";  // an NNAO ladder's rung; empty: the sample count names the setting
  // The point's label in charts and tables: the rung, or the sample count.
  std::string label() const { return setting.empty() ? std::to_string(samples) : setting; }
};

inline std::string fmt(double v, int prec = 6) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", prec, v);
  return b;
}

// before_view(view_file) runs before the methods on a view (shader-style NNAO's jitter
// seed follows the frame number). Error heat-maps saturate at 0.5 (white).
inline std::vector<report::Comparison> write_ao_previews(const std::vector<std::string>& views, int count,
                                                         const std::vector<Method>& methods, const std::string& out,
                                                         const std::function<void(const std::string&)>& before_view) {
  namespace fs = std::filesystem;
  std::vector<report::Comparison> comparisons;
  const size_t n = std::min(views.size(), size_t(std::max(count, 0)));
  for (size_t k = 0; k < n; ++k) {
    const size_t v = k * views.size() / n;
    const data::View view = data::read_view(views[v]);
    const screen_space::GBuffer g = screen_space::gbuffer_from_view(view);
    const auto& gt = view.channel("AO");
    std::vector<uint8_t> mask(size_t(g.pixels()));
    for (int64_t i = 0; i < g.pixels(); ++i) mask[size_t(i)] = !g.sky(i);
    const std::string stem =
        fs::path(views[v]).parent_path().filename().string() + "_" + fs::path(views[v]).stem().string();
    report::Comparison c{view.scene + " — " + fs::path(views[v]).filename().string(), {}};
    c.images.push_back({"ray-traced AO (ground truth)", "previews/" + stem + "_ground_truth.png", ""});
    report::write_png_gray((fs::path(out) / c.images.back().file).string(), gt.data(), g.width, g.height);
    before_view(views[v]);
    std::vector<float> result(size_t(g.pixels())), err(result.size());
    for (auto& m : methods) {
      m.run(g, result.data());
      for (size_t i = 0; i < err.size(); ++i) err[i] = mask[i] ? std::abs(result[i] - gt[i]) : 0.0f;
      const std::string base = "previews/" + stem + "_" + safe(m.name) + "_" + safe(m.label());
      const std::string numbers =
          "MSE " + fmt(report::masked_mse(result.data(), gt.data(), mask.data(), g.pixels()), 4) + ", SSIM " +
          fmt(report::masked_ssim(result.data(), gt.data(), mask.data(), g.width, g.height), 4);
      report::write_png_gray((fs::path(out) / (base + ".png")).string(), result.data(), g.width, g.height);
      report::write_png_heatmap((fs::path(out) / (base + "_error.png")).string(), err.data(), g.width, g.height, 0.5f);
      const std::string label =
          m.name + ", " + (m.setting.empty() ? std::to_string(m.samples) + " samples" : m.setting);
      c.images.push_back({label, base + ".png", numbers});
      c.images.push_back({label + ": error", base + "_error.png", numbers + "; |AO - truth| black 0, white 0.5"});
    }
    comparisons.push_back(std::move(c));
  }
  return comparisons;
}

}  // namespace nns::runs
