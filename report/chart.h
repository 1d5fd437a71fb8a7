#pragma once
// Line charts as SVG (no dependency), with an optional log-scaled axis, a legend, axis
// labels and per-point labels — enough for loss curves and speed-versus-accuracy
// plots. The PNG beside it is drawn from the SVG by librsvg and cairo in-process.
#include <string>
#include <vector>

namespace nns::report {

struct ChartSeries {
  std::string name;
  std::vector<double> x, y;
  std::vector<std::string> point_labels;  // optional, one per point (e.g. sample counts)
  int colour = -1;                        // index into the palette; -1: the series' position
  bool dashed = false;                    // a variant of another series (e.g. the same method with TAA)
};

struct ChartOptions {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  int width = 860, height = 520;
};

// The SVG text. Non-finite points (and non-positive ones on a log axis) are skipped.
std::string line_chart_svg(const std::vector<ChartSeries>& series, const ChartOptions& options);

// Writes `svg_path` and the PNG next to it (same name, .png), each atomically
// (core/atomic_file.h). Returns "" on success, or a note explaining why there is no
// PNG. Throws std::runtime_error naming the file if a file cannot be written.
std::string write_chart(const std::string& svg_path, const std::vector<ChartSeries>& series,
                        const ChartOptions& options);

}  // namespace nns::report
