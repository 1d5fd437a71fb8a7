#pragma once
// A validation split carved from the training split: whole scenes (as the test split
// is made), so model selection — the size sweep, every default — never looks at the
// test split and never at another pixel of a scene it trains on.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "data/dataset.h"
#include "data/validate.h"

namespace nns::data {

// {training, validation}: about `fraction` of the items of `train`, whole scenes,
// moved to validation (split_flat_by_scene's rule). fraction <= 0: nothing moves.
inline std::pair<SplitListing, SplitListing> hold_out_validation(const SplitListing& train, double fraction) {
  if (fraction <= 0) return {train, SplitListing{train.dir + " (no validation)", {}, {}}};
  DatasetListing flat;
  flat.root = train.dir;
  flat.flat = true;
  flat.train = train;
  DatasetListing s = split_flat_by_scene(flat, fraction);
  s.test.dir = train.dir + " (validation scenes)";
  return {s.train, s.test};
}

// {training, validation}: every view of the named scene families (header `scene`,
// family = the name without its trailing "-<number>") moved to validation — the
// held-out-families judgement of the test data, made inside the training split so
// that model selection can aim at geometry it did not train on. Throws naming a family
// that has no view.
inline std::pair<SplitListing, SplitListing> hold_out_validation_families(const SplitListing& train,
                                                                          const std::vector<std::string>& families) {
  SplitListing kept{train.dir, {}, {}}, val{train.dir + " (validation families)", {}, {}};
  std::vector<int> seen(families.size(), 0);
  for (auto& v : train.views) {
    const auto it = std::find(families.begin(), families.end(), scene_family_of(scene_of(v)));
    if (it == families.end()) kept.views.push_back(v);
    else val.views.push_back(v), seen[size_t(it - families.begin())] = 1;
  }
  for (size_t i = 0; i < families.size(); ++i)
    if (!seen[i])
      throw std::runtime_error(train.dir + ": no training view of family '" + families[i] + "' to validate on");
  return {kept, val};
}

// The share of a flat dataset's scenes (no train/ and test/ folders) that becomes its
// test split: whole scenes, never pixels.
inline constexpr double kFlatTestFraction = 0.2;

// The dataset's train and test splits: its folders, or a flat folder split by scene.
inline DatasetListing list_splits(const std::string& dir) {
  DatasetListing d = list_dataset(dir);
  if (d.flat) d = split_flat_by_scene(d, kFlatTestFraction);
  return d;
}

// What a trainer reads: the listing, whose train split has lost the validation scenes,
// and the validation split.
struct TrainingSplits {
  DatasetListing listing;
  SplitListing validation;
};

// The splits with about `validation_fraction` of the training scenes held out, or
// (when named) every view of `validation_families`. Throws when nothing is left to
// train on.
inline TrainingSplits open_training_splits(const std::string& dir, double validation_fraction,
                                           const std::vector<std::string>& validation_families = {}) {
  TrainingSplits s{list_splits(dir), {}};
  if (s.listing.train.size() == 0) throw std::runtime_error(dir + ": no training views or frames found");
  std::tie(s.listing.train, s.validation) = validation_families.empty()
                                                ? hold_out_validation(s.listing.train, validation_fraction)
                                                : hold_out_validation_families(s.listing.train, validation_families);
  if (s.listing.train.size() == 0)
    throw std::runtime_error(dir + ": no training views left after the validation split");
  return s;
}

}  // namespace nns::data
