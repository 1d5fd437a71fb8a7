#pragma once
// A bounded first pass over an OpenEXR header, before OpenEXR reads it: OpenEXR sizes
// its buffers (and data/exr_io.cpp its planes) from the header's data window, tile size
// and attribute lengths, so a 10 KB file can declare gigabytes. Every length is checked
// against the bytes the file holds, and the declared image against the file size and a
// sane maximum, before anything is allocated from it.
#include <cstdint>
#include <string>

namespace nns::data {

struct ExrHeaderLimits {
  // Largest side of a view. A G-buffer view is a screen; 16384 is four 4K screens wide.
  int64_t max_side = 16384;
  // Decoded planes (FLOAT, every channel) may be at most this many times the file size:
  // deflate's best ratio is about 1032:1, stored HALF doubles when read as FLOAT.
  int64_t max_expansion = 4096;
  // ...but a small file may always declare this much (tiny constant images compress
  // better than any ratio), and no file more than max_decoded_bytes.
  int64_t small_file_allowance = int64_t(8) << 20;
  int64_t max_decoded_bytes = int64_t(4) << 30;
};

struct ExrHeaderFacts {
  int64_t width = 0, height = 0, channels = 0, file_bytes = 0;
  bool tiled = false;
  int64_t tile_width = 0, tile_height = 0;
};

// Throws "<path>: <problem>" for a header that is malformed or declares more than the
// file can hold. Single-part flat files only (read_view refuses the others first).
ExrHeaderFacts check_exr_header(const std::string& path, const ExrHeaderLimits& limits = {});

}  // namespace nns::data
