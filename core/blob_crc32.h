#pragma once
// CRC-32 as in zlib, PNG and Ethernet (reflected polynomial 0xEDB88320, initial value
// and final xor 0xFFFFFFFF), so a blob's checksum can be verified with Python's
// zlib.crc32 or any off-the-shelf implementation.
#include <array>
#include <cstddef>
#include <cstdint>

namespace nns {

inline constexpr std::array<uint32_t, 256> make_crc32_table() {
  std::array<uint32_t, 256> table{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  return table;
}

inline uint32_t crc32(const void* data, size_t n, uint32_t crc = 0) {
  static constexpr std::array<uint32_t, 256> table = make_crc32_table();
  const auto* p = static_cast<const unsigned char*>(data);
  crc = ~crc;
  for (size_t i = 0; i < n; ++i) crc = table[(crc ^ p[i]) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

}  // namespace nns
