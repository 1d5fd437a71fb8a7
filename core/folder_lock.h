#pragma once
// One folder, one run: every command that writes a folder holds an advisory lock on a
// file inside it (flock on "<dir>/.nnshade-lock") for as long as it runs. Two train-nnao
// runs with one --out interleaved their lines in one metrics.jsonl and both exited 0;
// the second is now refused, naming the folder and the process that holds it. The kernel
// drops the lock when the holder dies, so a kill -9 never leaves a stale lock; the file
// itself stays (removing it would let two runs lock two different files of one name).
//
//   FolderLock lock = prepare_output_folder(out, "eval-ao");  // create, lock, clean
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/atomic_file.h"

namespace nns {

class FolderLock {
 public:
  static constexpr const char* kFileName = ".nnshade-lock";

  FolderLock() = default;
  // Locks `dir` (which must exist) for `app`; throws if another process holds it.
  FolderLock(const std::string& dir, const std::string& app) {
    const std::string path = (std::filesystem::path(dir) / kFileName).string();
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd_ < 0)
      throw std::runtime_error(app + ": cannot lock the output folder '" + dir + "': " + std::strerror(errno));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      char buf[32] = {};
      const ssize_t n = ::pread(fd_, buf, sizeof buf - 1, 0);
      std::string holder = n > 0 ? std::string(buf, size_t(n)) : std::string("unknown");
      while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) holder.pop_back();
      ::close(fd_);
      fd_ = -1;
      if (err == EWOULDBLOCK)
        throw std::runtime_error(app + ": the output folder '" + dir + "' is in use by another run (pid " + holder +
                                 "); wait for it to finish or choose another folder");
      throw std::runtime_error(app + ": cannot lock the output folder '" + dir + "': " + std::strerror(err));
    }
    const std::string pid = std::to_string(::getpid()) + "\n";
    // The pid is only for the message of a refused run: best effort.
    if (::ftruncate(fd_, 0) == 0 && ::pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
    }
  }
  FolderLock(FolderLock&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
  FolderLock& operator=(FolderLock&& o) noexcept {
    if (this != &o) {
      release();
      fd_ = std::exchange(o.fd_, -1);
    }
    return *this;
  }
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;
  ~FolderLock() { release(); }

  bool held() const { return fd_ >= 0; }

 private:
  void release() {
    if (fd_ >= 0) ::close(fd_);  // closing the last descriptor drops the flock
    fd_ = -1;
  }
  int fd_ = -1;
};

// What every command does with the folder it writes, before it writes: create it, lock
// it, and remove the temporaries a killed writer left anywhere in it (core/atomic_file.h's
// names; the lock makes every one of them another run's).
inline FolderLock prepare_output_folder(const std::string& dir, const std::string& app) {
  std::filesystem::create_directories(dir);
  FolderLock lock(dir, app);
  remove_stale_temporaries(dir, /*recursive=*/true);
  return lock;
}

}  // namespace nns
