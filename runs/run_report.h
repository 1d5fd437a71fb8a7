#pragma once
// The report of a training run (report.md and report.html, report/html_report.h), the
// same for every trainer: how the run ended, what the trainer adds (its loss chart, its
// sample images), its figures, its metrics per epoch and its configuration — the rows
// of summary.json, metrics.jsonl and the checkpoint's configuration, for people.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "report/html_report.h"
#include "runs/metrics_log.h"

namespace nns::runs {

// The run's metrics, one row per epoch (its last record), at most `max_rows` rows evenly
// spaced over the epochs (the last always shown): a 200-epoch run stays one screen.
inline report::Table epoch_table(const std::vector<MetricsRecord>& records, size_t max_rows = 25) {
  std::vector<const MetricsRecord*> last;  // per epoch
  for (auto& r : records) {
    if (!last.empty() && last.back()->epoch == r.epoch) last.back() = &r;
    else last.push_back(&r);
  }
  report::Table t{{"epoch", "step"}, {}};
  if (last.empty()) return t;
  for (auto& [k, v] : last.back()->values) t.header.push_back(k);
  const size_t n = last.size(), shown = std::min(n, max_rows);
  for (size_t k = 0; k < shown; ++k) {
    const MetricsRecord& r = *last[shown == 1 ? n - 1 : k * (n - 1) / (shown - 1)];
    t.rows.push_back({std::to_string(r.epoch), std::to_string(r.step)});
    for (size_t c = 2; c < t.header.size(); ++c) {
      const double v = r.get(t.header[c]);
      char b[32];
      std::snprintf(b, sizeof b, "%.5g", v);
      t.rows.back().push_back(std::isfinite(v) ? b : "–");  // a non-finite value (null in the log)
    }
  }
  return t;
}

// "1 epoch", "2 epochs".
inline std::string count_of(int64_t n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

// A configuration value for people: a number recorded with 17 significant digits (so
// that it reads back as the same double, 0.29999999999999999) in the fewest digits that
// still do (0.3); any other text as it is.
inline std::string readable_value(const std::string& v) {
  if (v.size() < 17) return v;  // as written (100000 stays 100000, not 1e+05)
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  if (end != v.c_str() + v.size() || !std::isfinite(x)) return v;
  for (int digits = 1; digits <= 17; ++digits) {
    char b[40];
    std::snprintf(b, sizeof b, "%.*g", digits, x);
    if (std::strtod(b, nullptr) == x) return std::string(b).size() < v.size() ? b : v;
  }
  return v;
}

struct RunOutcome {
  std::string app, stop_message;  // stop_message: "" when the run finished
  int64_t epochs_done = 0, steps = 0;
  std::vector<std::pair<std::string, double>> figures;
};

// `add` puts the trainer's own blocks (charts, sample images) after the outcome.
inline report::Report training_report(const RunOutcome& o, const std::vector<MetricsRecord>& records,
                                      const std::vector<std::pair<std::string, std::string>>& config,
                                      const std::function<void(report::Report&)>& add) {
  report::Report r(o.app + " run");
  const std::string done = count_of(o.epochs_done, "epoch") + ", " + count_of(o.steps, "step");
  r.text(o.stop_message.empty() ? "**Finished**: " + done + "."
                                : "**Stopped** after " + done + ": " + o.stop_message + ".");
  if (add) add(r);
  report::Table figures{{"figure", "value"}, {}};
  for (auto& [k, v] : o.figures) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    figures.rows.push_back({k, std::isfinite(v) ? b : "–"});
  }
  r.heading("Figures").text("As in summary.json.").table(figures);
  const report::Table epochs = epoch_table(records);
  r.heading("Metrics per epoch").text("The last record of each epoch (every record: metrics.jsonl).");
  if (epochs.rows.empty()) r.text("No epoch finished.");
  else r.table(epochs);
  report::Table c{{"setting", "value"}, {}};
  for (auto& [k, v] : config) c.rows.push_back({k, readable_value(v)});
  r.heading("Configuration").text("What the checkpoint records; a --resume must match it.").table(c);
  return r;
}

}  // namespace nns::runs
