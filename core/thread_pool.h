#pragma once
// One persistent thread pool for the whole process.
//
// Kernels split work statically: worker i of n gets a fixed share (ggml's (ith, nth)).
// Results must never depend on the number of threads, so
//  - element-wise work may be split any way (each output is computed the same way);
//  - reductions use parallel_chunks(): the chunk boundaries are fixed by the caller,
//    not by the thread count, and partial results are combined in chunk order.
// A parallel call made from inside a worker runs inline on that worker: no nesting,
// no oversubscription, no new thread per call.
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <ctime>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <pthread.h>
#include <stdexcept>
#include <thread>
#include <vector>
#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace nns {

class ThreadPool {
 public:
  static ThreadPool& global() {
    static ThreadPool pool(2);
    return pool;
  }

  explicit ThreadPool(int n) { start(n); }
  ~ThreadPool() { stop(); }
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int threads() const { return n_; }

  // CPU time the calling thread and every worker have used so far, in ms, read from each
  // thread's own clock. The process clock (CLOCK_PROCESS_CPUTIME_ID) was no substitute:
  // Linux adds another running thread's time to it only when the scheduler accounts it,
  // and eval-ao timed through it reported one thread busy for methods that ran twice as
  // fast on 2 threads (GTAO-4 at 320x180: 1.43 ms on 1 thread, 0.69 ms on 2). Call it
  // from outside the workers.
  double cpu_ms() {
    double ms = thread_cpu_ms(CLOCK_THREAD_CPUTIME_ID);
    for (auto& t : workers_) {
      clockid_t clock;
      if (pthread_getcpuclockid(t.native_handle(), &clock) == 0) ms += thread_cpu_ms(clock);
    }
    return ms;
  }

  void set_threads(int n) {
    if (n < 1) throw std::invalid_argument("threads must be >= 1, got " + std::to_string(n));
    if (n == n_) return;
    stop();
    start(n);
  }

  // Calls fn(worker, nworkers) once on every worker; the caller is worker 0.
  void run(const std::function<void(int, int)>& fn) {
    if (n_ == 1 || in_worker()) {
      fn(0, 1);
      return;
    }
    std::lock_guard<std::mutex> one_job_at_a_time(run_mu_);
    job_ = &fn;
    error_ = nullptr;
    remaining_.store(n_ - 1, std::memory_order_relaxed);
    {
      std::lock_guard<std::mutex> lock(mu_);
      generation_.fetch_add(1, std::memory_order_release);
    }
    cv_.notify_all();
    std::exception_ptr mine;
    in_worker() = true;
    try {
      fn(0, n_);
    } catch (...) {
      mine = std::current_exception();
    }
    in_worker() = false;
    // Spin: most kernels finish their shares within microseconds of each other. The
    // workers must be done with `fn` before it goes out of scope, even on error.
    // When the cores are oversubscribed a spinning caller would steal the time slice
    // the late worker needs, so after a short spin it yields instead.
    for (int spin = 0; remaining_.load(std::memory_order_acquire) != 0; ++spin) {
      if (spin < 4000) pause();
      else std::this_thread::yield();
    }
    job_ = nullptr;
    if (mine) std::rethrow_exception(mine);
    if (error_) std::rethrow_exception(error_);
  }

 private:
  static bool& in_worker() {
    thread_local bool flag = false;
    return flag;
  }
  static double thread_cpu_ms(clockid_t clock) {
    timespec t{};
    clock_gettime(clock, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
  }
  static void pause() {
#if defined(__x86_64__)
    _mm_pause();
#else
    std::this_thread::yield();
#endif
  }

  void start(int n) {
    n_ = n;
    quit_ = false;
    // The generation is read here, not in the new thread: a job posted before the
    // thread gets going must still count as new to it.
    const uint64_t seen = generation_.load(std::memory_order_acquire);
    for (int i = 1; i < n; ++i) workers_.emplace_back([this, i, seen] { worker_loop(i, seen); });
  }
  void stop() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      quit_ = true;
      generation_.fetch_add(1, std::memory_order_release);
    }
    cv_.notify_all();
    for (auto& t : workers_) t.join();
    workers_.clear();
  }

  void worker_loop(int index, uint64_t seen) {
    in_worker() = true;
    for (;;) {
      // Spin for a short while before sleeping, so back-to-back kernels of a training
      // step do not pay a futex wake-up each.
      for (int spin = 0; spin < 20000 && generation_.load(std::memory_order_acquire) == seen; ++spin) pause();
      if (generation_.load(std::memory_order_acquire) == seen) {
        std::unique_lock<std::mutex> lock(mu_);
        cv_.wait(lock, [&] { return generation_.load(std::memory_order_acquire) != seen; });
      }
      seen = generation_.load(std::memory_order_acquire);
      if (quit_) return;
      try {
        (*job_)(index, n_);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mu_);
        if (!error_) error_ = std::current_exception();
      }
      remaining_.fetch_sub(1, std::memory_order_acq_rel);
    }
  }

  int n_ = 1;
  std::vector<std::thread> workers_;
  std::mutex mu_, run_mu_;
  std::condition_variable cv_;
  std::atomic<uint64_t> generation_{0};
  std::atomic<int> remaining_{0};
  const std::function<void(int, int)>* job_ = nullptr;
  std::exception_ptr error_;  // first exception thrown by a worker during run()
  bool quit_ = false;
};

inline void set_num_threads(int n) { ThreadPool::global().set_threads(n); }
inline int num_threads() { return ThreadPool::global().threads(); }
// CPU ms used so far by this thread and the pool's workers (ThreadPool::cpu_ms).
inline double pool_cpu_ms() { return ThreadPool::global().cpu_ms(); }

// Splits [0, n) into one contiguous range per worker, each a multiple of `align`
// (except the last), and calls f(begin, end). Work below `min_work` runs inline.
template <class F>
void parallel_for(int64_t n, F&& f, int64_t min_work = 1, int64_t align = 1) {
  if (n <= 0) return;
  ThreadPool& pool = ThreadPool::global();
  if (pool.threads() == 1 || n < 2 * min_work) {
    f(int64_t(0), n);
    return;
  }
  pool.run([&](int w, int nw) {
    int64_t units = (n + align - 1) / align;
    int64_t b = units * w / nw * align, e = std::min(n, units * (w + 1) / nw * align);
    if (b < e) f(b, e);
  });
}

// Calls f(begin, end) on consecutive pieces of [0, n), `grain` items each, handed to the
// workers as they come free. For loops whose items cost unequal time and are each
// computed the same way whoever takes them (the rows of a screen-space AO pass: a sky
// row costs nothing, a row of geometry the whole march): an even split there leaves one
// worker idle while the other finishes the costly half of the frame.
template <class F>
void parallel_for_dynamic(int64_t n, int64_t grain, F&& f) {
  if (n <= 0) return;
  ThreadPool& pool = ThreadPool::global();
  if (pool.threads() == 1 || n <= grain) {
    f(int64_t(0), n);
    return;
  }
  std::atomic<int64_t> next{0};
  pool.run([&](int, int) {
    for (int64_t b; (b = next.fetch_add(grain, std::memory_order_relaxed)) < n;) f(b, std::min(n, b + grain));
  });
}

// Calls f(chunk, begin, end) for the fixed chunks [k*chunk, (k+1)*chunk) of [0, n),
// distributed over the workers. Chunk boundaries never depend on the thread count,
// which is what keeps reductions bitwise identical for 1 and 2 threads.
template <class F>
void parallel_chunks(int64_t n, int64_t chunk, F&& f) {
  if (n <= 0) return;
  int64_t nchunks = (n + chunk - 1) / chunk;
  parallel_for(nchunks, [&](int64_t cb, int64_t ce) {
    for (int64_t c = cb; c < ce; ++c) f(c, c * chunk, std::min(n, (c + 1) * chunk));
  });
}

}  // namespace nns
