#pragma once
// Loading a split of a G-buffer dataset into GiSamples (gi_inputs.h): all of it, or one
// item at a time (gi_training_frames.h streams training frames that do not fit in memory).
//
//  * --mode front takes single views, or the `front` face of surround frames;
//  * --mode surround takes surround frames and merges their six faces into the global
//    view (data/global_view.h); a frame with a missing face is refused by read_frame()
//    with a message naming the folder and the face.
//  * --size N box-filters every face down to N x N (N must divide the face size), so
//    one rendered dataset serves every input size of the sweep.
// The normalisation constants (depth range, HDR scale) are fitted on the training split
// once and stored in the model blob, so test data is assembled exactly like training.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/progress.h"
#include "data/coord_maps.h"
#include "data/dataset.h"
#include "data/exr_io.h"
#include "data/global_view.h"
#include "data/kept_views.h"
#include "models/gi/gi_inputs.h"

namespace nns::runs {

// Box-filters every plane of `v` by `factor`. Depth averages the geometry pixels of a
// block (sky only if the whole block is sky); normals are renormalised.
inline data::View downsample_view(const data::View& v, int factor) {
  data::check_depth(v);  // NaN, 0 or negative depth would be averaged away as sky
  if (factor == 1) return v;
  if (v.width % factor || v.height % factor)
    throw std::runtime_error(v.source + ": size " + std::to_string(v.width) + "x" + std::to_string(v.height) +
                             " is not a multiple of the reduction " + std::to_string(factor));
  data::View o = v;
  o.width = v.width / factor, o.height = v.height / factor;
  const float inv = 1.0f / float(factor * factor);
  for (auto& [name, plane] : v.channels) {
    auto& dst = o.add_channel(name);
    for (int y = 0; y < o.height; ++y)
      for (int x = 0; x < o.width; ++x) {
        double s = 0;
        int geo = 0;
        for (int dy = 0; dy < factor; ++dy)
          for (int dx = 0; dx < factor; ++dx) {
            float val = plane[size_t(y * factor + dy) * size_t(v.width) + size_t(x * factor + dx)];
            if (name == "Z") {
              if (data::is_sky(val)) continue;
              ++geo;
            }
            s += val;
          }
        float& d = dst[size_t(y) * size_t(o.width) + size_t(x)];
        if (name == "Z") d = geo ? float(s / geo) : INFINITY;
        else d = float(s) * inv;
      }
  }
  if (o.has("N.X") && o.has("N.Y") && o.has("N.Z")) {
    auto &nx = o.channels["N.X"], &ny = o.channels["N.Y"], &nz = o.channels["N.Z"];
    for (size_t i = 0; i < nx.size(); ++i) {
      float len = std::sqrt(nx[i] * nx[i] + ny[i] * ny[i] + nz[i] * nz[i]);
      if (len > 1e-6f) nx[i] /= len, ny[i] /= len, nz[i] /= len;
    }
  }
  return o;
}

inline int reduction_for(const data::View& v, int size, const std::string& what) {
  if (size <= 0) return 1;
  if (v.width != v.height && size != v.width)
    throw std::runtime_error(what + ": --size needs square views, got " + std::to_string(v.width) + "x" +
                             std::to_string(v.height));
  if (v.width % size)
    throw std::runtime_error(what + ": --size " + std::to_string(size) + " must divide the view size " +
                             std::to_string(v.width));
  return v.width / size;
}

// Coordinate channels in [-1, 1]: (x, y) for one view, (phi, theta) for a global view.
inline void append_coords(Tensor<float>& input, const std::vector<float>& c0, const std::vector<float>& c1,
                          int64_t first_channel) {
  const int64_t n = input.size(2) * input.size(3);
  for (int64_t i = 0; i < n; ++i) {
    input[first_channel * n + i] = 2.0f * c0[size_t(i)] - 1.0f;
    input[(first_channel + 1) * n + i] = 2.0f * c1[size_t(i)] - 1.0f;
  }
}

// One front view -> sample. targets = false: a frame without ground truth (gi-infer);
// the sample gets no target, only what shades a prediction.
inline gi::GiSample assemble_front(const data::View& v, const gi::GiInputConfig& cfg, bool targets = true) {
  gi::GiSample s;
  s.name = v.source;
  s.scene = v.scene;
  Tensor<float> planes = gi::view_planes(v, cfg.norm);
  s.input = Tensor<float>({1, cfg.channels(), v.height, v.width});
  std::copy(planes.begin(), planes.end(), s.input.begin());
  if (cfg.coordconv) {
    auto xy = data::xy_coordinate_maps(v.width, v.height);
    append_coords(s.input, xy.x, xy.y, 10);
  }
  s.front = {0, 0, v.width, v.height};
  s.front_geometry = gi::geometry_of(v);
  if (targets) gi::fill_front_targets(s, v, cfg.norm);
  else gi::fill_front_shading(s, v);
  return s;
}

// Share of the frame's direct light (summed over the six faces) that the front face
// sees: low means the directly lit surfaces are off the screen (the thesis's case).
inline float front_direct_share(const std::array<data::View, 6>& faces) {
  double all = 0, front = 0;
  for (int f = 0; f < 6; ++f)
    for (char c : {'R', 'G', 'B'}) {
      const auto& d = faces[size_t(f)].channel(std::string("direct.") + c);
      double s = 0;
      for (float x : d) s += x;
      all += s;
      if (f == 0) front += s;
    }
  return all > 0 ? float(front / all) : 1.0f;
}

// Six faces -> sample on the global view (front region = the front face).
inline gi::GiSample assemble_surround(const std::array<data::View, 6>& faces, const gi::GiInputConfig& cfg,
                                      const std::string& name, bool targets = true) {
  const int F = faces[0].width;
  std::array<Tensor<float>, 6> planes;
  for (int f = 0; f < 6; ++f) planes[size_t(f)] = gi::view_planes(faces[size_t(f)], cfg.norm);
  const data::GlobalViewLayout& layout = data::global_view_layout(F);
  gi::GiSample s;
  s.name = name;
  s.scene = faces[0].scene;
  s.input = Tensor<float>({1, cfg.channels(), layout.height, layout.width});
  const int64_t fn = int64_t(F) * F, gn = int64_t(layout.height) * layout.width;
  for (int c = 0; c < 10; ++c) {
    std::array<const float*, 6> src;
    for (int f = 0; f < 6; ++f) src[size_t(f)] = planes[size_t(f)].data() + c * fn;
    data::merge_to_global_view(src, F, s.input.data() + c * gn);
  }
  if (cfg.coordconv) {
    auto pt = data::phi_theta_maps(F);
    append_coords(s.input, pt.phi, pt.theta, 10);
  }
  auto r = layout.front_rect();
  s.front = {r.x0, r.y0, r.w, r.h};
  s.front_geometry = gi::geometry_of(faces[0]);
  if (targets) gi::fill_front_targets(s, faces[0], cfg.norm);
  else gi::fill_front_shading(s, faces[0]);
  s.front_direct_share = front_direct_share(faces);
  return s;
}

// Reads one item of a split (a view or a frame) at the requested size: from its files, or
// from the views the dataset check kept (data/kept_views.h), which shrink() has already
// brought to that size.
struct GiItemReader {
  gi::GiMode mode;
  int size;                         // 0: as stored
  data::KeptViews* kept = nullptr;  // complete, or null: read the files
  bool take = false;                // this read is a kept view's last use: move it out
  std::array<data::View, 6> frame(const data::FrameEntry& e) const {
    if (kept) {
      std::array<data::View, 6> faces;
      for (size_t i = 0; i < 6; ++i) faces[i] = kept_view(e.faces[i]);
      return faces;
    }
    auto faces = data::read_frame(e);
    int k = reduction_for(faces[0], size, e.dir);
    for (auto& f : faces) f = downsample_view(f, k);
    return faces;
  }
  data::View view(const std::string& path) const {
    if (kept) return kept_view(path);
    return shrink(data::read_view(path));
  }
  // A view as read from its file -> the view at the requested size.
  data::View shrink(data::View v) const { return downsample_view(v, reduction_for(v, size, v.source)); }

 private:
  data::View kept_view(const std::string& path) const { return take ? kept->take(path) : kept->get(path); }
};

inline size_t split_items(const data::SplitListing& s, gi::GiMode mode) {
  return mode == gi::GiMode::surround || s.views.empty() ? s.frames.size() : s.views.size();
}

// Calls fn(item index, front view, faces or nullptr, name) for the items first .. max_items-1
// of the split.
template <class Fn>
void for_each_item(const data::SplitListing& s, const GiItemReader& rd, size_t max_items, Fn&& fn, size_t first = 0) {
  const bool frames = rd.mode == gi::GiMode::surround || s.views.empty();
  if (rd.mode == gi::GiMode::surround && s.frames.empty())
    throw std::runtime_error(s.dir + ": --mode surround needs surround frames (folders of six faces)");
  size_t n = std::min(max_items, split_items(s, rd.mode));
  for (size_t i = first; i < n; ++i) {
    if (frames) {
      auto faces = rd.frame(s.frames[i]);
      fn(i, faces[0], &faces, s.frames[i].dir);
    } else {
      auto v = rd.view(s.views[i]);
      fn(i, v, static_cast<std::array<data::View, 6>*>(nullptr), s.views[i]);
    }
  }
}

// Depth range: the 99th percentile of geometry depth (a far outlier must not squash the
// rest); HDR scale: the median of the target light over geometry pixels of front views;
// the light cap: their maximum.
inline gi::GiNormalisation fit_normalisation(const data::SplitListing& train, const GiItemReader& rd,
                                             size_t max_items) {
  std::vector<float> depths, light;
  float light_max = 0;
  for_each_item(train, rd, max_items,
                [&](size_t, const data::View& front, std::array<data::View, 6>* faces, const std::string&) {
                  auto take_depth = [&](const data::View& v) {
                    const auto& z = v.channel("Z");
                    for (size_t i = 0; i < z.size(); i += 7)
                      if (!data::is_sky(z[i])) depths.push_back(z[i]);
                  };
                  if (faces)
                    for (auto& f : *faces) take_depth(f);
                  else take_depth(front);
                  const auto& z = front.channel("Z");
                  for (char c : {'R', 'G', 'B'}) {
                    const auto& d = front.channel(std::string("direct.") + c);
                    const auto& ind = front.channel(std::string("indirect.") + c);
                    std::string env = std::string("env.") + c;
                    const std::vector<float>* e = front.has(env) ? &front.channel(env) : nullptr;
                    for (size_t i = 0; i < d.size(); ++i) {
                      if (data::is_sky(z[i])) continue;
                      float t = d[i] + ind[i] + (e ? (*e)[i] : 0.0f);
                      light_max = std::max(light_max, t);
                      if (i % 5 == 0) light.push_back(t);
                    }
                  }
                });
  gi::GiNormalisation n;
  auto pct = [](std::vector<float>& v, double q) {
    size_t k = std::min(v.size() - 1, size_t(q * double(v.size())));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return v[k];
  };
  if (!depths.empty()) n.depth_max = std::max(pct(depths, 0.99), 1e-6f);
  if (!light.empty()) n.hdr_scale = pct(light, 0.5);
  if (!(n.hdr_scale > 1e-6f)) n.hdr_scale = 1.0f;
  if (light_max > 0) n.light_max = light_max;
  return n;
}

// Item i of a split as a sample, assembled as for training (and as eval-gi does).
inline gi::GiSample load_sample(const data::SplitListing& split, const GiItemReader& rd, const gi::GiInputConfig& cfg,
                                size_t i) {
  if (i >= split_items(split, rd.mode)) throw std::out_of_range(split.dir + ": no item " + std::to_string(i));
  gi::GiSample out;
  for_each_item(
      split, rd, i + 1,
      [&](size_t, const data::View& front, std::array<data::View, 6>* faces, const std::string& name) {
        if (rd.mode == gi::GiMode::surround) {
          out = assemble_surround(*faces, cfg, name);
        } else {
          out = assemble_front(front, cfg);
          out.name = name;
          if (faces) out.front_direct_share = front_direct_share(*faces);
        }
      },
      i);
  return out;
}

inline std::vector<gi::GiSample> load_samples(const data::SplitListing& split, const GiItemReader& rd,
                                              const gi::GiInputConfig& cfg, size_t max_items, const std::string& label,
                                              bool quiet = false) {
  std::vector<gi::GiSample> out(std::min(max_items, split_items(split, rd.mode)));
  Progress bar(label, int64_t(out.size()));
  for (size_t i = 0; i < out.size(); ++i) {
    out[i] = load_sample(split, rd, cfg, i);
    if (!quiet) bar.update(int64_t(i + 1));
  }
  return out;
}

// The bytes one sample holds (its tensors and masks): what decides whether a split fits
// in memory.
inline size_t sample_bytes(const gi::GiSample& s) {
  size_t b = 0;
  for (const Tensor<float>* t : {&s.input, &s.target, &s.albedo, &s.emission, &s.direct_env, &s.target_linear})
    if (t->defined()) b += size_t(t->numel()) * sizeof(float);
  return b + data::view_bytes(s.front_geometry) + s.geometry.size();
}

}  // namespace nns::runs
