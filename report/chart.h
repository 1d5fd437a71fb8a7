#pragma once
// Line charts as SVG (no dependency), with an optional log-scaled axis, a legend, axis
// labels and per-point labels — enough for loss curves and speed-versus-accuracy
// plots. A PNG is made from the SVG by `rsvg-convert` (Debian librsvg2-bin) when it
// is installed; otherwise write_chart says so and only the SVG exists.
#include <string>
#include <vector>

namespace nns::data {

struct ChartSeries {
  std::string name;
  std::vector<double> x, y;
  std::vector<std::string> point_labels;  // optional, one per point (e.g. sample counts)
};

struct ChartOptions {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  int width = 860, height = 520;
};

// The SVG text. Non-finite points (and non-positive ones on a log axis) are skipped.
std::string line_chart_svg(const std::vector<ChartSeries>& series, const ChartOptions& options);

// Writes `svg_path` (temp file + rename) and, if rsvg-convert exists, the PNG next to it
// (same name, .png). Returns "" on success with PNG, or a note explaining why there is
// no PNG. Throws std::runtime_error naming the file if the SVG cannot be written.
std::string write_chart(const std::string& svg_path, const std::vector<ChartSeries>& series,
                        const ChartOptions& options);

// Writes `text` to `path` via a temporary file in the same folder and a rename.
void write_text_atomic(const std::string& path, const std::string& text);

}  // namespace nns::data
