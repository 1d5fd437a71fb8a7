#pragma once
// A validation split carved from the training split: whole scenes (as the test split
// is made), so model selection — the size sweep, every default — never looks at the
// test split and never at another pixel of a scene it trains on.
#include <string>
#include <utility>

#include "data/dataset.h"

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

}  // namespace nns::data
