#include "data/image_dataset.h"

#include <algorithm>
#include <atomic>
#include <thread>
#include <exception>
#include <stdexcept>

#include "data/exr_io.h"

namespace nns::data {
namespace {

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

}  // namespace

ImageDataset::ImageDataset(std::vector<std::string> paths, ImageDatasetOptions options)
    : paths_(std::move(paths)), o_(std::move(options)) {
  if (o_.inputs.empty()) throw std::invalid_argument("ImageDataset: no input channels chosen");
  channels_ = o_.inputs;
  channels_.insert(channels_.end(), o_.targets.begin(), o_.targets.end());
  if (o_.augment && contains(channels_, "N.X") != contains(channels_, "N.Y"))
    throw std::invalid_argument("ImageDataset: augmentation rotates normals, so choose both N.X and N.Y");

  if (o_.crop_width < 0 || o_.crop_height < 0 || (o_.crop_width == 0) != (o_.crop_height == 0))
    throw std::invalid_argument("ImageDataset: crop must be both 0 (whole views) or both > 0");

  // Headers first: sizes, fov, channel presence, and the memory this would take.
  const size_t n = paths_.size();
  widths_.resize(n);
  heights_.resize(n);
  fovs_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    ReadOptions ro;
    ro.header_only = true;
    ro.require_attributes = false;
    ExrInfo info;
    View h = read_view(paths_[i], ro, &info);
    for (auto& c : channels_) {
      bool present = std::any_of(info.channels.begin(), info.channels.end(),
                                 [&](const ExrInfo::Channel& ch) { return ch.name == c; });
      if (!present && !contains(o_.zero_if_missing, c))
        throw std::runtime_error(paths_[i] + ": missing channel '" + c + "' (chosen as " +
                                 (contains(o_.inputs, c) ? "input" : "target") + ")");
    }
    if (o_.crop_width > h.width || o_.crop_height > h.height)
      throw std::runtime_error(paths_[i] + ": view " + std::to_string(h.width) + "x" + std::to_string(h.height) +
                               " is smaller than the crop " + std::to_string(o_.crop_width) + "x" +
                               std::to_string(o_.crop_height));
    if (o_.crop_width == 0 && i > 0 && (h.width != widths_[0] || h.height != heights_[0]))
      throw std::runtime_error(paths_[i] + ": view is " + std::to_string(h.width) + "x" + std::to_string(h.height) +
                               " but " + paths_[0] + " is " + std::to_string(widths_[0]) + "x" +
                               std::to_string(heights_[0]) + "; set a crop size to mix sizes");
    widths_[i] = h.width;
    heights_[i] = h.height;
    fovs_[i] = h.fov_y_deg;
    bytes_ += int64_t(h.width) * h.height * int64_t(channels_.size()) * int64_t(sizeof(float));
  }

  in_memory_ = bytes_ <= o_.memory_budget_bytes;
  if (!in_memory_) return;
  planes_.resize(n);
  // Decoding is the slow part and views are independent: two threads share them, each
  // view landing in its own slot, so the result does not depend on who decoded what.
  // (A private thread rather than core/thread_pool.h: its first job after the pool is
  // created can be missed by a worker that starts late, which hangs; reported.)
  std::vector<std::exception_ptr> errors(n);
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i; (i = next.fetch_add(1)) < n;) {
      try {
        planes_[i] = load_planes(i);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  std::thread helper;
  if (n > 1) helper = std::thread(work);
  work();
  if (helper.joinable()) helper.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

std::vector<float> ImageDataset::load_planes(size_t i) const {
  ReadOptions ro;
  ro.require_attributes = false;
  ro.only_channels = channels_;
  View v = read_view(paths_[i], ro);
  if (v.width != widths_[i] || v.height != heights_[i])
    throw std::runtime_error(paths_[i] + ": changed size since the dataset was opened");
  const size_t n = size_t(v.width) * size_t(v.height);
  std::vector<float> out(channels_.size() * n, 0.0f);
  for (size_t c = 0; c < channels_.size(); ++c)
    if (v.has(channels_[c])) std::copy(v.channel(channels_[c]).begin(), v.channel(channels_[c]).end(), out.begin() + long(c * n));
  return out;
}

std::vector<size_t> ImageDataset::shuffled_order(Rng& rng) const {
  std::vector<size_t> order(size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  for (size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);  // Fisher-Yates
  return order;
}

Batch ImageDataset::batch(const std::vector<size_t>& indices, Rng rng) const {
  if (indices.empty()) throw std::invalid_argument("ImageDataset::batch: no indices");
  const bool crop = o_.crop_width > 0;
  const int cw = crop ? o_.crop_width : widths_[indices[0]];
  const int ch = crop ? o_.crop_height : heights_[indices[0]];
  // Quarter turns of a non-square sample would change its shape within the batch.
  const bool turns = cw == ch;
  const int64_t N = int64_t(indices.size()), Ci = int64_t(o_.inputs.size()), Ct = int64_t(o_.targets.size());
  const int out_w = cw, out_h = ch;
  Batch b;
  b.input = Tensor<float>({N, Ci, out_h, out_w});
  if (Ct) b.target = Tensor<float>({N, Ct, out_h, out_w});
  const size_t pn = size_t(cw) * size_t(ch);
  std::vector<float> window(channels_.size() * pn), turned(window.size());

  for (int64_t j = 0; j < N; ++j) {
    const size_t idx = indices[size_t(j)];
    if (idx >= size()) throw std::out_of_range("ImageDataset::batch: index " + std::to_string(idx) + " of " + std::to_string(size()));
    Rng r = rng.fork(uint64_t(j));
    SampleInfo info;
    info.index = idx;
    info.view_width = widths_[idx];
    info.view_height = heights_[idx];
    info.fov_y_deg = fovs_[idx];
    info.x0 = crop ? int(r.below(uint64_t(widths_[idx] - cw + 1))) : 0;
    info.y0 = crop ? int(r.below(uint64_t(heights_[idx] - ch + 1))) : 0;
    if (o_.augment) {
      info.symmetry = Dihedral::random(r);
      if (!turns) info.symmetry.quarter_turns &= 2;  // 0 or 180 degrees only
    }
    std::vector<float> streamed;
    if (!in_memory_) streamed = load_planes(idx);
    const std::vector<float>& stored = in_memory_ ? planes_[idx] : streamed;
    const size_t vw = size_t(widths_[idx]), vn = vw * size_t(heights_[idx]);
    for (size_t c = 0; c < channels_.size(); ++c)
      for (int y = 0; y < ch; ++y) {
        const float* src = stored.data() + c * vn + size_t(info.y0 + y) * vw + size_t(info.x0);
        std::copy(src, src + cw, window.data() + c * pn + size_t(y) * size_t(cw));
      }
    const float* out = window.data();
    if (o_.augment) {
      transform_planes(channels_, window.data(), cw, ch, info.symmetry, turned.data());
      out = turned.data();
    }
    std::copy(out, out + size_t(Ci) * pn, b.input.data() + j * Ci * int64_t(pn));
    if (Ct) std::copy(out + size_t(Ci) * pn, out + channels_.size() * pn, b.target.data() + j * Ct * int64_t(pn));
    b.info.push_back(info);
  }
  return b;
}

}  // namespace nns::data
