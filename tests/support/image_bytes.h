#pragma once
// Reads a PNG (or any image) back as 8-bit RGB through OpenImageIO directly, so a test
// of a writer checks the file as another program sees it. Grey images come back with
// R = G = B. Fails the test (throws) naming the file.
#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace nns::testing {

inline std::vector<uint8_t> read_rgb8(const std::string& path, int* width, int* height) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw std::runtime_error(path + ": " + OIIO::geterror());
  const OIIO::ImageSpec& s = in->spec();
  const int nc = s.nchannels;
  std::vector<uint8_t> all(size_t(s.width) * size_t(s.height) * size_t(nc));
  if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::UINT8, all.data()))
    throw std::runtime_error(path + ": " + in->geterror());
  std::vector<uint8_t> rgb(size_t(s.width) * size_t(s.height) * 3);
  for (size_t i = 0; i < size_t(s.width) * size_t(s.height); ++i)
    for (int c = 0; c < 3; ++c) rgb[3 * i + size_t(c)] = all[i * size_t(nc) + size_t(nc >= 3 ? c : 0)];
  *width = s.width;
  *height = s.height;
  return rgb;
}

}  // namespace nns::testing
