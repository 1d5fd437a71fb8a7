#pragma once
// The training frames of a GAN run: held in memory, or streamed from disk when they
// would not fit (data larger than memory). Streaming reads item i from its
// EXR files exactly as load_samples does, so sample i is the same bytes either way and a
// streamed run is bitwise equal to an in-memory one (tested). While step j trains, the
// next item of the epoch's order is read on a thread of its own (std::async): the order
// depends on (seed, epoch) only, so what is prefetched never depends on timing.
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "runs/gi/gi_samples.h"

namespace nns::runs {

class GiTrainData {
 public:
  // In memory: every sample loaded up front.
  explicit GiTrainData(std::vector<gi::GiSample> samples) : samples_(std::move(samples)) {}
  // Streamed: item i of `split` read when asked for; `n` items (max_items applied).
  GiTrainData(data::SplitListing split, GiItemReader rd, gi::GiInputConfig cfg, size_t n)
      : stream_(std::make_unique<Stream>(std::move(split), rd, std::move(cfg), n)) {}

  size_t size() const { return stream_ ? stream_->n : samples_.size(); }
  bool empty() const { return size() == 0; }
  bool streamed() const { return stream_ != nullptr; }

  // Sample i, valid until the next call; `next` (if any) is read ahead meanwhile.
  const gi::GiSample& get(size_t i, std::optional<size_t> next = std::nullopt) {
    if (!stream_) return samples_.at(i);
    Stream& s = *stream_;
    if (s.ahead && s.ahead_index == i) {
      s.current = s.ahead->get();  // rethrows a reader's error (file named) here
      s.ahead.reset();
    } else {
      if (s.ahead) s.ahead->wait(), s.ahead.reset();  // a prefetch nobody asked for
      s.current = load_sample(s.split, s.rd, s.cfg, i);
    }
    if (next) {
      s.ahead_index = *next;
      const size_t k = *next;
      s.ahead = std::async(std::launch::async, [&s, k] { return load_sample(s.split, s.rd, s.cfg, k); });
    }
    return s.current;
  }

 private:
  struct Stream {
    Stream(data::SplitListing s, GiItemReader r, gi::GiInputConfig c, size_t count)
        : split(std::move(s)), rd(r), cfg(std::move(c)), n(count) {}
    data::SplitListing split;
    GiItemReader rd;
    gi::GiInputConfig cfg;
    size_t n = 0;
    gi::GiSample current;
    // Declared after what the prefetch reads: a std::async future's destructor waits for
    // its task, so the read finishes before split/rd/cfg go away.
    std::optional<std::future<gi::GiSample>> ahead;
    size_t ahead_index = 0;
  };
  std::vector<gi::GiSample> samples_;
  std::unique_ptr<Stream> stream_;
};

}  // namespace nns::runs
