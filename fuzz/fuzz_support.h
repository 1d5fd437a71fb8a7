#pragma once
// Shared by the libFuzzer targets (fuzz/README in docs/fuzzing.md): the rules every
// reader of outside bytes must keep, checked on every input.
//  * bad bytes end in an exception that names the source (file or blob) — never a crash,
//    a hang, a leak or an allocation sized by the input (ASan, UBSan and libFuzzer's
//    -rss_limit_mb / -malloc_limit_mb / -timeout catch those);
//  * an error that does not name its source is a finding too: abort() makes it a crash.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/blob.h"

namespace nns::fuzz {

[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "FUZZ FINDING: %s\n", what.c_str());
  std::abort();
}

// The error of a refused input must name `source`.
inline void expect_named(const std::exception& e, const std::string& source) {
  if (std::string(e.what()).find(source) == std::string::npos)
    finding("error does not name '" + source + "': " + e.what());
}

// A per-process scratch file (libFuzzer may run several jobs side by side).
inline std::string scratch_path(const std::string& name) {
  // /dev/shm when there is one: a file per execution, kept off the disk.
  static const std::string base = ::access("/dev/shm", W_OK) == 0 ? "/dev/shm/" : "/tmp/";
  static std::vector<std::string> made;  // removed when the fuzzer exits
  static const bool once = [] {
    std::atexit([] {
      std::error_code ec;
      for (auto& p : made) std::filesystem::remove_all(p, ec);
    });
    return true;
  }();
  (void)once;
  made.push_back(base + "nnshade-fuzz-" + std::to_string(::getpid()) + "-" + name);
  return made.back();
}
inline void write_bytes(const std::string& path, const uint8_t* data, size_t size) {
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

// The blob's CRC-32 and size fields would stop almost every mutation at the door; the
// harness repairs them so the fuzzer reaches the parser behind them (the unrepaired
// input is parsed too).
inline std::string with_valid_envelope(const uint8_t* data, size_t size) {
  std::string b(reinterpret_cast<const char*>(data), size);
  if (b.size() < Blob::kFixedHeader + 4) return b;
  uint64_t total = b.size();
  std::memcpy(&b[16], &total, 8);
  uint32_t crc = crc32(b.data(), b.size() - 4);
  std::memcpy(&b[b.size() - 4], &crc, 4);
  return b;
}

}  // namespace nns::fuzz
