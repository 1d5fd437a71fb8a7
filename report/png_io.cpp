#include "report/png_io.h"

#include <png.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace nns::data {
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
  static const float stops[5][3] = {{0.00f, 0.00f, 0.02f}, {0.34f, 0.06f, 0.43f}, {0.73f, 0.21f, 0.33f},
                                    {0.98f, 0.55f, 0.04f}, {0.99f, 1.00f, 0.64f}};
  t = std::clamp(t, 0.0f, 1.0f) * 4.0f;
  int i = std::min(int(t), 3);
  float f = t - float(i);
  for (int c = 0; c < 3; ++c) rgb[c] = unit_to_byte(stops[i][c] * (1 - f) + stops[i + 1][c] * f);
}

void write_png_rgb8(const std::string& path, const uint8_t* rgb, int w, int h) {
  check_size(path, w, h);
  const std::string tmp = path + ".partial-" + std::to_string(getpid());
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw std::runtime_error(path + ": cannot open for writing");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": libpng failed while writing");
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, png_uint_32(w), png_uint_32(h), 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < h; ++y) png_write_row(png, rgb + size_t(y) * size_t(w) * 3);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fclose(f) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": write failed (disk full?)");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot rename the finished file (" + ec.message() + ")");
  }
}

std::vector<uint8_t> read_png_rgb8(const std::string& path, int* width, int* height) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path.c_str()))
    throw std::runtime_error(path + ": not a readable PNG (" + img.message + ")");
  img.format = PNG_FORMAT_RGB;
  std::vector<uint8_t> out(PNG_IMAGE_SIZE(img));
  if (!png_image_finish_read(&img, nullptr, out.data(), 0, nullptr)) {
    png_image_free(&img);
    throw std::runtime_error(path + ": PNG decoding failed (" + img.message + ")");
  }
  *width = int(img.width);
  *height = int(img.height);
  return out;
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

}  // namespace nns::data
