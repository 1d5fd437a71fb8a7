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
#include <exception>
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
  FolderLock(FolderLock&& o) noexcept
      : fd_(std::exchange(o.fd_, -1)), made_dir_(std::move(o.made_dir_)), exceptions_(o.exceptions_) {}
  FolderLock& operator=(FolderLock&& o) noexcept {
    if (this != &o) {
      release();
      fd_ = std::exchange(o.fd_, -1);
      made_dir_ = std::move(o.made_dir_);
      exceptions_ = o.exceptions_;
    }
    return *this;
  }
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;
  ~FolderLock() { release(); }

  bool held() const { return fd_ >= 0; }

  // `dir` was made for this run: if the run fails (the lock is released while an
  // exception unwinds) before it wrote a file, the folder goes too, so that an error
  // found after the folder was made (a model that is no blob, no views to evaluate)
  // leaves nothing behind. A file the run wrote keeps the folder: a failed training's
  // metrics and checkpoints are what the user reads next.
  void remove_if_failed_empty(const std::string& dir) { made_dir_ = dir; }

 private:
  void release() {
    if (fd_ >= 0 && !made_dir_.empty() && std::uncaught_exceptions() > exceptions_) remove_made_dir_if_empty();
    if (fd_ >= 0) ::close(fd_);  // closing the last descriptor drops the flock
    fd_ = -1;
  }
  // Nothing but the lock file and empty folders in it. Never throws (it runs while an
  // exception unwinds); the lock is still held, so no other run writes into it meanwhile.
  void remove_made_dir_if_empty() noexcept {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path dir = made_dir_, lock = dir / kFileName;
    for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec)) {
      std::error_code type_ec;
      if (!it->is_directory(type_ec) && it->path() != lock) return;
    }
    if (!ec) fs::remove_all(dir, ec);
  }
  int fd_ = -1;
  std::string made_dir_;                         // empty: a folder that was there
  int exceptions_ = std::uncaught_exceptions();  // unwinding at construction
};

// What every command does with the folder it writes, before it writes: create it, lock
// it, and remove the temporaries a killed writer left anywhere in it (core/atomic_file.h's
// names; the lock makes every one of them another run's). A folder it made goes again if
// the run fails before writing a file into it.
inline FolderLock prepare_output_folder(const std::string& dir, const std::string& app) {
  std::error_code ec;
  const bool made = !std::filesystem::exists(dir, ec);
  std::filesystem::create_directories(dir);
  FolderLock lock(dir, app);
  if (made) lock.remove_if_failed_empty(dir);
  remove_stale_temporaries(dir, /*recursive=*/true);
  return lock;
}

}  // namespace nns
