#pragma once
// The report a run leaves for people: report.md and report.html, both written from one
// list of blocks (headings, paragraphs, tables, charts, image comparisons), so the page
// shows exactly the rows of the markdown and neither is ever parsed back from the other.
//
//   Report r("AO evaluation");
//   r.text("Data: `" + dir + "`, ...");          // `code` and **bold**, as in markdown
//   r.chart("speed_vs_accuracy.svg", "speed vs accuracy");
//   r.table({{"method", "MSE"}, {{"SSAO", "0.012"}}});
//   r.comparison({"view 0", {{"ground truth", "previews/v0_gt.png", ""}, ...}});
//   r.write(out_dir);                            // report.md and report.html, atomically
//
// The page is self-contained (images are files beside it, nothing comes from the
// network) and needs no JavaScript: a comparison flips between its images with radio
// buttons and CSS — click a thumbnail, or the arrow keys once one has focus — the way
// pix2pix's results page puts input, output and target side by side, plus the numbers.
// Every string is escaped and every file name percent-encoded, so a hostile path or
// model label cannot inject markup.
#include <string>
#include <string_view>
#include <vector>

namespace nns::report {

// Text for HTML (element content and quoted attributes): & < > " ' become entities.
std::string html_escape(std::string_view s);
// A relative file path as a URL path: every byte but [A-Za-z0-9-._~/] percent-encoded,
// so it names the file and nothing else (no scheme, query, fragment or quote survives).
std::string url_path(std::string_view path);
// One paragraph of markdown's inline subset (`code`, **bold**) as escaped HTML.
std::string inline_html(std::string_view markdown);

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};
// A GitHub-style markdown table ('|' inside a cell escaped).
std::string markdown(const Table& t);

struct ComparisonImage {
  std::string label;    // "ground truth", "SSAO, 16 samples", "SSAO error"
  std::string file;     // relative to the report's folder
  std::string numbers;  // "MSE 0.0123, SSIM 0.871" (may be empty)
};

struct Comparison {
  std::string title;  // the view or frame
  std::vector<ComparisonImage> images;
};

class Report {
 public:
  explicit Report(std::string title) : title_(std::move(title)) {}
  Report& heading(std::string text);  // a section (## in markdown)
  Report& text(std::string markdown_paragraph);
  Report& list(std::vector<std::string> markdown_items);
  Report& table(Table t);
  // An image the run drew (an SVG chart); `note` says e.g. why its PNG is missing.
  Report& chart(std::string file, std::string caption, std::string note = "");
  Report& comparison(Comparison c);

  std::string markdown() const;
  std::string html() const;
  // DIR/report.md and DIR/report.html, each written to a temporary name and renamed.
  void write(const std::string& dir) const;

 private:
  enum class Kind { heading, text, list, table, chart, comparison };
  struct Block {
    Kind kind;
    std::vector<std::string> s;  // heading/text: [text]; list: items; chart: [file, caption, note]
    Table table;
    Comparison comparison;
  };
  std::string title_;
  std::vector<Block> blocks_;
};

}  // namespace nns::report
