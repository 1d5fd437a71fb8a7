#pragma once
// ImageDataset: views as NCHW float tensors for training — chosen input and target
// channels, random crops, the eight square symmetries (data/augment.h), batches that are
// a function of (indices, Rng) alone.
//
//   ImageDatasetOptions o;
//   o.inputs = {"Z", "N.X", "N.Y", "N.Z"};  o.targets = {"AO"};
//   o.crop_width = o.crop_height = 64;  o.augment = true;
//   ImageDataset data(listing.train.views, o);         // loads into memory, or streams
//   Rng epoch_rng(seed);
//   auto order = data.shuffled_order(epoch_rng);
//   Prefetcher<Batch> p(order.size() / 16, [&](size_t k) {
//     return data.batch({order.begin() + 16 * k, order.begin() + 16 * (k + 1)}, epoch_rng.fork(k));
//   });
//
// Views are kept in memory (only the chosen channels, as floats) unless that exceeds
// `memory_budget_bytes`; then every sample is read from disk when asked for (use a
// Prefetcher so the reading overlaps training). Both give identical batches.
#include <cstdint>
#include <string>
#include <vector>

#include "core/rng.h"
#include "core/tensor.h"
#include "data/augment.h"

namespace nns::data {

struct ImageDatasetOptions {
  std::vector<std::string> inputs;            // input channels, in this order
  std::vector<std::string> targets;           // target channels (may be empty)
  std::vector<std::string> zero_if_missing;   // optional channels (e.g. "emission.R")
  int crop_width = 0, crop_height = 0;        // 0: whole views (then all the same size)
  bool augment = false;                       // a random symmetry per sample
  int64_t memory_budget_bytes = int64_t(2) << 30;
};

// Where a sample came from and how it was transformed: enough to reconstruct positions
// from depth (the crop's offset from the principal point) and to undo the symmetry.
struct SampleInfo {
  size_t index = 0;               // in the dataset
  int x0 = 0, y0 = 0;             // crop origin in the stored view (before the symmetry)
  int view_width = 0, view_height = 0;
  float fov_y_deg = 0;            // of the stored view
  Dihedral symmetry;
};

struct Batch {
  Tensor<float> input;    // (N, inputs, h, w)
  Tensor<float> target;   // (N, targets, h, w); undefined when there are no targets
  std::vector<SampleInfo> info;
};

class ImageDataset {
 public:
  // Throws "<file>: ..." for an unreadable view or a missing channel; checks every view's
  // header up front even when streaming, so a bad file fails now, not mid-training.
  ImageDataset(std::vector<std::string> paths, ImageDatasetOptions options);

  size_t size() const { return paths_.size(); }
  bool in_memory() const { return in_memory_; }
  int64_t bytes_needed() const { return bytes_; }
  const ImageDatasetOptions& options() const { return o_; }
  const std::string& path(size_t i) const { return paths_[i]; }

  // A random permutation of [0, size()).
  std::vector<size_t> shuffled_order(Rng& rng) const;

  // Sample j of the batch draws its crop and symmetry from rng.fork(j). With a crop and
  // quarter turns, crops must be square or the symmetry is restricted to 180-degree turns
  // and mirrors so that every sample of the batch has the same shape.
  Batch batch(const std::vector<size_t>& indices, Rng rng) const;

 private:
  // Reads the chosen channels (inputs then targets) of view i: C planes of h x w.
  std::vector<float> load_planes(size_t i) const;

  std::vector<std::string> paths_;
  ImageDatasetOptions o_;
  std::vector<std::string> channels_;  // inputs then targets
  std::vector<int> widths_, heights_;
  std::vector<float> fovs_;
  std::vector<std::vector<float>> planes_;  // when in memory
  bool in_memory_ = true;
  int64_t bytes_ = 0;
};

}  // namespace nns::data
