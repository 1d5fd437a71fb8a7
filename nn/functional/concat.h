#pragma once
// concat_channels({a, b, ...}): concatenation along dim 1, e.g. a U-Net skip connection
// joining (N, C1, H, W) and (N, C2, H, W) into (N, C1 + C2, H, W). All other dims must
// match; works for any rank >= 2.
#include <stdexcept>
#include <vector>

#include "core/autograd.h"
#include "core/kernels/concat.h"

namespace nns {

template <class T>
Var<T> concat_channels(const std::vector<Var<T>>& xs) {
  if (xs.empty()) throw std::invalid_argument("concat_channels: no inputs");
  const Shape& s0 = xs[0].shape();
  if (s0.dim() < 2) throw std::invalid_argument("concat_channels: inputs need >= 2 dims, got " + s0.str());
  std::vector<int64_t> channels;
  std::vector<const T*> ptrs;
  int64_t Ct = 0;
  for (const auto& x : xs) {
    const Shape& s = x.shape();
    bool ok = s.dim() == s0.dim() && s[0] == s0[0];
    for (int d = 2; ok && d < s.dim(); ++d) ok = s[d] == s0[d];
    if (!ok)
      throw std::invalid_argument("concat_channels: shape " + s.str() + " does not match " + s0.str() +
                                  " outside dim 1");
    channels.push_back(s[1]);
    ptrs.push_back(x.value().data());
    Ct += s[1];
  }
  const int64_t N = s0[0];
  int64_t S = 1;
  for (int d = 2; d < s0.dim(); ++d) S *= s0[d];
  Shape out_shape = s0;
  out_shape[1] = Ct;
  Tensor<T> out(out_shape);
  concat_channels_forward(out.data(), ptrs, channels, N, S);
  return make_result<T>(std::move(out), xs, "concat_channels", [channels, N, S](Node<T>& n) {
    std::vector<T*> d(channels.size(), nullptr);
    for (size_t k = 0; k < channels.size(); ++k)
      if (wants_grad(n, k)) d[k] = n.parents[k]->grad_buffer().data();
    concat_channels_backward(d, n.grad.data(), channels, N, S);
  });
}

}  // namespace nns
