#include "report/image_write.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/atomic_file.h"

namespace nns::report {
namespace {

constexpr uint8_t kNonFinite[3] = {255, 0, 255};

void check_size(const std::string& path, int w, int h) {
  if (w <= 0 || h <= 0)
    throw std::runtime_error(path + ": cannot write a " + std::to_string(w) + "x" + std::to_string(h) + " image");
}

uint8_t unit_to_byte(float t) { return uint8_t(std::lround(std::clamp(t, 0.0f, 1.0f) * 255.0f)); }

}  // namespace

uint8_t srgb_encode(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  float s = x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
  return unit_to_byte(s);
}

void heatmap_colour(float t, uint8_t rgb[3]) {
  // Control points sampled by eye from matplotlib's "inferno" (0, .25, .5, .75, 1).
  static const float stops[5][3] = {{0.00f, 0.00f, 0.02f},
                                    {0.34f, 0.06f, 0.43f},
                                    {0.73f, 0.21f, 0.33f},
                                    {0.98f, 0.55f, 0.04f},
                                    {0.99f, 1.00f, 0.64f}};
  t = std::clamp(t, 0.0f, 1.0f) * 4.0f;
  int i = std::min(int(t), 3);
  float f = t - float(i);
  for (int c = 0; c < 3; ++c) rgb[c] = unit_to_byte(stops[i][c] * (1 - f) + stops[i + 1][c] * f);
}

namespace {

OIIO::TypeDesc file_type(PixelType t) {
  switch (t) {
    case PixelType::u8:
      return OIIO::TypeDesc::UINT8;
    case PixelType::u16:
      return OIIO::TypeDesc::UINT16;
    case PixelType::f16:
      return OIIO::TypeDesc::HALF;
    case PixelType::f32:
      break;
  }
  return OIIO::TypeDesc::FLOAT;
}

// One path for every file: the format from the final name's extension (a caller's own
// temporary, "x.png.tmp.<pid>" as gi-infer's, counts as its target x.png), the bytes to
// the temporary name, then core/atomic_file.h's fsync and rename.
void write_pixels(const std::string& path, int w, int h, const std::vector<std::string>& channels,
                  OIIO::TypeDesc memory, const void* pixels, OIIO::TypeDesc stored) {
  check_size(path, w, h);
  if (channels.empty()) throw std::invalid_argument(path + ": an image needs at least one channel");
  write_path_atomic(path, [&](const std::string& tmp) {
    auto out = OIIO::ImageOutput::create(target_of_temporary(path));
    if (!out) throw std::runtime_error(path + ": no image format for this file name (" + OIIO::geterror() + ")");
    OIIO::ImageSpec spec(w, h, int(channels.size()), stored);
    spec.channelnames = channels;
    // Values stored as given: a 4th channel is data here, and OpenImageIO would otherwise
    // divide the colour by it ("unassociate") before storing a PNG or TIFF.
    spec.alpha_channel = -1;
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!out->open(tmp, spec)) throw std::runtime_error(path + ": cannot open for writing (" + out->geterror() + ")");
    const bool wrote = out->write_image(memory, pixels);
    const bool closed = out->close();
    if (!wrote || !closed) throw std::runtime_error(path + ": write failed (" + out->geterror() + ")");
  });
}

}  // namespace

void write_image(const std::string& path, int w, int h, const std::vector<std::string>& channels, const float* pixels,
                 PixelType type) {
  write_pixels(path, w, h, channels, OIIO::TypeDesc::FLOAT, pixels, file_type(type));
}

void write_png_rgb8(const std::string& path, const uint8_t* rgb, int w, int h) {
  write_pixels(path, w, h, {"R", "G", "B"}, OIIO::TypeDesc::UINT8, rgb, OIIO::TypeDesc::UINT8);
}

void write_png_gray(const std::string& path, const float* v, int w, int h, float lo, float hi) {
  check_size(path, w, h);
  std::vector<uint8_t> rgb(size_t(w) * size_t(h) * 3);
  const float scale = hi > lo ? 1.0f / (hi - lo) : 0.0f;
  for (size_t i = 0; i < size_t(w) * size_t(h); ++i) {
    if (!std::isfinite(v[i])) {
      std::copy(kNonFinite, kNonFinite + 3, &rgb[3 * i]);
      continue;
    }
    uint8_t g = unit_to_byte((v[i] - lo) * scale);
    rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = g;
  }
  write_png_rgb8(path, rgb.data(), w, h);
}

void write_png_rgb(const std::string& path, const float* r, const float* g, const float* b, int w, int h,
                   const ToneMap& tone) {
  check_size(path, w, h);
  std::vector<uint8_t> rgb(size_t(w) * size_t(h) * 3);
  const float* planes[3] = {r, g, b};
  for (size_t i = 0; i < size_t(w) * size_t(h); ++i) {
    if (!std::isfinite(r[i]) || !std::isfinite(g[i]) || !std::isfinite(b[i])) {
      std::copy(kNonFinite, kNonFinite + 3, &rgb[3 * i]);
      continue;
    }
    for (int c = 0; c < 3; ++c) {
      float x = std::max(0.0f, planes[c][i] * tone.exposure);
      rgb[3 * i + size_t(c)] = srgb_encode(tone.reinhard ? x / (1 + x) : x);
    }
  }
  write_png_rgb8(path, rgb.data(), w, h);
}

void write_png_heatmap(const std::string& path, const float* v, int w, int h, float max) {
  check_size(path, w, h);
  if (!(max > 0)) throw std::invalid_argument(path + ": heat map needs max > 0");
  std::vector<uint8_t> rgb(size_t(w) * size_t(h) * 3);
  for (size_t i = 0; i < size_t(w) * size_t(h); ++i) {
    if (!std::isfinite(v[i])) std::copy(kNonFinite, kNonFinite + 3, &rgb[3 * i]);
    else heatmap_colour(v[i] / max, &rgb[3 * i]);
  }
  write_png_rgb8(path, rgb.data(), w, h);
}

}  // namespace nns::report
