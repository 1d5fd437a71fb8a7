#pragma once
// Caching allocator for tensor storage.
//
// Why: a training step allocates the same large buffers every iteration. glibc serves
// large blocks with mmap and returns them on free, so every step would page-fault its
// activations in again (on these VMs that costs as much as the arithmetic). Freed
// blocks are kept in per-size free lists and handed back on the next request of the
// same size class. Blocks are 64-byte aligned (one cache line, one AVX-512 vector).
#include <cstddef>
#include <cstdlib>
#include <mutex>
#include <new>
#include <unordered_map>
#include <vector>

namespace nns {

class CachingAllocator {
 public:
  static CachingAllocator& instance() {
    static CachingAllocator* a = new CachingAllocator();  // never destroyed: storage may outlive statics
    return *a;
  }

  // Size classes: below 4 KiB round to 64 bytes; above, to 1/8 of the enclosing power
  // of two, so at most 12.5% is wasted and a few classes cover all sizes.
  static size_t size_class(size_t bytes) {
    if (bytes <= 4096) return (bytes + 63) & ~size_t(63);
    size_t p = 1;
    while (p < bytes) p <<= 1;
    size_t step = p / 8;
    return (bytes + step - 1) / step * step;
  }

  void* allocate(size_t bytes) {
    size_t cls = size_class(bytes == 0 ? 1 : bytes);
    {
      std::lock_guard<std::mutex> lock(mu_);
      auto it = free_.find(cls);
      if (it != free_.end() && !it->second.empty()) {
        void* p = it->second.back();
        it->second.pop_back();
        cached_ -= cls;
        note_use(cls);
        return p;
      }
    }
    void* p = std::aligned_alloc(64, cls);
    if (!p) {
      trim();
      p = std::aligned_alloc(64, cls);
      if (!p) throw std::bad_alloc();
    }
    std::lock_guard<std::mutex> lock(mu_);
    note_use(cls);
    return p;
  }

  void release(void* p, size_t bytes) {
    if (!p) return;
    size_t cls = size_class(bytes == 0 ? 1 : bytes);
    std::lock_guard<std::mutex> lock(mu_);
    in_use_ -= cls;
    free_[cls].push_back(p);
    cached_ += cls;
  }

  // Return every cached block to the system.
  void trim() {
    std::lock_guard<std::mutex> lock(mu_);
    for (auto& [cls, list] : free_)
      for (void* p : list) std::free(p);
    free_.clear();
    cached_ = 0;
  }

  size_t bytes_in_use() const { return in_use_; }
  size_t bytes_cached() const { return cached_; }
  size_t peak_bytes_in_use() const { return peak_; }
  void reset_peak() { peak_ = in_use_; }

 private:
  void note_use(size_t cls) {
    in_use_ += cls;
    if (in_use_ > peak_) peak_ = in_use_;
  }
  std::mutex mu_;
  std::unordered_map<size_t, std::vector<void*>> free_;
  size_t in_use_ = 0, cached_ = 0, peak_ = 0;
};

}  // namespace nns
