#pragma once
// Coordinate channels for CoordConv (Liu et al. 2018): constant planes that tell a
// convolution where in the image it is.
//  - xy_coordinate_maps(W, H): for a single view, x and y of each pixel centre in [0,1],
//    x = (px + 0.5) / W left to right, y = (py + 0.5) / H top to bottom.
//  - phi_theta_maps(F): for the global view (data/global_view.h), the direction each
//    global-view pixel shows, as the thesis (sec. 4.2.2) derives it from a unit sphere
//    rendered through MergeToGlobalView — here computed analytically from the face
//    pixel each global pixel copies, in the front camera's space (x right, y up, -z
//    forward):
//      phi   = (atan2(x, -z) + pi) / (2 pi)   0.5 straight ahead, 0.75 right, 0.25 left,
//                                             0 and 1 behind (the global view's seam)
//      theta = acos(y) / pi                   0 straight up, 0.5 horizon, 1 straight down
// Both are rows of H x W floats, row 0 at the top, as View planes.
#include <algorithm>
#include <cmath>
#include <vector>

#include "data/global_view.h"

namespace nns::data {

struct XyMaps {
  std::vector<float> x, y;
};

inline XyMaps xy_coordinate_maps(int width, int height) {
  XyMaps m;
  m.x.resize(size_t(width) * size_t(height));
  m.y.resize(m.x.size());
  for (int py = 0; py < height; ++py)
    for (int px = 0; px < width; ++px) {
      size_t i = size_t(py) * size_t(width) + size_t(px);
      m.x[i] = (float(px) + 0.5f) / float(width);
      m.y[i] = (float(py) + 0.5f) / float(height);
    }
  return m;
}

struct PhiThetaMaps {
  std::vector<float> phi, theta;
};

inline float direction_phi(const std::array<float, 3>& d) {
  return float((std::atan2(double(d[0]), -double(d[2])) + M_PI) / (2 * M_PI));
}
inline float direction_theta(const std::array<float, 3>& d) {
  return float(std::acos(std::clamp(double(d[1]), -1.0, 1.0)) / M_PI);
}

inline PhiThetaMaps phi_theta_maps(int face_size) {
  const GlobalViewLayout& L = global_view_layout(face_size);
  PhiThetaMaps m;
  const size_t n = size_t(L.width) * size_t(L.height);
  m.phi.resize(n);
  m.theta.resize(n);
  const int F = face_size;
  for (size_t i = 0; i < n; ++i) {
    int p = L.source_pixel(int64_t(i));
    auto d = face_direction(L.source_face(int64_t(i)), p % F, p / F, F);
    m.phi[i] = direction_phi(d);
    m.theta[i] = direction_theta(d);
  }
  return m;
}

}  // namespace nns::data
