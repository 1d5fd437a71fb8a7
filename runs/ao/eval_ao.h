#pragma once
// eval-ao's job: every AO method at every sample count on every view of a dataset, timed
// and scored against the ray-traced AO — the paper's Table 1 and Figure 4 for this data.
//
//   eval-ao --data DIR --model nnao.blob --out DIR [--methods NNAO,SSAO,...] [--threads 2]
//   eval-ao --data DIR --ladder LADDER --out DIR     (every rung of a trained NNAO ladder)
//
// DIR is a split folder or a flat folder; a dataset root with train/ + test/ means its
// test/ split. Writes results.csv, results_by_scene.csv, results_by_family.csv,
// failure_bands.csv, temporal.csv, timing.csv, pareto.csv, speed_vs_accuracy.svg/.png,
// flicker_vs_time.svg, previews/, report.md and report.html.
// Temporal stability is measured on camera-path frames (files "<scene>-pNN-fNNN.exr", or
// surround frame folders of that name, as render-dataset --path-frames writes them),
// reprojected: classical_ao/temporal.h.
//
// Timing is the same for every method: the same frames, the same thread pool, the same
// loop; each method's wall time and the CPU time of the caller and the pool's workers
// (pool_cpu_ms) are kept per view, and their ratio (the threads a method really kept
// busy) is in timing.csv and the report.
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "runs/ao/eval_ao_evaluation.h"
#include "runs/ao/eval_ao_report.h"
#include "runs/ao/nnao_ladder.h"

namespace nns::runs {

// The NNAO models of the options: one blob, or every rung of a ladder.
inline MethodInputs load_method_inputs(const EvalAoOptions& o) {
  MethodInputs in;
  if (!o.model.empty() && !o.ladder.empty()) throw std::invalid_argument("--model and --ladder: give one of them");
  if (!o.model.empty()) in.models.push_back(nnao::NnaoWeights::load(o.model));
  if (!o.ladder.empty())
    for (const auto& e : runs::read_ladder(o.ladder)) {
      in.models.push_back(nnao::NnaoWeights::load(e.blob));
      in.model_settings.push_back(e.name);
    }
  in.classical =
      o.params_file.empty() ? classical_ao::ClassicalParams{} : classical_ao::read_classical_params(o.params_file);
  return in;
}

// Scores every method on the split, writes the tables, charts, previews and report into
// o.out and prints the results table; returns what the charts' notes say (the caller
// names the files: o.out may be a stage, core/staged_output.h).
inline ChartNotes evaluate_ao(const EvalAoOptions& o) {
  const EvalViews views = open_split(o);
  MethodInputs in = load_method_inputs(o);
  fs::create_directories(fs::path(o.out) / "previews");
  const Evaluation ev = evaluate_views(o, views.files, in);
  const std::string csv = write_tables(o, ev);
  const ChartNotes notes = write_charts(o, ev);
  const std::vector<ParetoRow> front = write_pareto(o, ev);
  write_report(o, ev, views, in, notes, front);
  std::printf("%s", csv.c_str());
  return notes;
}

}  // namespace nns::runs
