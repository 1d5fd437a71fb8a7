#pragma once
// Dataset validation for `dataset-info` (docs/dataset-format.md): every file is read,
// every problem names the file and the channel, and nothing throws past
// validate_dataset() — a corrupt file is a problem in the report, not a crash.
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "data/exr_io.h"
#include "data/view.h"

namespace nns::data {

// Which trainer the dataset is for decides the required channels: Z and N.X/N.Y/N.Z
// always; AO for nnao; albedo, direct and (front views only) indirect for gi.
enum class Purpose { any, nnao, gi };

struct Problem {
  std::string file, channel, message;
  bool warning = false;     // reported, but does not make the dataset fail
  std::string split;        // "train", "test" or "flat" when found by validate_dataset
  std::string str() const;  // "<file>: channel '<channel>': <message>[ in split '<split>']"
};

struct ChannelSummary {
  int64_t files = 0;
  double min = 0, max = 0;  // over finite values (Z: over non-sky pixels)
  bool any_finite = false;
  int64_t sky = 0, pixels = 0;  // Z only: sky pixels, all pixels
};

struct ValidationReport {
  std::string root;
  bool flat = false;
  std::map<std::string, int64_t> views, frames;         // per split ("train", "test")
  std::map<std::string, int64_t> resolutions;           // "WxH" -> files
  std::map<std::string, std::set<std::string>> scenes;  // split -> scene names ("holdout" too)
  // DIR/metadata.txt, when present (render-dataset writes it for every render; before
  // that, for nnao-v2, surround-v2 .. v4 and --holdout-families): every "key: value"
  // line, and the "families.<split>" lists. Its "views.<split>" counts are checked
  // against the folders (an error when they differ).
  bool has_metadata = false;
  std::map<std::string, std::string> metadata;
  std::map<std::string, std::vector<std::string>> split_families;
  std::map<std::string, ChannelSummary> channels;
  std::vector<Problem> problems;     // the first max_problems errors and warnings
  int64_t errors = 0, warnings = 0;  // all of them, also those not kept
  bool clean() const { return errors == 0; }
};

struct ValidateOptions {
  Purpose purpose = Purpose::any;
  int64_t max_problems = 50;
  // |N| may differ from 1 by this much (HALF storage alone gives ~1e-3).
  double normal_tolerance = 1e-2;
  // Handed every view that was read, after its checks, in the listing's order and on the
  // calling thread: a trainer keeps what it trains on (kept_views.h) instead of decoding
  // the file again.
  std::function<void(View&&)> on_view;
};

// Collects problems, keeping the first `limit` and counting the rest.
class ProblemSink {
 public:
  explicit ProblemSink(ValidationReport& r, int64_t limit) : r_(r), limit_(limit) {}
  void error(const std::string& file, const std::string& channel, const std::string& message) {
    add({file, channel, message, false, ""});
  }
  void warn(const std::string& file, const std::string& channel, const std::string& message) {
    add({file, channel, message, true, ""});
  }
  // The split the next problems belong to ("" outside a split).
  void set_split(std::string split) { split_ = std::move(split); }

 private:
  void add(Problem p) {
    if (!p.file.empty()) p.split = split_;
    (p.warning ? r_.warnings : r_.errors)++;
    if (int64_t(r_.problems.size()) < limit_) r_.problems.push_back(std::move(p));
  }
  ValidationReport& r_;
  int64_t limit_;
  std::string split_;
};

// Checks one view already in memory. `is_front` is false for the five non-front faces of
// a surround frame, which need no GI target. `info` (may be null) tells which channels
// were HALF and which attributes existed.
void check_view(const View& v, const ExrInfo* info, bool is_front, const ValidateOptions& o, ProblemSink& sink,
                ValidationReport* summary = nullptr);

ValidationReport validate_dataset(const std::string& root, const ValidateOptions& o);

// The family of a procedural scene name "<family>-<instance>" (the name without its
// trailing "-<digits>"); a name without such a suffix is its own family.
std::string scene_family_of(const std::string& scene);

void print_report(std::FILE* out, const ValidationReport& r);

}  // namespace nns::data
