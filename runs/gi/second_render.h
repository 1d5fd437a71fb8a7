#pragma once
// Another render of the scored frames: the same scenes and cameras with independent
// Monte-Carlo noise (render-dataset --noise-seed N, the job otherwise unchanged; a job
// with other train/test counts makes the same holdout/ frames). eval-gi scores its light
// as rows of their own (eval_gi.h):
//
//   another render          MSE = 2 x the reference's own noise variance: the noise
//                           floor of every score against this reference
//   another render @L guided  its light box-filtered to face L and brought up by the
//                           guided upsample, as a face-L network's: what a network that
//                           knew the light exactly would score, paying only for the
//                           resolution and a quarter-ish of one render's noise. Unlike
//                           `truth @L guided`, its noise is not the reference's own, so
//                           it does not flatter the ceiling.
//
// A frame is found by its split and name; one missing, or with other geometry, is an
// error naming it.
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "data/dataset.h"
#include "runs/gi/gi_samples.h"

namespace nns::runs {

class SecondRender {
 public:
  explicit SecondRender(const std::string& dir) : listing_(data::list_dataset(dir)) {
    for (const data::SplitListing* s : {&listing_.train, &listing_.test, &listing_.holdout}) {
      for (size_t i = 0; i < s->frames.size(); ++i) items_[key(s->frames[i].dir)] = {s, i};
      for (size_t i = 0; i < s->views.size(); ++i) items_[key(s->views[i])] = {s, i};
    }
  }

  // The frame that is `a` in the other render, read as `rd` reads (its size) and
  // assembled as `cfg` says; the same scene and depth as `a` (noise never moves the
  // geometry), or an error naming both.
  gi::GiSample of(const gi::GiSample& a, const GiItemReader& rd, const gi::GiInputConfig& cfg) const {
    auto it = items_.find(key(a.name));
    if (it == items_.end())
      throw std::runtime_error(listing_.root + ": no frame " + key(a.name) +
                               " (--second-render must be a render of the same frames: render-dataset --noise-seed)");
    gi::GiSample b = load_sample(*it->second.first, rd, cfg, it->second.second);
    if (a.scene != b.scene || a.front_geometry.channel("Z") != b.front_geometry.channel("Z"))
      throw std::runtime_error(b.name + ": not the frame " + a.name +
                               " (other depth); --second-render must render the same scenes and cameras (the "
                               "same --seed and job, another --noise-seed)");
    return b;
  }

 private:
  // The split folder and the item's own name: "holdout/cave-200000-p00-f000".
  static std::string key(const std::string& path) {
    const std::filesystem::path p(path);
    return p.parent_path().filename().string() + "/" + p.filename().string();
  }
  data::DatasetListing listing_;
  std::map<std::string, std::pair<const data::SplitListing*, size_t>> items_;
};

}  // namespace nns::runs
