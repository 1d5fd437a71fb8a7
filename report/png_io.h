#pragma once
// 8-bit PNG previews of float planes (libpng), for reports and docs — never training data
// (use EXR for that). All planes are H x W floats, row 0 at the top.
//
//   write_png_gray("ao.png", ao, w, h);                       // [0,1] -> 0..255, linear
//   write_png_rgb("gi.png", r, g, b, w, h, {.exposure = 2});  // HDR: Reinhard, then sRGB
//   write_png_heatmap("err.png", abs_err, w, h, 0.1f);        // 0 black -> max yellow-white
//
// Non-finite values are drawn magenta, so a NaN never hides as black.
#include <cstdint>
#include <string>
#include <vector>

namespace nns::data {

// Tone map for HDR lighting: c' = exposure * c; Reinhard c'/(1+c') (keeps highlights
// from clipping); then the sRGB transfer curve (IEC 61966-2-1) for display. With
// reinhard = false the value is clamped to [0,1] before sRGB instead (for albedo).
struct ToneMap {
  float exposure = 1.0f;
  bool reinhard = true;
};

// Linear map of [lo, hi] to 0..255, clamped, no gamma (AO, depth, masks).
void write_png_gray(const std::string& path, const float* v, int width, int height, float lo = 0,
                    float hi = 1);
void write_png_rgb(const std::string& path, const float* r, const float* g, const float* b, int width,
                   int height, const ToneMap& tone = {});
// Error heat map: 0 -> black, through purple and orange, to pale yellow at `max`
// (a coarse "inferno"-like ramp, monotonic in lightness so it reads in grey too).
void write_png_heatmap(const std::string& path, const float* v, int width, int height, float max);

// The 8-bit layer: rgb holds width*height*3 bytes, row-major. Written to a temporary
// name and renamed; throws "<file>: <problem>".
void write_png_rgb8(const std::string& path, const uint8_t* rgb, int width, int height);

// Reads an 8-bit RGB or grey PNG back as RGB bytes (tests and tools).
std::vector<uint8_t> read_png_rgb8(const std::string& path, int* width, int* height);

// The colour maps themselves, for callers that compose their own images.
void heatmap_colour(float t, uint8_t rgb[3]);   // t in [0,1]
uint8_t srgb_encode(float linear);               // [0,1] linear -> 0..255 sRGB

}  // namespace nns::data
