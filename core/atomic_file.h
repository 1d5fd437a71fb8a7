#pragma once
// The one atomic writer: every file the project writes (blobs, checkpoints, CSVs,
// reports, charts, summaries) goes to a temporary file in the same folder
// ("<name>.tmp.<pid>"), is fsynced, renamed over the target, and the folder fsynced. A
// crash leaves either the old file or the new one, never a torn mix; the temporaries a
// killed process leaves behind are removed by remove_stale_temporaries on the next start.
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace nns {

namespace detail {

inline std::runtime_error io_error(const std::string& path, const std::string& what) {
  return std::runtime_error("cannot write '" + path + "': " + what + ": " + std::strerror(errno));
}

// The pid keeps two processes writing the same target from sharing a temporary.
inline std::string temp_name(const std::string& path) { return path + ".tmp." + std::to_string(::getpid()); }

// Renames a finished, fsynced temporary over `path`, then fsyncs the folder.
inline void rename_into_place(const std::string& tmp, const std::string& path) {
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    auto e = io_error(path, "rename " + tmp);
    ::unlink(tmp.c_str());
    throw e;
  }
  // Make the rename itself durable; best effort (some filesystems refuse a dir fsync).
  auto slash = path.find_last_of('/');
  std::string dir = slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
  int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

}  // namespace detail

inline void write_file_atomic(const std::string& path, const std::string& bytes) {
  auto fail = [&](const std::string& what) { return detail::io_error(path, what); };
  const std::string tmp = detail::temp_name(path);
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw fail("open " + tmp);
  size_t done = 0;
  while (done < bytes.size()) {
    ssize_t w = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      auto e = fail("write " + tmp);
      ::close(fd);
      ::unlink(tmp.c_str());
      throw e;
    }
    done += size_t(w);
  }
  if (::fsync(fd) != 0) {
    auto e = fail("fsync " + tmp);
    ::close(fd);
    ::unlink(tmp.c_str());
    throw e;
  }
  if (::close(fd) != 0) {
    auto e = fail("close " + tmp);
    ::unlink(tmp.c_str());
    throw e;
  }
  detail::rename_into_place(tmp, path);
}

// For a library that writes to a file name itself (OpenImageIO): `write(tmp)` writes
// the whole file at the temporary name, which is then fsynced and renamed like
// write_file_atomic's. If `write` throws, the temporary is removed and the error passes
// on unchanged; the target is never touched.
template <class WriteToPath>
void write_path_atomic(const std::string& path, WriteToPath&& write) {
  const std::string tmp = detail::temp_name(path);
  try {
    write(tmp);
  } catch (...) {
    ::unlink(tmp.c_str());
    throw;
  }
  int fd = ::open(tmp.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0 || ::fsync(fd) != 0) {
    auto e = detail::io_error(path, "fsync " + tmp);
    if (fd >= 0) ::close(fd);
    ::unlink(tmp.c_str());
    throw e;
  }
  ::close(fd);
  detail::rename_into_place(tmp, path);
}

// Files that belong together (an image and its previews): each written by
// `write(i, tmp)` at its temporary name and fsynced, then all renamed. A failed write
// renames nothing and removes every temporary; a rename that fails half-way removes
// the files already renamed (they are not a complete set) and the rest. Either the
// whole new set is in place or none of it is.
template <class WriteToPath>
void write_paths_atomic(const std::vector<std::string>& paths, WriteToPath&& write) {
  std::vector<std::string> temps;
  for (const auto& p : paths) temps.push_back(detail::temp_name(p));
  size_t renamed = 0;
  try {
    for (size_t i = 0; i < paths.size(); ++i) {
      write(i, temps[i]);
      int fd = ::open(temps[i].c_str(), O_RDONLY | O_CLOEXEC);
      const bool synced = fd >= 0 && ::fsync(fd) == 0;
      if (fd >= 0) ::close(fd);
      if (!synced) throw detail::io_error(paths[i], "fsync " + temps[i]);
    }
    for (; renamed < paths.size(); ++renamed) detail::rename_into_place(temps[renamed], paths[renamed]);
  } catch (...) {
    for (size_t i = 0; i < paths.size(); ++i) ::unlink((i < renamed ? paths[i] : temps[i]).c_str());
    throw;
  }
}

// The pid of a temporary's name "<name>.tmp.<pid>", or -1 for any other name.
inline int temporary_pid(const std::string& name) {
  const auto at = name.rfind(".tmp.");
  if (at == std::string::npos) return -1;
  const std::string pid = name.substr(at + 5);
  if (pid.empty() || pid.size() > 9 || pid.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stoi(pid);
}

// The file a temporary stands for ("x.png.tmp.12" -> "x.png"); other names unchanged.
// A writer that picks the format by the extension (OpenImageIO) looks at this name.
inline std::string target_of_temporary(const std::string& name) {
  return temporary_pid(name) < 0 ? name : name.substr(0, name.rfind(".tmp."));
}

// Removes "<name>.tmp.<pid>" files in `dir` (and with `recursive` in its sub-folders:
// previews/, a dataset's splits) whose writer is no longer running (a run killed
// mid-write), and folders of that name (core/staged_output.h's stage) with what they
// hold; returns how many. Another live process's temporaries are kept.
inline int remove_stale_temporaries(const std::string& dir, bool recursive = false) {
  namespace fs = std::filesystem;
  int removed = 0;
  std::error_code ec;
  std::vector<fs::path> stale;
  auto consider = [&](const fs::directory_entry& e) {
    std::error_code type_ec;
    const int p = temporary_pid(e.path().filename().string());
    if (p < 0 || e.is_symlink(type_ec) || !(e.is_regular_file(type_ec) || e.is_directory(type_ec))) return;
    if (p == ::getpid() || (::kill(p, 0) == 0 || errno == EPERM)) return;  // a live writer
    stale.push_back(e.path());
  };
  if (recursive) {
    for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec))
      consider(*it);
  } else {
    for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator(); it.increment(ec))
      consider(*it);
  }
  for (auto& p : stale)
    if (std::error_code rm_ec; fs::remove_all(p, rm_ec) > 0) ++removed;
  return removed;
}

// Removes the temporaries of one target ("<path>.tmp.<pid>" of writers no longer
// running): what a command that writes single files (nnao-infer --out x.exr) does, where
// the folder is the user's and other files in it are none of ours.
inline int remove_stale_temporaries_of(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string prefix = target.filename().string() + ".tmp.";
  int removed = 0;
  std::error_code ec;
  std::vector<fs::path> stale;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const int p = temporary_pid(name);
    std::error_code type_ec;
    if (p < 0 || name.rfind(prefix, 0) != 0 || name.size() != prefix.size() + std::to_string(p).size() ||
        !it->is_regular_file(type_ec))
      continue;
    if (p == ::getpid() || (::kill(p, 0) == 0 || errno == EPERM)) continue;  // a live writer
    stale.push_back(it->path());
  }
  for (auto& p : stale)
    if (std::error_code rm_ec; fs::remove(p, rm_ec)) ++removed;
  return removed;
}

// The most read_file takes unless told otherwise: above every blob and checkpoint the
// project writes (the 256x256 GAN's checkpoint is under 1 GiB), far below what would
// exhaust a machine's memory.
inline constexpr uint64_t kMaxReadBytes = uint64_t(4) << 30;

// "4 GiB", "1 MiB", "1000 bytes": a limit as a person reads it.
inline std::string byte_count_text(uint64_t n) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  int u = 0;
  while (u < 4 && n >= 1024 && n % 1024 == 0) n /= 1024, ++u;
  return std::to_string(n) + " " + units[u];
}

// The one way the project reads a file's bytes: only a regular file (a FIFO blocks a
// reader forever, /dev/zero never ends, a folder has no bytes) and at most `max_bytes`,
// both checked on the opened descriptor so nothing can be swapped in between. Errors
// name the file, the problem and the limit.
inline std::string read_file(const std::string& path, uint64_t max_bytes = kMaxReadBytes) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer.
  int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("cannot open '" + path + "': " + std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw std::runtime_error("cannot read '" + path + "': " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw std::runtime_error("cannot read '" + path + "': it is a folder, not a file");
  if (!S_ISREG(st.st_mode)) {
    const char* kind = S_ISFIFO(st.st_mode)   ? "a FIFO"
                       : S_ISCHR(st.st_mode)  ? "a character device"
                       : S_ISBLK(st.st_mode)  ? "a block device"
                       : S_ISSOCK(st.st_mode) ? "a socket"
                                              : "not a file";
    throw std::runtime_error("cannot read '" + path + "': it is " + std::string(kind) +
                             ", not a regular file (only regular files of at most " + byte_count_text(max_bytes) +
                             " are read)");
  }
  const auto too_large = [&](uint64_t n) {
    return std::runtime_error("cannot read '" + path + "': " + std::to_string(n) + " bytes, more than the limit of " +
                              byte_count_text(max_bytes));
  };
  if (uint64_t(st.st_size) > max_bytes) throw too_large(uint64_t(st.st_size));
  std::string bytes(size_t(st.st_size), '\0');
  size_t done = 0;
  for (;;) {
    // A file that grows while it is read is read to its end, within the limit.
    if (done == bytes.size()) {
      if (bytes.size() >= max_bytes) {
        char probe;
        const ssize_t r = ::read(fd, &probe, 1);
        if (r > 0) throw too_large(uint64_t(bytes.size()) + 1);
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) throw std::runtime_error("cannot read '" + path + "': " + std::strerror(errno));
        break;
      }
      bytes.resize(size_t(std::min<uint64_t>(max_bytes, uint64_t(bytes.size()) * 2 + 4096)));
    }
    const ssize_t r = ::read(fd, bytes.data() + done, bytes.size() - done);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) throw std::runtime_error("cannot read '" + path + "': " + std::strerror(errno));
    if (r == 0) break;
    done += size_t(r);
  }
  bytes.resize(done);
  return bytes;
}

}  // namespace nns
