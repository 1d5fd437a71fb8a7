#pragma once
// Tensor<T>: a contiguous N-d array (row-major; images are NCHW) with shared storage.
//
// Copies share storage (like a shared_ptr); clone() makes a deep copy. There are no
// strides: every kernel may assume contiguous data. reshape() is the one view, because
// it is free. T is float for training and double for gradient checks.
#include <algorithm>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/allocator.h"
#include "core/shape.h"
#include "core/thread_pool.h"

namespace nns {

template <class T>
class Storage {
 public:
  explicit Storage(int64_t n) : n_(n) {
    data_ = static_cast<T*>(CachingAllocator::instance().allocate(sizeof(T) * size_t(n)));
  }
  ~Storage() { CachingAllocator::instance().release(data_, sizeof(T) * size_t(n_)); }
  Storage(const Storage&) = delete;
  Storage& operator=(const Storage&) = delete;
  T* data() { return data_; }
  int64_t size() const { return n_; }

 private:
  T* data_ = nullptr;
  int64_t n_ = 0;
};

template <class T>
class Tensor {
 public:
  using value_type = T;

  Tensor() = default;
  // Uninitialised contents: use zeros()/full() when the values matter.
  explicit Tensor(const Shape& shape) : shape_(shape), storage_(std::make_shared<Storage<T>>(shape.numel())) {}

  static Tensor empty(const Shape& s) { return Tensor(s); }
  static Tensor zeros(const Shape& s) { return full(s, T(0)); }
  static Tensor ones(const Shape& s) { return full(s, T(1)); }
  static Tensor full(const Shape& s, T v) {
    Tensor t(s);
    t.fill(v);
    return t;
  }
  static Tensor from(const Shape& s, const std::vector<T>& values) {
    if (int64_t(values.size()) != s.numel())
      throw std::invalid_argument("Tensor::from: " + std::to_string(values.size()) + " values for shape " + s.str());
    Tensor t(s);
    std::copy(values.begin(), values.end(), t.data());
    return t;
  }

  bool defined() const { return storage_ != nullptr; }
  const Shape& shape() const { return shape_; }
  int dim() const { return shape_.dim(); }
  int64_t size(int i) const { return shape_[i]; }
  int64_t numel() const { return shape_.numel(); }

  T* data() { return storage_ ? storage_->data() : nullptr; }
  const T* data() const { return storage_ ? storage_->data() : nullptr; }
  T* begin() { return data(); }
  T* end() { return data() + numel(); }
  const T* begin() const { return data(); }
  const T* end() const { return data() + numel(); }
  T& operator[](int64_t i) { return data()[i]; }
  const T& operator[](int64_t i) const { return data()[i]; }

  // Large fills (gradient buffers of whole layers) are split over the workers: one
  // thread writing 100 MB of zeros left the other idle for ~3% of a GAN iteration.
  void fill(T v) {
    T* p = data();
    parallel_for(
        numel(), [&](int64_t b, int64_t e) { std::fill(p + b, p + e, v); }, kParallelFill);
  }
  void zero() {
    T* p = data();
    parallel_for(
        numel(), [&](int64_t b, int64_t e) { std::memset(static_cast<void*>(p + b), 0, sizeof(T) * size_t(e - b)); },
        kParallelFill);
  }

  // A view of the same storage with another shape of the same size.
  Tensor reshape(const Shape& s) const {
    if (s.numel() != numel()) throw std::invalid_argument("reshape: " + shape_.str() + " to " + s.str());
    Tensor t = *this;
    t.shape_ = s;
    return t;
  }
  Tensor clone() const {
    Tensor t(shape_);
    if (numel()) std::memcpy(static_cast<void*>(t.data()), data(), sizeof(T) * size_t(numel()));
    return t;
  }
  template <class U>
  Tensor<U> cast() const {
    Tensor<U> t(shape_);
    for (int64_t i = 0; i < numel(); ++i) t[i] = static_cast<U>((*this)[i]);
    return t;
  }
  // True if both tensors use the same storage.
  bool shares_storage(const Tensor& o) const { return storage_ == o.storage_; }

 private:
  static constexpr int64_t kParallelFill = int64_t(1) << 17;  // elements per worker, at least
  Shape shape_;
  std::shared_ptr<Storage<T>> storage_;
};

template <class T>
inline void check_shape(const Tensor<T>& t, const Shape& s, const char* what) {
  if (t.shape() != s)
    throw std::invalid_argument(std::string(what) + ": expected shape " + s.str() + ", got " + t.shape().str());
}

}  // namespace nns
