#pragma once
// Prefetcher<T>: a background thread makes items 0, 1, 2, ... of a sequence ahead of
// the consumer, so training never waits on EXR decoding.
//
//   Prefetcher<Batch> p(steps, [&](size_t k) { return data.batch(order_k, rng.fork(k)); });
//   while (auto b = p.next()) train_on(*b);
//
// Items come out in index order and item k is made by make(k) alone, so the sequence is
// the same whatever the timing; that is why make must depend only on k (fork an Rng
// from k, never share one). The queue is bounded (`depth` items) so memory stays flat.
// An exception thrown by make(k) is rethrown by the next() that would return item k.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

namespace nns::data {

template <class T>
class Prefetcher {
 public:
  Prefetcher(size_t count, std::function<T(size_t)> make, size_t depth = 2)
      : count_(count), depth_(depth < 1 ? 1 : depth), make_(std::move(make)) {
    worker_ = std::thread([this] { run(); });
  }
  ~Prefetcher() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
    }
    cv_.notify_all();
    worker_.join();
  }
  Prefetcher(const Prefetcher&) = delete;
  Prefetcher& operator=(const Prefetcher&) = delete;

  // The next item, or nullopt after the last.
  std::optional<T> next() {
    std::unique_lock<std::mutex> lock(mu_);
    if (taken_ == count_) return std::nullopt;
    cv_.wait(lock, [&] { return !queue_.empty() || error_; });
    if (queue_.empty()) std::rethrow_exception(error_);
    T item = std::move(queue_.front());
    queue_.pop_front();
    ++taken_;
    cv_.notify_all();
    return item;
  }
  size_t size() const { return count_; }

 private:
  void run() {
    for (size_t k = 0; k < count_; ++k) {
      {
        std::unique_lock<std::mutex> lock(mu_);
        cv_.wait(lock, [&] { return stop_ || queue_.size() < depth_; });
        if (stop_) return;
      }
      std::optional<T> item;
      try {
        item.emplace(make_(k));
      } catch (...) {
        std::lock_guard<std::mutex> lock(mu_);
        error_ = std::current_exception();
        cv_.notify_all();
        return;
      }
      std::lock_guard<std::mutex> lock(mu_);
      queue_.push_back(std::move(*item));
      cv_.notify_all();
    }
  }

  const size_t count_, depth_;
  std::function<T(size_t)> make_;
  std::mutex mu_;
  std::condition_variable cv_;
  std::deque<T> queue_;
  size_t taken_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;
  std::thread worker_;  // last: starts after everything above is constructed
};

}  // namespace nns::data
