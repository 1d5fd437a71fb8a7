#pragma once
// The one image writer (OpenImageIO): previews, error heat maps and chart rasters for
// people, and any other raster a test or tool needs — never training data (the dataset
// is EXR through data/exr_io.h). Every file is written at a temporary name and renamed
// (core/atomic_file.h); errors read "<file>: <problem>". Planes are H x W floats, row 0
// at the top.
//
//   write_png_gray("ao.png", ao, w, h);                       // [0,1] -> 0..255, linear
//   write_png_rgb("gi.png", r, g, b, w, h, {.exposure = 2});  // HDR: Reinhard, then sRGB
//   write_png_heatmap("err.png", abs_err, w, h, 0.1f);        // 0 black -> max yellow-white
//   write_image("n.png", w, h, {"R","G","B"}, rgb, PixelType::u16);  // format from the name
//
// In the 8-bit previews, non-finite values are drawn magenta, so a NaN never hides as black.
#include <cstdint>
#include <string>
#include <vector>

namespace nns::report {

// Tone map for HDR lighting: c' = exposure * c; Reinhard c'/(1+c') (keeps highlights
// from clipping); then the sRGB transfer curve (IEC 61966-2-1) for display. With
// reinhard = false the value is clamped to [0,1] before sRGB instead (for albedo).
struct ToneMap {
  float exposure = 1.0f;
  bool reinhard = true;
};

// Linear map of [lo, hi] to 0..255, clamped, no gamma (AO, depth, masks).
void write_png_gray(const std::string& path, const float* v, int width, int height, float lo = 0, float hi = 1);
void write_png_rgb(const std::string& path, const float* r, const float* g, const float* b, int width, int height,
                   const ToneMap& tone = {});
// Error heat map: 0 -> black, through purple and orange, to pale yellow at `max`
// (a coarse "inferno"-like ramp, monotonic in lightness so it reads in grey too).
void write_png_heatmap(const std::string& path, const float* v, int width, int height, float max);

// The 8-bit layer: rgb holds width*height*3 bytes, row-major.
void write_png_rgb8(const std::string& path, const uint8_t* rgb, int width, int height);

// What the file stores. Integer types take [0,1] to 0..max (clamped, rounded); whether a
// format can hold the type is OpenImageIO's rule (PNG: u8/u16; HDR: f32 as RGBE; TIFF
// and EXR: all; EXR stores u8/u16 as HALF).
enum class PixelType { u8, u16, f16, f32 };

// Any format OpenImageIO writes, chosen by the file name's extension (.png, .tif, .hdr,
// .exr, ...): `pixels` holds width*height*channels.size() floats, interleaved, and
// `channels` names them (EXR keeps the names; other formats their count).
void write_image(const std::string& path, int width, int height, const std::vector<std::string>& channels,
                 const float* pixels, PixelType type);

// The colour maps themselves, for callers that compose their own images.
void heatmap_colour(float t, uint8_t rgb[3]);  // t in [0,1]
uint8_t srgb_encode(float linear);             // [0,1] linear -> 0..255 sRGB

}  // namespace nns::report
