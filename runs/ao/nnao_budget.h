#pragma once
// "Model no more than a scene needs": given a trained ladder (nnao_ladder.h), a time
// budget and a frame size, the rung to ship — the highest rung (the ladder lists them
// from least to most accurate, as measured on the validation families) whose exact
// inference takes no more than the budget on this machine, timed here on a frame of
// that size. The frame is a dataset
// view brought to the size by nearest-pixel resampling (its depth and normals as they
// are), so the rungs are timed on real geometry, not on an empty plane.
//   export-nnao --ladder DIR --budget-ms X --size WxH [--view VIEW.exr]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/thread_pool.h"
#include "data/exr_io.h"
#include "models/nnao/nnao_inference.h"
#include "runs/ao/nnao_ladder.h"

namespace nns::runs {

// The view's G-buffer planes at width x height, each pixel from the nearest source pixel.
inline data::View resize_nearest(const data::View& v, int width, int height) {
  data::View out = v;
  out.width = width, out.height = height;
  out.channels.clear();
  for (const char* c : {"Z", "N.X", "N.Y", "N.Z"}) {
    if (!v.has(c)) throw std::runtime_error(v.source + ": missing channel '" + c + "'");
    const auto& src = v.channel(c);
    auto& dst = out.add_channel(c);
    dst.resize(size_t(width) * size_t(height));
    for (int y = 0; y < height; ++y) {
      const int sy = std::min(v.height - 1, int((int64_t(y) * v.height) / height));
      for (int x = 0; x < width; ++x)
        dst[size_t(y) * width + x] =
            src[size_t(sy) * v.width + std::min(v.width - 1, int((int64_t(x) * v.width) / width))];
    }
  }
  return out;
}

// The machine's processor, as /proc/cpuinfo names it ("" where it does not).
inline std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      return colon == std::string::npos ? "" : line.substr(line.find_first_not_of(' ', colon + 1));
    }
  return "";
}

struct TimedRung {
  LadderEntry rung;
  double ms = NAN;  // median wall time of the exact inference at the asked size
};

// Every rung timed on `view` resized to width x height (median of `rounds` runs after one
// warm-up, on the thread pool as it is set).
inline std::vector<TimedRung> time_ladder(const std::string& dir, const data::View& view, int width, int height,
                                          int rounds = 7) {
  const std::vector<LadderEntry> rungs = read_ladder(dir);
  const data::View frame = resize_nearest(view, width, height);
  const screen_space::GBuffer g = screen_space::gbuffer_from_view(frame);
  std::vector<float> out(size_t(g.pixels()));
  std::vector<TimedRung> timed;
  for (size_t k = 0; k < rungs.size(); ++k) {
    const nnao::NnaoWeights m = nnao::NnaoWeights::load(rungs[k].blob);
    std::vector<double> ms;
    for (int r = 0; r <= rounds; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      nnao::infer_exact(m, g, out.data());
      if (r > 0) ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    timed.push_back({rungs[k], ms[ms.size() / 2]});
  }
  return timed;
}

// The highest (most accurate) rung within the budget; nullptr when none fits.
inline const TimedRung* pick_rung(const std::vector<TimedRung>& timed, double budget_ms) {
  const TimedRung* pick = nullptr;
  for (auto& t : timed)
    if (t.ms <= budget_ms) pick = &t;
  return pick;
}

}  // namespace nns::runs
