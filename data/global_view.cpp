#include "data/global_view.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace nns::data {

FaceBasis face_basis(Face f) {
  switch (f) {
    case Face::front:
      return {{0, 0, -1}, {1, 0, 0}, {0, 1, 0}};
    case Face::back:
      return {{0, 0, 1}, {-1, 0, 0}, {0, 1, 0}};
    case Face::left:
      return {{-1, 0, 0}, {0, 0, -1}, {0, 1, 0}};
    case Face::right:
      return {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}};
    case Face::up:
      return {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}};
    case Face::down:
      return {{0, -1, 0}, {1, 0, 0}, {0, 0, -1}};
  }
  throw std::invalid_argument("face_basis: bad face");
}

std::array<float, 3> face_direction(Face f, int px, int py, int F) {
  const FaceBasis b = face_basis(f);
  const double a = 2.0 * (px + 0.5) / F - 1.0, c = 1.0 - 2.0 * (py + 0.5) / F;
  double d[3], len = 0;
  for (int k = 0; k < 3; ++k) {
    d[k] = b.forward[size_t(k)] + a * b.right[size_t(k)] + c * b.up[size_t(k)];
    len += d[k] * d[k];
  }
  len = std::sqrt(len);
  return {float(d[0] / len), float(d[1] / len), float(d[2] / len)};
}

namespace {

// Ring order of the side faces across the middle band, starting at x = F - h.
constexpr Face kRing[4] = {Face::left, Face::front, Face::right, Face::back};

// Normalised point on the up/down face where the edge shared with ring face k is
// crossed at fraction u along that face's top/bottom row (derived from face_basis:
// the two faces' directions agree along the shared edge).
std::array<double, 2> up_edge(int k, double u) {
  switch (k) {
    case 0:
      return {0, u};  // left  face top row  <-> up's left column
    case 1:
      return {u, 1};  // front face top row  <-> up's bottom row
    case 2:
      return {1, 1 - u};  // right face top row  <-> up's right column
    default:
      return {1 - u, 0};  // back  face top row  <-> up's top row
  }
}
std::array<double, 2> down_edge(int k, double u) {
  switch (k) {
    case 0:
      return {0, 1 - u};
    case 1:
      return {u, 0};
    case 2:
      return {1, u};
    default:
      return {1 - u, 1};
  }
}

int clamp_pixel(double v, int F) { return std::clamp(int(std::floor(v * F)), 0, F - 1); }

}  // namespace

GlobalViewLayout::GlobalViewLayout(int F)
    : face_size(F), width(4 * F), height(2 * F), top_rows(F / 2), bottom_rows(F - F / 2) {
  if (F < 2) throw std::invalid_argument("global view: face size must be >= 2, got " + std::to_string(F));
  const int h = F / 2;
  face_.resize(size_t(width) * size_t(height));
  pixel_.resize(face_.size());
  for (int x = 0; x < width; ++x) {
    const int p = ((x - (F - h)) % width + width) % width;  // position along the ring
    const int k = p / F, u_pix = p % F;
    const double u = (u_pix + 0.5) / F;
    for (int y = 0; y < height; ++y) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      Face face;
      int px, py;
      if (y >= top_rows && y < top_rows + F) {
        face = kRing[k], px = u_pix, py = y - top_rows;
      } else {
        const bool top = y < top_rows;
        // t: 0 at the pole (outer row), -> 1 at the edge shared with the side face.
        const double t = top ? (y + 0.5) / top_rows : (height - y - 0.5) / bottom_rows;
        const auto e = top ? up_edge(k, u) : down_edge(k, u);
        face = top ? Face::up : Face::down;
        px = clamp_pixel(0.5 + t * (e[0] - 0.5), F);
        py = clamp_pixel(0.5 + t * (e[1] - 0.5), F);
      }
      face_[i] = uint8_t(face);
      pixel_[i] = py * F + px;
    }
  }
}

PixelRect GlobalViewLayout::front_rect() const {
  return {2 * face_size - face_size / 2, top_rows, face_size, face_size};
}

const GlobalViewLayout& global_view_layout(int F) {
  static std::mutex mu;
  static std::map<int, std::unique_ptr<GlobalViewLayout>> cache;
  std::lock_guard<std::mutex> lock(mu);
  auto& slot = cache[F];
  if (!slot) slot = std::make_unique<GlobalViewLayout>(F);
  return *slot;
}

void merge_to_global_view(const std::array<const float*, 6>& faces, int F, float* out) {
  const GlobalViewLayout& L = global_view_layout(F);
  const int64_t n = int64_t(L.width) * L.height;
  for (int64_t i = 0; i < n; ++i) out[i] = faces[size_t(L.source_face(i))][L.source_pixel(i)];
}

Tensor<float> extract_front(const Tensor<float>& g) {
  if (g.dim() != 4 || g.size(3) != 2 * g.size(2))
    throw std::invalid_argument("extract_front: expected (N, C, 2F, 4F), got " + g.shape().str());
  const int F = int(g.size(2) / 2);
  if (g.size(3) != 4 * F || g.size(2) != 2 * F)
    throw std::invalid_argument("extract_front: expected (N, C, 2F, 4F), got " + g.shape().str());
  const PixelRect r = global_view_layout(F).front_rect();
  const int64_t planes = g.size(0) * g.size(1);
  Tensor<float> out({g.size(0), g.size(1), F, F});
  for (int64_t p = 0; p < planes; ++p)
    for (int y = 0; y < F; ++y) {
      const float* src = g.data() + p * 8 * F * F + int64_t(r.y0 + y) * 4 * F + r.x0;
      std::copy(src, src + F, out.data() + p * F * F + int64_t(y) * F);
    }
  return out;
}

}  // namespace nns::data
