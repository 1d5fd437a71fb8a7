#pragma once
// The speed/accuracy front of eval-ao: every setting of every method (each classical
// method at each sample count, each NNAO model or ladder rung) with its wall time and
// errors, whether any other setting is at least as fast and at least as accurate (then
// it is not on the front), and for every classical setting the cheapest NNAO setting
// that beats it at no more wall time on the same frames and threads, in MSE and SSIM
// both — or "none". What an engine with a time budget reads off to pick a method.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "report/csv_field.h"
#include "report/html_report.h"

namespace nns::runs {

struct ParetoRow {
  std::string method, setting;
  double ms, cpu_ms, mse, ssim, flicker;  // flicker: x the ground truth's (NaN: no camera paths)
  bool on_front = false;
  std::string beaten_by;  // classical rows: "NNAO-exact@<setting>", or "none"; NNAO rows: empty
  bool is_nnao() const { return method.rfind("NNAO", 0) == 0; }
};

// Marks the front (no other row with wall ms <= and MSE <=, one of them strictly) and,
// for every classical row, the fastest NNAO row with wall ms <= its own, lower MSE and
// higher SSIM.
inline void mark_front_and_wins(std::vector<ParetoRow>& rows) {
  for (auto& r : rows) {
    r.on_front = std::isfinite(r.mse);
    for (auto& q : rows)
      if (&q != &r && q.ms <= r.ms && q.mse <= r.mse && (q.ms < r.ms || q.mse < r.mse)) r.on_front = false;
  }
  for (auto& r : rows) {
    if (r.is_nnao()) continue;
    const ParetoRow* win = nullptr;
    for (auto& q : rows)
      if (q.is_nnao() && q.ms <= r.ms && q.mse < r.mse && q.ssim > r.ssim && (!win || q.ms < win->ms)) win = &q;
    r.beaten_by = win ? win->method + "@" + win->setting : "none";
  }
}

inline std::string pareto_fmt(double v, int prec) {
  if (!std::isfinite(v)) return "";
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", prec, v);
  return b;
}

inline std::string pareto_csv(const std::vector<ParetoRow>& rows) {
  std::string csv = "method,setting,wall_ms,cpu_ms,mse,ssim,flicker_x_truth,on_front,beaten_by_nnao_at_no_more_time\n";
  for (auto& r : rows)
    csv += report::csv_field(r.method) + "," + report::csv_field(r.setting) + "," + pareto_fmt(r.ms, 5) + "," +
           pareto_fmt(r.cpu_ms, 5) + "," + pareto_fmt(r.mse, 6) + "," + pareto_fmt(r.ssim, 6) + "," +
           pareto_fmt(r.flicker, 4) + "," + (r.on_front ? "yes" : "no") + "," + report::csv_field(r.beaten_by) + "\n";
  return csv;
}

inline const ParetoRow* find_row(const std::vector<ParetoRow>& rows, const std::string& tag) {
  for (auto& q : rows)
    if (q.method + "@" + q.setting == tag) return &q;
  return nullptr;
}

// The report's section: the classical settings, each with the NNAO setting that beats it
// at no more time (its time and errors beside), and the front in order of time.
inline void add_pareto_section(report::Report& r, const std::vector<ParetoRow>& rows) {
  int classical = 0, beaten = 0;
  bool any_nnao = false;
  for (auto& q : rows) any_nnao |= q.is_nnao();
  if (!any_nnao) return;
  report::Table t{
      {"classical setting", "ms", "MSE", "SSIM", "beaten at no more time by", "its ms", "its MSE", "its SSIM"}, {}};
  for (auto& q : rows) {
    if (q.is_nnao()) continue;
    ++classical;
    const ParetoRow* w = find_row(rows, q.beaten_by);
    beaten += w != nullptr;
    t.rows.push_back({q.method + "@" + q.setting, pareto_fmt(q.ms, 3), pareto_fmt(q.mse, 4), pareto_fmt(q.ssim, 4),
                      w ? q.beaten_by : "none", w ? pareto_fmt(w->ms, 3) : "-", w ? pareto_fmt(w->mse, 4) : "-",
                      w ? pareto_fmt(w->ssim, 4) : "-"});
  }
  r.heading("The speed/accuracy front");
  r.text(std::to_string(beaten) + " of " + std::to_string(classical) +
         " classical settings are beaten by an NNAO setting that takes no more wall time on the same frames and "
         "threads, with lower MSE and higher SSIM (the fastest such NNAO setting is named). pareto.csv lists every "
         "setting and whether it is on the front (no other setting at least as fast and at least as accurate in MSE).");
  r.table(t);
  report::Table f{{"on the front", "ms", "MSE", "SSIM"}, {}};
  std::vector<const ParetoRow*> front;
  for (auto& q : rows)
    if (q.on_front) front.push_back(&q);
  std::sort(front.begin(), front.end(), [](const ParetoRow* a, const ParetoRow* b) { return a->ms < b->ms; });
  for (auto* q : front)
    f.rows.push_back(
        {q->method + "@" + q->setting, pareto_fmt(q->ms, 3), pareto_fmt(q->mse, 4), pareto_fmt(q->ssim, 4)});
  r.table(f);
}

}  // namespace nns::runs
