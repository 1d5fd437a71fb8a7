#pragma once
// The views a trainer keeps from the dataset check, so that each training file is decoded
// once before the first step. The check (require_valid_dataset) reads every file in full
// anyway; decoding an EXR is most of a trainer's start-up at face 128 (a surround frame
// is six files), so reading them again to fit the normalisation and a third time to load
// the samples tripled it.
//
//   data::KeptViews kept(paths_to_train_on, budget_bytes, shrink);
//   data::require_valid_dataset(dir, data::Purpose::gi, &kept);
//   if (kept.complete()) v = kept.get(path);   // or take(path) at its last use; else read the file
//
// A view is kept when its path is wanted, after `shrink` (a trainer's box filter to its
// training size) has made it as small as it will be used. Keeping stops, and what was
// kept is dropped, when the kept views would pass the budget or a view cannot be shrunk;
// the trainer then reads from disk and the error, if any, comes from there.
#include <malloc.h>

#include <cstddef>
#include <functional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "data/view.h"

namespace nns::data {

inline size_t view_bytes(const View& v) {
  size_t b = 0;
  for (auto& [name, plane] : v.channels) b += plane.size() * sizeof(float);
  return b;
}

class KeptViews {
 public:
  using Shrink = std::function<View(View&&)>;
  KeptViews(const std::vector<std::string>& wanted, double budget_bytes, Shrink shrink = {})
      : budget_(budget_bytes), shrink_(std::move(shrink)) {
    for (auto& p : wanted) views_.emplace(p, View{});
  }

  // Called by the dataset check with each view it has read and checked.
  void offer(View&& v) {
    if (given_up_) return;
    auto it = views_.find(v.source);
    if (it == views_.end()) return;
    try {
      const size_t read = view_bytes(v);
      View small = shrink_ ? shrink_(std::move(v)) : std::move(v);
      if (shrink_) freed(read);  // the view as read is gone; its shrunk copy stays
      const size_t b = view_bytes(small);
      // The first view's size times the count: a budget that cannot hold them all is
      // known before memory is spent on them.
      if (double(bytes_ + b) > budget_ || (kept_ == 0 && double(b) * double(views_.size()) > budget_))
        return give_up("the decoded training views would take more than the memory budget");
      bytes_ += b, ++kept_;
      it->second = std::move(small);
    } catch (const std::exception& e) {
      give_up(e.what());
    }
  }

  // Every wanted view is here.
  bool complete() const { return !given_up_ && kept_ == views_.size(); }
  // Why keeping stopped ("" while it has not).
  const std::string& reason() const { return reason_; }
  double gib() const { return double(bytes_) / double(size_t(1) << 30); }

  const View& get(const std::string& path) const { return views_.at(path); }
  // Moves a view out (its last use: the kept views shrink as a trainer's samples grow).
  View take(const std::string& path) {
    View& v = views_.at(path);
    const size_t b = view_bytes(v);
    bytes_ -= b;
    freed(b);
    return std::move(v);
  }

 private:
  // A view's planes are small blocks of malloc's heap (64 KiB at face 128), a sample's
  // tensors large mmapped ones: the samples never reuse the freed planes and glibc does
  // not hand them back on its own, so both stayed held (train-gan at face 128: 18.0 GB
  // peak RSS for 10 GiB of samples). A trim every 256 MiB freed returns them (freed
  // memory is trimmed one call late: the caller drops a view after this returns).
  void freed(size_t b) {
    if ((released_ += b) > (size_t(256) << 20)) released_ = 0, malloc_trim(0);
  }
  void give_up(std::string why) {
    given_up_ = true;
    reason_ = std::move(why);
    for (auto& [path, v] : views_) v = View{};
    bytes_ = 0;
    malloc_trim(0);
  }
  double budget_;
  Shrink shrink_;
  std::unordered_map<std::string, View> views_;
  size_t bytes_ = 0, kept_ = 0, released_ = 0;
  bool given_up_ = false;
  std::string reason_;
};

}  // namespace nns::data
