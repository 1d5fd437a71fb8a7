#pragma once
// Gradient accumulation over K micro-batches (--accumulate K), in one process or over
// the N ranks of an MPI world, with ONE summation order whatever N is:
//
//   g = ((..((g_0 + g_1) + g_2) + ..) + g_{K-1}) / K      element by element, in float
//
// g_m is micro-batch m's gradient alone (its backward runs into zeroed buffers), so a
// step is the mean of the K micro-batch gradients, folded left in micro-batch order.
// For K = 1 that is g_0 itself. Rank r computes the contiguous block of micro-batches
// [K r / N, K (r+1) / N) (K >= N). The left fold is a chain: rank r receives from rank
// r-1 the sum of every micro-batch before its block, adds its own in order, and sends the
// result to rank r+1; rank N-1 divides by K and broadcasts the mean. Every addition is
// the one a single process makes, so the weights are bitwise equal for N = 1, 2, 3, ...
// (MPI_Allreduce(SUM) adds in an order that depends on N and on the library's algorithm).
// Bytes per rank and step: one gradient in, one out, one broadcast: about a ring
// all-reduce's 2 gradients, but N hops of latency instead of 2 (N - 1) / N pipelined
// segments (docs/distributed.md has the cost model).
//
// Buckets: the gradient vector is cut into buckets of about --bucket-mb, in reverse
// parameter order (backward finishes the last layers first). In the rank's last
// micro-batch a bucket's exchange starts as soon as the backward pass has finished every
// gradient in it (Node::grad_final, core/autograd.h), so early buckets travel while the
// rest of the backward pass runs. MPI makes progress only inside MPI calls; each hook
// call is one.
//
// Dropout: micro-batch m draws its masks from the step's generators forked at m, on
// whichever rank computes it; after the step every generator advances by one draw.
// Buffers (BatchNorm's running statistics, set_buffers): every micro-batch starts from
// the step's buffers and each normalises with its own image's statistics; after the step
// the buffers are the mean, in micro-batch order, of what each micro-batch left in them,
// i.e. one momentum update towards the mean of the step's per-image statistics (a
// sequential update would make each rank wait for the previous rank's forward passes).
//
//   GradSync sync(params, rngs, K, bucket_mb);
//   for (int m = sync.mine().begin; m < sync.mine().end; ++m) {
//     sync.begin_micro(m);  ... zero the gradients, forward, backward ...  sync.end_micro(m);
//   }
//   sync.finish_step();     // every parameter's gradient buffer holds the mean g
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/autograd.h"
#include "core/rng.h"
#include "runs/distributed/world.h"

namespace nns::runs {

struct MicroRange {
  int begin = 0, end = 0;
};
// The micro-batches of a step that `rank` of `ranks` computes.
inline MicroRange micro_range(int K, int rank, int ranks) {
  return {int(int64_t(K) * rank / ranks), int(int64_t(K) * (rank + 1) / ranks)};
}

// Where the exchange's time goes, summed over the steps of this process.
struct SyncTimes {
  int64_t steps = 0;
  double overlap_seconds = 0;  // from the first bucket's start to the end of backward
  double wait_seconds = 0;     // after backward, until the mean gradient is in place: not hidden
  double buckets = 0;          // buckets per step
};

class GradSync {
 public:
  GradSync(std::vector<Var<float>> params, std::vector<Rng*> rngs, int accumulate, double bucket_mb)
      : params_(std::move(params)), rngs_(std::move(rngs)), K_(accumulate), r_(rank()), n_(size()) {
    if (K_ < 1) throw std::invalid_argument("--accumulate must be at least 1");
    if (K_ < n_)
      throw std::invalid_argument("--accumulate " + std::to_string(K_) + " is less than the " + std::to_string(n_) +
                                  " MPI ranks: every rank needs at least one micro-batch per step");
    mine_ = micro_range(K_, r_, n_);
    make_buckets(bucket_mb);
    sum_.assign(size_t(total_), 0.f);
    final_.assign(size_t(total_), 0.f);
    if (const char* k = std::getenv("NNSHADE_TEST_KILL_RANK_AT_STEP")) {  // the dead-rank test
      if (std::sscanf(k, "%d:%lld", &kill_rank_, &kill_step_) != 2) kill_rank_ = -1;
    }
  }
  ~GradSync() { arm(false); }
  GradSync(const GradSync&) = delete;
  GradSync& operator=(const GradSync&) = delete;

  // False for K = 1 in one process: the trainer keeps its plain step.
  bool active() const { return K_ > 1 || n_ > 1; }
  int accumulate() const { return K_; }
  MicroRange mine() const { return mine_; }
  const SyncTimes& times() const { return times_; }
  size_t bucket_count() const { return buckets_.size(); }

  // Buffers that forward passes update (running statistics), averaged per step.
  void set_buffers(std::vector<Tensor<float>*> buffers) { buffers_ = std::move(buffers); }

  void begin_micro(int m) {
    if (m == mine_.begin) start_step();
    for (size_t i = 0; i < buffers_.size(); ++i)
      std::memcpy(buffers_[i]->data(), buffer_start_[i].data(), sizeof(float) * buffer_start_[i].size());
    for (size_t i = 0; i < rngs_.size(); ++i) rngs_[i]->set_state(snapshot_[i].fork(uint64_t(m)).state());
    if (m == mine_.end - 1) arm(true);
  }

  void end_micro(int m) {
    std::vector<double> left;
    for (Tensor<float>* b : buffers_) left.insert(left.end(), b->data(), b->data() + b->numel());
    buffers_left_.push_back(std::move(left));
    if (m < mine_.end - 1) {
      hold();
      return;
    }
    arm(false);
    for (auto& b : buckets_) b.ready = true;  // backward is over: every gradient is final
    backward_end_ = now();
    progress();
  }

  // Waits for the exchange and writes the mean gradient into every parameter's buffer.
  void finish_step() {
    const double t0 = now();
    for (size_t b = 0; b < buckets_.size(); ++b)
      if (!buckets_[b].combined) {
#ifdef NNSHADE_MPI
        if (r_ > 0) MPI_Wait(&recv_[b], MPI_STATUS_IGNORE);
#endif
        combine(b);
        post_broadcasts();
      }
#ifdef NNSHADE_MPI
    if (n_ > 1) {
      MPI_Waitall(int(send_.size()), send_.data(), MPI_STATUSES_IGNORE);
      MPI_Waitall(int(bcast_.size()), bcast_.data(), MPI_STATUSES_IGNORE);
    }
#endif
    for (size_t i = 0; i < params_.size(); ++i) {
      Tensor<float>& g = params_[i].grad_buffer();
      std::memcpy(g.data(), final_.data() + offset_[i], sizeof(float) * size_t(g.numel()));
    }
    for (size_t i = 0; i < rngs_.size(); ++i) {
      *rngs_[i] = snapshot_[i];
      rngs_[i]->next_u64();
    }
    if (!buffers_.empty()) {
      const std::vector<double> mean = mean_over_micro(buffers_left_);
      size_t k = 0;
      for (Tensor<float>* b : buffers_)
        for (int64_t e = 0; e < b->numel(); ++e) (*b)[e] = float(mean[k++]);
    }
    const double t1 = now();
    ++times_.steps;
    times_.wait_seconds += t1 - t0;
    times_.overlap_seconds += first_start_ > 0 ? std::max(0.0, backward_end_ - first_start_) : 0;
    times_.buckets = double(buckets_.size());
  }

  // The mean over the step's K micro-batches of per-micro-batch figures (losses), summed
  // in micro-batch order like the gradients: every rank gets the same numbers for any N.
  // `per_micro` holds this rank's micro-batches, in order, each with the same count.
  std::vector<double> mean_over_micro(const std::vector<std::vector<double>>& per_micro) const {
    const size_t M = per_micro.empty() ? 0 : per_micro[0].size();
    std::vector<double> mine;
    for (auto& v : per_micro) {
      if (v.size() != M) throw std::logic_error("mean_over_micro: figures of unequal count");
      mine.insert(mine.end(), v.begin(), v.end());
    }
    std::vector<double> all = mine;
#ifdef NNSHADE_MPI
    if (n_ > 1) {
      std::vector<int> counts(static_cast<size_t>(n_)), displs(static_cast<size_t>(n_));
      for (int q = 0; q < n_; ++q) {
        const MicroRange mr = micro_range(K_, q, n_);
        counts[size_t(q)] = int(size_t(mr.end - mr.begin) * M);
        displs[size_t(q)] = int(size_t(mr.begin) * M);
      }
      all.assign(size_t(K_) * M, 0.0);
      MPI_Allgatherv(mine.data(), int(mine.size()), MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE,
                     MPI_COMM_WORLD);
    }
#endif
    std::vector<double> mean(all.begin(), all.begin() + std::ptrdiff_t(M));
    for (int m = 1; m < K_; ++m)
      for (size_t j = 0; j < M; ++j) mean[j] += all[size_t(m) * M + j];
    for (auto& x : mean) x /= K_;
    return mean;
  }

 private:
  struct Bucket {
    int64_t offset = 0, length = 0;
    std::vector<size_t> params;
    size_t pending = 0;  // gradients of the bucket not yet final in this backward
    bool ready = false, combined = false;
  };

  static double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  }

  // Buckets of about bucket_mb MiB (<= 0: one bucket), last parameters first; at most
  // 32000 of them (a bucket's index is its message tag; MPI guarantees tags to 32767).
  void make_buckets(double bucket_mb) {
    int64_t total = 0;
    for (auto& p : params_) total += p.numel();
    double cap = bucket_mb > 0 ? bucket_mb * 1048576.0 / sizeof(float) : double(total) + 1;
    cap = std::max(cap, double(total) / 32000.0);
    offset_.assign(params_.size(), 0);
    bucket_of_.assign(params_.size(), 0);
    int64_t off = 0;
    for (size_t k = params_.size(); k-- > 0;) {
      if (buckets_.empty() || double(buckets_.back().length) >= cap) buckets_.push_back({off, 0, {}, 0, false, false});
      Bucket& b = buckets_.back();
      offset_[k] = off;
      bucket_of_[k] = buckets_.size() - 1;
      b.params.push_back(k);
      b.length += params_[k].numel();
      off += params_[k].numel();
    }
    total_ = off;
  }

  void start_step() {
    if (kill_rank_ == r_ && times_.steps == kill_step_) {
      std::fprintf(stderr, "rank %d: NNSHADE_TEST_KILL_RANK_AT_STEP: killing myself at step %lld\n", r_, kill_step_);
      raise(SIGKILL);
    }
    snapshot_.clear();
    for (Rng* g : rngs_) snapshot_.push_back(*g);
    buffer_start_.clear();
    for (Tensor<float>* b : buffers_) buffer_start_.emplace_back(b->data(), b->data() + b->numel());
    buffers_left_.clear();
    held_.clear();
    for (auto& b : buckets_) b.pending = b.params.size(), b.ready = b.combined = false;
    first_start_ = 0;
    next_broadcast_ = 0;
#ifdef NNSHADE_MPI
    if (n_ > 1) {
      recv_.assign(buckets_.size(), MPI_REQUEST_NULL);
      send_.assign(buckets_.size(), MPI_REQUEST_NULL);
      bcast_.assign(buckets_.size(), MPI_REQUEST_NULL);
      for (size_t b = 0; b < buckets_.size(); ++b) {
        if (r_ > 0)
          MPI_Irecv(sum_.data() + buckets_[b].offset, int(buckets_[b].length), MPI_FLOAT, r_ - 1, int(b),
                    MPI_COMM_WORLD, &recv_[b]);
        // Collectives match in call order: every rank posts the broadcasts in bucket
        // order; the root (rank N-1) posts each once its sum is complete.
        if (r_ != n_ - 1)
          MPI_Ibcast(final_.data() + buckets_[b].offset, int(buckets_[b].length), MPI_FLOAT, n_ - 1, MPI_COMM_WORLD,
                     &bcast_[b]);
      }
    }
#endif
  }

  // The hooks that start a bucket as soon as its gradients are final (the rank's last
  // micro-batch only: earlier ones are held until then).
  void arm(bool on) {
    for (size_t i = 0; i < params_.size(); ++i)
      params_[i].node()->grad_final = on ? std::function<void()>([this, i] { gradient_final(i); }) : nullptr;
  }
  void gradient_final(size_t i) {
    Bucket& b = buckets_[size_t(bucket_of_[i])];
    if (b.pending > 0 && --b.pending == 0) {
      b.ready = true;
      progress();
    }
  }

  // Packs parameter gradients (zeros where a parameter got none) into flat[bucket layout].
  void pack(const Bucket& b, float* flat) const {
    for (size_t k : b.params) {
      const Tensor<float>& g = params_[k].grad();
      float* d = flat + offset_[k];
      if (g.defined()) std::memcpy(d, g.data(), sizeof(float) * size_t(g.numel()));
      else std::fill(d, d + params_[k].numel(), 0.f);
    }
  }
  void add(const Bucket& b, float* acc) const {
    for (size_t k : b.params) {
      const Tensor<float>& g = params_[k].grad();
      float* d = acc + offset_[k];
      if (g.defined())
        for (int64_t e = 0; e < g.numel(); ++e) d[e] += g[e];
      else
        for (int64_t e = 0; e < params_[k].numel(); ++e) d[e] += 0.f;  // as a zero gradient adds
    }
  }

  // A micro-batch before this rank's last: rank 0 starts the fold itself; a later rank
  // keeps each one, since its additions must wait for the prefix from rank r-1.
  void hold() {
    if (r_ == 0 && !held_.empty()) {
      for (auto& b : buckets_) add(b, held_[0].data());
      return;
    }
    held_.emplace_back(size_t(total_));
    for (auto& b : buckets_) pack(b, held_.back().data());
  }

  // The bucket's sum over the micro-batches up to this rank's last; passed on, or (rank
  // N-1) divided by K into the mean.
  void combine(size_t bi) {
    Bucket& b = buckets_[bi];
    float* s = sum_.data() + b.offset;
    const size_t len = size_t(b.length);
    size_t h = 0;
    if (r_ == 0) {
      if (held_.empty()) {
        pack(b, sum_.data());
      } else {
        std::memcpy(s, held_[0].data() + b.offset, sizeof(float) * len);
        h = 1;
        add(b, sum_.data());
      }
    } else {  // s holds the prefix received from rank r-1
      for (; h < held_.size(); ++h)
        for (size_t e = 0; e < len; ++e) s[e] += held_[h][size_t(b.offset) + e];
      add(b, sum_.data());
    }
    b.combined = true;
    if (first_start_ == 0) first_start_ = now();
    if (r_ == n_ - 1) {
      const float k = float(K_);
      float* f = final_.data() + b.offset;
      for (size_t e = 0; e < len; ++e) f[e] = s[e] / k;
    }
#ifdef NNSHADE_MPI
    if (r_ < n_ - 1) MPI_Isend(s, int(len), MPI_FLOAT, r_ + 1, int(bi), MPI_COMM_WORLD, &send_[bi]);
#endif
  }

  void post_broadcasts() {
#ifdef NNSHADE_MPI
    if (n_ > 1 && r_ == n_ - 1)
      while (next_broadcast_ < buckets_.size() && buckets_[next_broadcast_].combined) {
        const Bucket& b = buckets_[next_broadcast_];
        MPI_Ibcast(final_.data() + b.offset, int(b.length), MPI_FLOAT, n_ - 1, MPI_COMM_WORLD,
                   &bcast_[next_broadcast_]);
        ++next_broadcast_;
      }
#endif
  }

  // Combines every ready bucket whose prefix has arrived; lets MPI move the rest.
  void progress() {
    for (size_t b = 0; b < buckets_.size(); ++b) {
      if (!buckets_[b].ready || buckets_[b].combined) continue;
#ifdef NNSHADE_MPI
      if (r_ > 0) {
        int done = 0;
        MPI_Test(&recv_[b], &done, MPI_STATUS_IGNORE);
        if (!done) continue;
      }
#endif
      combine(b);
    }
    post_broadcasts();
#ifdef NNSHADE_MPI
    if (n_ > 1) {
      int done = 0;
      MPI_Testall(int(send_.size()), send_.data(), &done, MPI_STATUSES_IGNORE);
      MPI_Testall(int(bcast_.size()), bcast_.data(), &done, MPI_STATUSES_IGNORE);
    }
#endif
  }

  std::vector<Var<float>> params_;
  std::vector<Rng*> rngs_;
  std::vector<Rng> snapshot_;
  std::vector<Tensor<float>*> buffers_;
  std::vector<std::vector<float>> buffer_start_;
  std::vector<std::vector<double>> buffers_left_;  // per micro-batch of this rank
  int K_, r_, n_;
  MicroRange mine_;
  std::vector<Bucket> buckets_;
  std::vector<int64_t> offset_;    // parameter -> its place in the flat layout
  std::vector<size_t> bucket_of_;  // parameter -> its bucket
  int64_t total_ = 0;
  std::vector<float> sum_, final_;        // the running sum (sent on), the mean
  std::vector<std::vector<float>> held_;  // this rank's micro-batches before its last
  size_t next_broadcast_ = 0;
  double first_start_ = 0, backward_end_ = 0;
  SyncTimes times_;
  int kill_rank_ = -1;
  long long kill_step_ = -1;
#ifdef NNSHADE_MPI
  std::vector<MPI_Request> recv_, send_, bcast_;
#endif
};

// The exchange's figures for summary.json (nothing when the run did not accumulate).
inline void add_sync_figures(const GradSync& sync, std::vector<std::pair<std::string, double>>& figures) {
  if (!sync.active()) return;
  const SyncTimes& t = sync.times();
  const double per_step = t.steps ? 1e6 / double(t.steps) : 0;
  figures.emplace_back("ranks", double(size()));
  figures.emplace_back("accumulate", double(sync.accumulate()));
  figures.emplace_back("buckets", double(sync.bucket_count()));
  figures.emplace_back("exchange_wait_us_per_step", t.wait_seconds * per_step);
  figures.emplace_back("exchange_overlap_us_per_step", t.overlap_seconds * per_step);
}

}  // namespace nns::runs
