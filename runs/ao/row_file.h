#pragma once
// Training points on disk instead of in memory, read back in a shuffled order through a
// bounded buffer, so a trainer's memory does not grow with its data (ten
// times the default NNAO data would need ~13 GB as one in-memory matrix).
//
// RowFile: fixed-size rows in a file with no name. It is created in the output folder as
// "<name>.tmp.<pid>" and unlinked at once, so the kernel frees its blocks when the
// process ends however it ends (SIGKILL included); if it is killed in the microseconds
// before the unlink, the run layer's remove_stale_temporaries deletes the name on the
// next start. Reads and writes are pread/pwrite into the caller's memory: the page cache
// may hold the file, but that is reclaimable cache, not the process's resident set.
//
// ShuffledRows: one epoch's order. The file is cut into chunks of `chunk_rows`
// consecutive rows; the chunk order is shuffled with the data Rng, then cut into the
// fewest groups of at most buffer_rows / chunk_rows chunks, all of the same size but
// for one chunk (so an epoch never ends on a small remainder group whose few chunks
// would be the last thing the model sees); each group is loaded and its rows shuffled
// again. Memory: two buffers (the group being trained on and the next one, read by a
// background thread while the steps run), whatever the row count.
// This is not the global shuffle: a group of consecutive batches draws only from its
// group's chunks. When one group holds every chunk (one buffer, no prefetch) the chunk
// order is left alone (it cannot change the result) and the row shuffle over the whole
// file is exactly the former global shuffle, draw for draw. docs/nnao.md ("Memory")
// measures the difference.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <future>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/rng.h"

namespace nns::runs {

class RowFile {
 public:
  RowFile() = default;
  // An empty file of rows of `row_bytes` in `dir`, already unlinked.
  RowFile(const std::string& dir, const std::string& name, int64_t row_bytes) : row_bytes_(row_bytes) {
    if (row_bytes < 1) throw std::invalid_argument("RowFile: row size must be positive");
    path_ = dir + "/" + name + ".tmp." + std::to_string(::getpid());
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd_ < 0) throw error("create");
    ::unlink(path_.c_str());
  }
  RowFile(RowFile&& o) noexcept { *this = std::move(o); }
  RowFile& operator=(RowFile&& o) noexcept {
    std::swap(fd_, o.fd_);
    std::swap(rows_, o.rows_);
    std::swap(row_bytes_, o.row_bytes_);
    std::swap(path_, o.path_);
    return *this;
  }
  RowFile(const RowFile&) = delete;
  RowFile& operator=(const RowFile&) = delete;
  ~RowFile() {
    if (fd_ >= 0) ::close(fd_);
  }

  int64_t rows() const { return rows_; }
  int64_t row_bytes() const { return row_bytes_; }

  void append(const void* src, int64_t n) {
    write_rows(rows_, n, src);
    rows_ += n;
  }
  void write_rows(int64_t first, int64_t n, const void* src) {
    const char* p = static_cast<const char*>(src);
    int64_t off = first * row_bytes_, left = n * row_bytes_;
    while (left > 0) {
      const ssize_t w = ::pwrite(fd_, p, size_t(left), off);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) throw error("write");  // ENOSPC: the output folder's disk is full
      p += w, off += w, left -= w;
    }
  }
  void read_rows(int64_t first, int64_t n, void* dst) const {
    if (first < 0 || n < 0 || first + n > rows_) throw std::out_of_range("RowFile: read past the last row");
    char* p = static_cast<char*>(dst);
    int64_t off = first * row_bytes_, left = n * row_bytes_;
    while (left > 0) {
      const ssize_t r = ::pread(fd_, p, size_t(left), off);
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) throw error("read");
      p += r, off += r, left -= r;
    }
  }

 private:
  std::runtime_error error(const char* what) const {
    return std::runtime_error("point file '" + path_ + "' (unlinked): cannot " + what + ": " +
                              std::strerror(errno ? errno : EIO));
  }
  int fd_ = -1;
  int64_t rows_ = 0, row_bytes_ = 0;
  std::string path_;
};

class ShuffledRows {
 public:
  // buffer_rows: rows per loaded group (rounded down to whole chunks, at least one).
  ShuffledRows(const RowFile& f, int64_t chunk_rows, int64_t buffer_rows) : f_(f) {
    if (chunk_rows < 1) throw std::invalid_argument("ShuffledRows: chunk must hold at least one row");
    chunk_ = chunk_rows;
    nchunks_ = (f.rows() + chunk_ - 1) / chunk_;
    const int64_t most = std::max<int64_t>(1, std::min(buffer_rows / chunk_, nchunks_));
    ngroups_ = (nchunks_ + most - 1) / most;
    // The second buffer is needed only to train on one group while the next is read. One
    // group (the global shuffle) is read into the one buffer at each epoch's start, so it
    // holds the data once, as the former matrix did.
    buf_[0].resize(size_t(rows_per_group() * f.row_bytes()));
    if (ngroups_ > 1) buf_[1].resize(buf_[0].size());
  }
  ~ShuffledRows() { wait(); }

  int64_t groups() const { return ngroups_; }
  // Chunks [group_begin(g), group_begin(g + 1)) of the epoch's order form group g.
  int64_t group_begin(int64_t g) const { return ngroups_ ? g * nchunks_ / ngroups_ : 0; }
  // The buffer size: the largest group's rows.
  int64_t rows_per_group() const {
    return ngroups_ ? std::min((nchunks_ + ngroups_ - 1) / ngroups_ * chunk_, f_.rows()) : 0;
  }

  // Draws the epoch's chunk order from `rng` and starts reading the first group.
  void start_epoch(Rng& rng) {
    wait();
    order_.resize(size_t(nchunks_));
    for (int64_t i = 0; i < nchunks_; ++i) order_[size_t(i)] = i;
    if (ngroups_ > 1)
      for (int64_t i = nchunks_ - 1; i > 0; --i)
        std::swap(order_[size_t(i)], order_[size_t(rng.below(uint64_t(i + 1)))]);
    next_group_ = 0;
    pos_ = loaded_ = 0;
    prefetch();
  }

  // The next row of the epoch (pointer into the current buffer, valid until the next
  // call). Row shuffles draw from `rng` on the caller's thread, group by group, so the
  // draws are the same whatever the timing of the background reads.
  const char* next(Rng& rng) {
    if (pos_ == loaded_) {
      if (!pending_.valid()) throw std::logic_error("ShuffledRows: past the end of the epoch");
      loaded_ = pending_.get();
      if (ngroups_ > 1) cur_ = 1 - cur_;
      prefetch();
      perm_.resize(size_t(loaded_));
      for (int64_t i = 0; i < loaded_; ++i) perm_[size_t(i)] = i;
      for (int64_t i = loaded_ - 1; i > 0; --i) std::swap(perm_[size_t(i)], perm_[size_t(rng.below(uint64_t(i + 1)))]);
      pos_ = 0;
    }
    return buf_[cur_].data() + perm_[size_t(pos_++)] * f_.row_bytes();
  }

 private:
  // Reads the next group on another thread, into the buffer not being trained on (the
  // one buffer when there is one group: its rows were all used by then). Plain preads:
  // it never touches the thread pool, whose workers may run the caller's parallel loops.
  void prefetch() {
    const int64_t g = next_group_;
    if (g >= ngroups_) return;
    ++next_group_;
    char* dst = buf_[ngroups_ > 1 ? 1 - cur_ : cur_].data();
    pending_ = std::async(std::launch::async, [this, g, dst] {
      int64_t n = 0;
      for (int64_t k = group_begin(g); k < group_begin(g + 1); ++k) {
        const int64_t first = order_[size_t(k)] * chunk_, cnt = std::min(chunk_, f_.rows() - first);
        f_.read_rows(first, cnt, dst + n * f_.row_bytes());
        n += cnt;
      }
      return n;
    });
  }
  void wait() {
    if (pending_.valid()) {
      try {
        pending_.get();
      } catch (...) {
      }
    }
  }

  const RowFile& f_;
  int64_t chunk_ = 1, nchunks_ = 0, ngroups_ = 0, next_group_ = 0;
  std::vector<int64_t> order_, perm_;
  std::vector<char> buf_[2];
  int64_t pos_ = 0, loaded_ = 0;
  int cur_ = 0;  // the buffer being trained on
  std::future<int64_t> pending_;
};

}  // namespace nns::runs
