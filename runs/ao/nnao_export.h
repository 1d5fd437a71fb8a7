#pragma once
// Export of a trained NNAO for engines (paper, section 5), what export-nnao writes:
//  * nnao.frag: the NNAO pass, a GLSL 330 fragment shader with the network embedded:
//    for a grid model the shader-style inference (nnao_glsl_grid.h), for a horizon
//    model its march (nnao_glsl_horizon.h); nnao_blur.frag: the bilateral blur that
//    follows it in nnao-infer (nnao_glsl_blur.h), drawn as NNAO_BLUR_PAIRS pairs. docs/nnao.md says how
//    an engine draws them; examples/nnao_gl runs them. A model at 1/s resolution adds
//    nnao_downsample.frag before them and nnao_upsample.frag after (nnao_glsl_resolution.h).
//  * grid models only: the first layer's weights as H filter images (the paper's
//    Figure 2): filter k is a w x w RGBA image, channels = weights of the (Nx, Ny, Nz,
//    depth) features at that grid point, with the feature standardisation folded in
//    (what the shader multiplies raw features by). EXR (exact floats) + PNG (viewing:
//    normal weights as RGB, depth weights as grey, each scaled to its largest |w|);
//    nnao_filters.exr: all filters side by side (width H*w), the texture nnao.frag reads.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "data/exr_io.h"
#include "report/image_write.h"
#include "models/nnao/nnao_inference.h"
#include "models/nnao/nnao_weights.h"
#include "core/atomic_file.h"
#include "runs/ao/nnao_glsl_blur.h"
#include "runs/ao/nnao_glsl_grid.h"
#include "runs/ao/nnao_glsl_horizon.h"
#include "runs/ao/nnao_glsl_resolution.h"

namespace nns::runs {

// Filter k as four planes (w x w each): R, G, B, A = Nx, Ny, Nz, depth weights.
inline std::vector<std::vector<float>> filter_planes(const nnao::NnaoWeights& m, int k) {
  const int w = m.input.window;
  std::vector<std::vector<float>> p(4, std::vector<float>(size_t(w) * w));
  for (int j = 0; j < w; ++j)
    for (int i = 0; i < w; ++i)
      for (int c = 0; c < 4; ++c)
        p[size_t(c)][size_t(j) * w + i] = m.w0[size_t(int64_t(k) * m.features() + (int64_t(j) * w + i) * 4 + c)];
  return p;
}

inline data::View filter_view(int width, int height, const std::vector<std::vector<float>>& rgba) {
  data::View v;
  v.width = width;
  v.height = height;
  v.fov_y_deg = 90;  // not a camera view; the attribute is required by the format
  v.scene = "nnao-filter";
  const char* names[4] = {"R", "G", "B", "A"};
  for (int c = 0; c < 4; ++c) v.add_channel(names[c]) = rgba[size_t(c)];
  return v;
}

// Writes filter<k>.exr/.png (+ filter<k>_depth.png) and nnao_filters.exr into dir.
inline void write_filter_images(const nnao::NnaoWeights& m, const std::string& dir) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  const int w = m.input.window, H = m.hidden;
  std::vector<std::vector<float>> atlas(4, std::vector<float>(size_t(w) * w * H));
  for (int k = 0; k < H; ++k) {
    auto p = filter_planes(m, k);
    const std::string base = (fs::path(dir) / ("filter" + std::to_string(k))).string();
    data::write_view(base + ".exr", filter_view(w, w, p));
    float mn = 1e-12f, md = 1e-12f;
    for (size_t i = 0; i < p[0].size(); ++i) {
      for (int c = 0; c < 3; ++c) mn = std::max(mn, std::abs(p[size_t(c)][i]));
      md = std::max(md, std::abs(p[3][i]));
    }
    std::vector<float> rgb[3];
    for (int c = 0; c < 3; ++c) {
      rgb[c].resize(p[0].size());
      for (size_t i = 0; i < p[0].size(); ++i) rgb[c][i] = 0.5f + 0.5f * p[size_t(c)][i] / mn;
    }
    report::write_png_gray(base + "_depth.png", p[3].data(), w, w, -md, md);
    // Linear RGB through the sRGB curve would distort the sign around 0.5: write bytes.
    std::vector<uint8_t> rgb8(size_t(w) * w * 3);
    for (size_t i = 0; i < p[0].size(); ++i)
      for (int c = 0; c < 3; ++c)
        rgb8[i * 3 + size_t(c)] = uint8_t(std::lround(255 * std::min(1.0f, std::max(0.0f, rgb[c][i]))));
    report::write_png_rgb8(base + ".png", rgb8.data(), w, w);
    for (int c = 0; c < 4; ++c)
      for (int j = 0; j < w; ++j)
        for (int i = 0; i < w; ++i)
          atlas[size_t(c)][size_t(j) * w * H + size_t(k) * w + i] = p[size_t(c)][size_t(j) * w + i];
  }
  data::write_view((fs::path(dir) / "nnao_filters.exr").string(), filter_view(w * H, w, atlas));
}

// Writes the shaders (and a grid model's filter images) into dir; returns the files'
// names. `samples` is a grid shader's default uSamples (a horizon model's march is fixed).
inline std::vector<std::string> write_export(const nnao::NnaoWeights& m, const std::string& dir, int samples) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  std::vector<std::string> files = {"nnao.frag", "nnao_blur.frag"};
  if (m.input.is_horizon()) {
    write_file_atomic((fs::path(dir) / "nnao.frag").string(), glsl_horizon_pass(m));
  } else {
    nnao::check_sample_count(samples, m.input);
    write_filter_images(m, dir);
    write_file_atomic((fs::path(dir) / "nnao.frag").string(), glsl_grid_pass(m, samples));
    files.push_back("nnao_filters.exr");
    files.push_back("filter<k>.exr/.png");
  }
  const bool horizon = m.input.is_horizon();  // the grid's blur keeps the first terms, one pair
  write_file_atomic((fs::path(dir) / "nnao_blur.frag").string(),
                    glsl_blur_pass(horizon ? m.blur_passes : 1, horizon ? m.blur_edges : nnao::BlurEdges{}));
  if (horizon && m.downsample > 1) {  // the frame at 1/s, then back (nnao_glsl_resolution.h)
    write_file_atomic((fs::path(dir) / "nnao_downsample.frag").string(), glsl_downsample_pass(m.downsample));
    write_file_atomic((fs::path(dir) / "nnao_upsample.frag").string(), glsl_upsample_pass(m.downsample, m.blur_edges));
    files.push_back("nnao_downsample.frag");
    files.push_back("nnao_upsample.frag");
  } else {  // a full-resolution model's export holds no resolution passes, even over an older export
    for (const char* f : {"nnao_downsample.frag", "nnao_upsample.frag"}) fs::remove(fs::path(dir) / f);
  }
  return files;
}

}  // namespace nns::runs
