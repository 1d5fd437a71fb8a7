#pragma once
// A trainer's first act: validate every split of the dataset (data/validate.h, the same
// checks as dataset-info) before the first step, so a bad file in test/ stops the run
// now, not after hours of training when the test split is first read. `keep` (may be
// null) takes the views the trainer will train on as they pass, each file decoded once.
#include <stdexcept>
#include <string>

#include "data/kept_views.h"
#include "data/validate.h"

namespace nns::data {

inline void require_valid_dataset(const std::string& root, Purpose purpose, KeptViews* keep = nullptr) {
  ValidateOptions o;
  if (keep) o.on_view = [keep](View&& v) { keep->offer(std::move(v)); };
  o.purpose = purpose;
  o.max_problems = 5;
  ValidationReport r = validate_dataset(root, o);
  if (r.clean()) return;
  std::string first;
  for (auto& p : r.problems)
    if (!p.warning) first += "\n  " + p.str();
  throw std::runtime_error(root + ": not a valid dataset (" + std::to_string(r.errors) + " error" +
                           (r.errors == 1 ? "" : "s") + "; `dataset-info " + root + "` lists them all):" + first);
}

}  // namespace nns::data
