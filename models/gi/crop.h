#pragma once
// crop2d: a rectangle of an NCHW tensor, recorded in the autograd graph.
// Surround mode predicts the whole global view but only its front region has a ground
// truth; the loss, the discriminator and the metrics look at that region through this.
//   x (N, C, H, W) -> out (N, C, h, w) = x[:, :, y0:y0+h, x0:x0+w]
#include <cstring>
#include <stdexcept>
#include <string>

#include "core/autograd.h"

namespace nns::gi {

struct Rect {
  int64_t x0 = 0, y0 = 0, w = 0, h = 0;
  bool operator==(const Rect&) const = default;
};

template <class T>
void crop2d_forward(T* out, const T* inp, int64_t NC, int64_t H, int64_t W, const Rect& r) {
  for (int64_t p = 0; p < NC; ++p)
    for (int64_t y = 0; y < r.h; ++y)
      std::memcpy(out + (p * r.h + y) * r.w, inp + (p * H + r.y0 + y) * W + r.x0, sizeof(T) * size_t(r.w));
}

// Accumulates dout into the rectangle of dinp (the gradient contract).
template <class T>
void crop2d_backward(T* dinp, const T* dout, int64_t NC, int64_t H, int64_t W, const Rect& r) {
  for (int64_t p = 0; p < NC; ++p)
    for (int64_t y = 0; y < r.h; ++y) {
      T* d = dinp + (p * H + r.y0 + y) * W + r.x0;
      const T* g = dout + (p * r.h + y) * r.w;
      for (int64_t x = 0; x < r.w; ++x) d[x] += g[x];
    }
}

template <class T>
Tensor<T> crop2d(const Tensor<T>& x, const Rect& r) {
  if (x.dim() != 4 || r.x0 < 0 || r.y0 < 0 || r.w <= 0 || r.h <= 0 || r.x0 + r.w > x.size(3) || r.y0 + r.h > x.size(2))
    throw std::invalid_argument("crop2d: rectangle (" + std::to_string(r.x0) + "," + std::to_string(r.y0) + ") " +
                                std::to_string(r.w) + "x" + std::to_string(r.h) + " does not fit in " +
                                x.shape().str());
  Tensor<T> out({x.size(0), x.size(1), r.h, r.w});
  crop2d_forward(out.data(), x.data(), x.size(0) * x.size(1), x.size(2), x.size(3), r);
  return out;
}

template <class T>
Var<T> crop2d(const Var<T>& x, const Rect& r) {
  if (r.x0 == 0 && r.y0 == 0 && x.shape().dim() == 4 && r.w == x.size(3) && r.h == x.size(2)) return x;
  Tensor<T> out = crop2d(x.value(), r);
  const int64_t NC = x.size(0) * x.size(1), H = x.size(2), W = x.size(3);
  return make_result<T>(std::move(out), {x}, "crop2d", [NC, H, W, r](Node<T>& n) {
    crop2d_backward(n.parents[0]->grad_buffer().data(), n.grad.data(), NC, H, W, r);
  });
}

}  // namespace nns::gi
