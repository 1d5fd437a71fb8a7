#include "report/chart.h"

#include <cairo.h>
#include <librsvg/rsvg.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "report/html_report.h"
#include "report/image_write.h"

namespace nns::report {
namespace {

const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                          "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"};

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f", v);
  return b;
}

std::string tick_label(double v) {
  char b[32];
  double a = std::abs(v);
  if (a != 0 && (a < 1e-3 || a >= 1e5)) std::snprintf(b, sizeof b, "%.0e", v);
  else std::snprintf(b, sizeof b, "%g", v);
  return b;
}

struct Axis {
  double lo, hi;
  bool log;
  double map(double v, double a, double b) const {  // data -> pixels in [a, b]
    double t = log ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo)) : (v - lo) / (hi - lo);
    return a + t * (b - a);
  }
  std::vector<double> ticks() const {
    std::vector<double> t;
    if (log) {
      // 1, 2, 5 per decade; an axis spanning less than a decade would show one tick or
      // none, so it takes the finer steps.
      for (const std::vector<double>& mantissas :
           {std::vector<double>{1, 2, 5}, std::vector<double>{1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 7, 8, 9}}) {
        t.clear();
        for (double d = std::pow(10, std::floor(std::log10(lo))); d <= hi * 1.0001; d *= 10)
          for (double m : mantissas)
            if (d * m >= lo * 0.9999 && d * m <= hi * 1.0001) t.push_back(d * m);
        if (t.size() >= 3) break;
      }
      return t;
    }
    double span = hi - lo, step = std::pow(10, std::floor(std::log10(span / 5)));
    if (span / step > 10) step *= 2;
    if (span / step > 10) step *= 2.5;
    for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * span; v += step) t.push_back(v);
    return t;
  }
};

Axis make_axis(std::vector<double> v, bool log) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double x : v)
    if (std::isfinite(x) && (!log || x > 0)) lo = std::min(lo, x), hi = std::max(hi, x);
  if (!std::isfinite(lo)) lo = log ? 1 : 0, hi = log ? 10 : 1;
  if (log) {
    lo = std::pow(10, std::floor(std::log10(lo) * 4) / 4);
    hi = std::pow(10, std::ceil(std::log10(hi) * 4) / 4);
    if (hi <= lo) hi = lo * 10;
  } else {
    double pad = (hi - lo) * 0.05;
    if (pad == 0) pad = std::abs(hi) * 0.1 + 1e-9;
    lo -= pad, hi += pad;
  }
  return {lo, hi, log};
}

// A generous mean advance of the 12 px sans-serif text: the legend's column is sized by it,
// so that no name runs off the image.
constexpr double kCharWidth = 7.0;

// A legend name wrapped at spaces into lines of at most `chars` characters (a word
// longer than that keeps its own line).
std::vector<std::string> wrapped(const std::string& name, size_t chars) {
  std::vector<std::string> lines;
  std::istringstream words(name);
  std::string word, line;
  while (words >> word) {
    if (!line.empty() && line.size() + 1 + word.size() > chars) lines.push_back(line), line.clear();
    line += (line.empty() ? "" : " ") + word;
  }
  if (!line.empty() || lines.empty()) lines.push_back(line);
  return lines;
}

// Point labels (10 px text): the first of eight spots around the point (right or left
// of it, above or below, then further out) whose box overlaps no label placed before and
// stays inside the plot; the first spot when none does. Points of one curve close in time
// (an NNAO ladder's cheapest rungs) otherwise wrote their labels over each other.
constexpr double kLabelCharWidth = 5.6;
struct LabelBox {
  double x0, y0, x1, y1;
};
struct LabelSpot {
  double x, y;  // the text's anchor and baseline
  bool end;     // anchored at its end (left of the point)
};
LabelSpot place_label(std::vector<LabelBox>& placed, double px, double py, size_t chars, double L, double R, double T,
                      double B) {
  const double w = kLabelCharWidth * double(chars);
  const LabelSpot spots[] = {{px + 5, py - 5, false},  {px + 5, py + 14, false}, {px - 5, py - 5, true},
                             {px - 5, py + 14, true},  {px + 5, py - 17, false}, {px + 5, py + 26, false},
                             {px + 5, py - 29, false}, {px + 5, py + 38, false}};
  auto box = [&](const LabelSpot& s) {
    return s.end ? LabelBox{s.x - w, s.y - 9, s.x, s.y + 2} : LabelBox{s.x, s.y - 9, s.x + w, s.y + 2};
  };
  auto free = [&](const LabelBox& b) {
    if (b.x0 < L || b.x1 > R || b.y0 < T || b.y1 > B) return false;
    for (const LabelBox& o : placed)
      if (b.x0 < o.x1 && o.x0 < b.x1 && b.y0 < o.y1 && o.y0 < b.y1) return false;
    return true;
  };
  LabelSpot chosen = spots[0];
  for (const LabelSpot& s : spots)
    if (free(box(s))) {
      chosen = s;
      break;
    }
  placed.push_back(box(chosen));
  return chosen;
}

bool usable(double x, double y, const ChartOptions& o) {
  return std::isfinite(x) && std::isfinite(y) && (!o.log_x || x > 0) && (!o.log_y || y > 0);
}

}  // namespace

std::string line_chart_svg(const std::vector<ChartSeries>& series, const ChartOptions& o) {
  std::vector<double> xs, ys;
  for (auto& s : series)
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
      if (usable(s.x[i], s.y[i], o)) xs.push_back(s.x[i]), ys.push_back(s.y[i]);
  Axis ax = make_axis(xs, o.log_x), ay = make_axis(ys, o.log_y);
  // The legend's column: wide enough for the longest name, at most 45% of the chart
  // (longer names wrap).
  size_t longest = 0;
  for (auto& se : series) longest = std::max(longest, se.name.size());
  const double legend = std::clamp(46 + kCharWidth * double(longest) + 10, 190.0, 0.45 * o.width);
  const size_t legend_chars = size_t((legend - 46 - 10) / kCharWidth);
  const double L = 80, R = o.width - legend, T = 50, B = o.height - 60.0;
  double ly = T + 10;  // the next legend entry's baseline
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << o.width << "\" height=\"" << o.height
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << num((L + R) / 2) << "\" y=\"28\" text-anchor=\"middle\" font-size=\"16\">"
    << html_escape(o.title) << "</text>\n";
  for (double t : ax.ticks()) {
    double px = ax.map(t, L, R);
    s << "<line x1=\"" << num(px) << "\" y1=\"" << num(T) << "\" x2=\"" << num(px) << "\" y2=\"" << num(B)
      << "\" stroke=\"#e0e0e0\"/>\n<text x=\"" << num(px) << "\" y=\"" << num(B + 18) << "\" text-anchor=\"middle\">"
      << tick_label(t) << "</text>\n";
  }
  for (double t : ay.ticks()) {
    double py = ay.map(t, B, T);
    s << "<line x1=\"" << num(L) << "\" y1=\"" << num(py) << "\" x2=\"" << num(R) << "\" y2=\"" << num(py)
      << "\" stroke=\"#e0e0e0\"/>\n<text x=\"" << num(L - 6) << "\" y=\"" << num(py + 4) << "\" text-anchor=\"end\">"
      << tick_label(t) << "</text>\n";
  }
  s << "<rect x=\"" << num(L) << "\" y=\"" << num(T) << "\" width=\"" << num(R - L) << "\" height=\"" << num(B - T)
    << "\" fill=\"none\" stroke=\"black\"/>\n"
    << "<text x=\"" << num((L + R) / 2) << "\" y=\"" << num(B + 42) << "\" text-anchor=\"middle\">"
    << html_escape(o.x_label) << (o.log_x ? " (log scale)" : "") << "</text>\n"
    << "<text transform=\"translate(22," << num((T + B) / 2) << ") rotate(-90)\" text-anchor=\"middle\">"
    << html_escape(o.y_label) << (o.log_y ? " (log scale)" : "") << "</text>\n";
  std::vector<LabelBox> labels;  // the point labels placed so far
  for (size_t k = 0; k < series.size(); ++k) {
    const auto& se = series[k];
    const char* c = kColours[size_t(se.colour >= 0 ? se.colour : int(k)) % 10];
    const char* dash = se.dashed ? "\" stroke-dasharray=\"6,4" : "";
    std::string pts;
    for (size_t i = 0; i < se.x.size() && i < se.y.size(); ++i) {
      if (!usable(se.x[i], se.y[i], o)) continue;
      double px = ax.map(se.x[i], L, R), py = ay.map(se.y[i], B, T);
      pts += num(px) + "," + num(py) + " ";
      s << "<circle cx=\"" << num(px) << "\" cy=\"" << num(py) << "\" r=\"3.5\" fill=\"" << c << "\"/>\n";
      if (i < se.point_labels.size() && !se.point_labels[i].empty()) {
        const LabelSpot at = place_label(labels, px, py, se.point_labels[i].size(), L, R, T, B);
        s << "<text x=\"" << num(at.x) << "\" y=\"" << num(at.y) << "\"" << (at.end ? " text-anchor=\"end\"" : "")
          << " font-size=\"10\" fill=\"" << c << "\">" << html_escape(se.point_labels[i]) << "</text>\n";
      }
    }
    s << "<polyline points=\"" << pts << "\" fill=\"none\" stroke=\"" << c << dash << "\" stroke-width=\"2\"/>\n";
    s << "<line x1=\"" << num(R + 15) << "\" y1=\"" << num(ly) << "\" x2=\"" << num(R + 40) << "\" y2=\"" << num(ly)
      << "\" stroke=\"" << c << dash << "\" stroke-width=\"2\"/>\n<text x=\"" << num(R + 46) << "\" y=\"" << num(ly + 4)
      << "\">";
    const std::vector<std::string> lines = wrapped(se.name, legend_chars);
    for (size_t i = 0; i < lines.size(); ++i)
      s << "<tspan x=\"" << num(R + 46) << "\" dy=\"" << (i ? "14" : "0") << "\">" << html_escape(lines[i])
        << "</tspan>";
    s << "</text>\n";
    ly += 20 + 14.0 * double(lines.size() - 1);
  }
  s << "</svg>\n";
  return s.str();
}

namespace {

// librsvg and cairo rasterise the chart in this process (no user string, the output path
// included, ever reaches a shell); the pixels go through the one image writer, atomically
// like the SVG.
std::string svg_to_png(const std::string& svg, int width, int height, const std::string& png_path) {
  GError* error = nullptr;
  RsvgHandle* handle = rsvg_handle_new_from_data(reinterpret_cast<const guint8*>(svg.data()), svg.size(), &error);
  if (!handle) {
    std::string why = error ? error->message : "unknown error";
    if (error) g_error_free(error);
    return "no PNG for " + png_path + ": librsvg cannot read the chart (" + why + ")";
  }
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);  // an opaque page: viewers show transparency as black
  cairo_paint(cr);
  RsvgRectangle viewport{0, 0, double(width), double(height)};
  const bool drawn = rsvg_handle_render_document(handle, cr, &viewport, &error);
  std::vector<uint8_t> rgb;
  if (drawn) {
    // ARGB32 is one native-endian uint32 per pixel; on the opaque page alpha is 255, so
    // the premultiplied channels are the colour itself.
    cairo_surface_flush(surface);
    const unsigned char* data = cairo_image_surface_get_data(surface);
    const int stride = cairo_image_surface_get_stride(surface);
    rgb.resize(size_t(width) * size_t(height) * 3);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        uint32_t p;
        std::memcpy(&p, data + size_t(y) * size_t(stride) + 4 * size_t(x), 4);
        uint8_t* o = &rgb[3 * (size_t(y) * size_t(width) + size_t(x))];
        o[0] = uint8_t(p >> 16), o[1] = uint8_t(p >> 8), o[2] = uint8_t(p);
      }
  }
  std::string why = error ? error->message : "";
  if (error) g_error_free(error);
  cairo_destroy(cr);
  cairo_surface_destroy(surface);
  g_object_unref(handle);
  if (!drawn) return "no PNG for " + png_path + ": librsvg could not draw it " + why;
  write_png_rgb8(png_path, rgb.data(), width, height);
  return "";
}

}  // namespace

std::string write_chart(const std::string& svg_path, const std::vector<ChartSeries>& series,
                        const ChartOptions& options) {
  const std::string svg = line_chart_svg(series, options);
  write_file_atomic(svg_path, svg);
  std::string png = svg_path.size() > 4 && svg_path.substr(svg_path.size() - 4) == ".svg"
                        ? svg_path.substr(0, svg_path.size() - 4) + ".png"
                        : svg_path + ".png";
  return svg_to_png(svg, options.width, options.height, png);
}

}  // namespace nns::report
