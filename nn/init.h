#pragma once
// Weight initialisers (in place, drawing from an explicit Rng, in element order), with
// PyTorch's definitions:
//   normal_(t, mean, std, rng), uniform_(t, lo, hi, rng)
//   kaiming_normal_(t, rng, a = 0)   std   = gain / sqrt(fan_in),   gain = sqrt(2 / (1 + a^2))
//   kaiming_uniform_(t, rng, a = 0)  bound = gain * sqrt(3 / fan_in)
//   xavier_uniform_(t, rng, gain = 1)  bound = gain * sqrt(6 / (fan_in + fan_out))
//   xavier_normal_(t, rng, gain = 1)   std   = gain * sqrt(2 / (fan_in + fan_out))
// Fans follow torch.nn.init: for a weight of shape (d0, d1, k...) fan_in = d1 * prod(k),
// fan_out = d0 * prod(k): Linear (OUT, IN) -> IN; Conv2d (Cout, Cin/g, kh, kw) ->
// Cin/g*kh*kw. The kaiming functions take an explicit fan_in as a last argument when
// the shape does not tell it.
//
// init_pix2pix(module, rng): pix2pix's init_weights('normal', 0.02), identifying
// parameters by name and shape:
//   "...weight" with >= 2 dims (Linear, Conv2d, ConvTranspose2d) -> N(0, 0.02)
//   "...weight" with 1 dim (BatchNorm's gamma)                    -> N(1, 0.02)
//   "...bias"                                                     -> 0
//   anything else (e.g. PReLU's alpha/beta) is left as constructed.
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/rng.h"
#include "core/tensor.h"
#include "nn/module.h"

namespace nns {

template <class T>
void normal_(Tensor<T>& t, double mean, double std, Rng& rng) {
  for (auto& v : t) v = T(rng.normal(mean, std));
}

template <class T>
void uniform_(Tensor<T>& t, double lo, double hi, Rng& rng) {
  for (auto& v : t) v = T(rng.uniform(lo, hi));
}

inline int64_t receptive_field(const Shape& s) {
  int64_t r = 1;
  for (int d = 2; d < s.dim(); ++d) r *= s[d];
  return r;
}
inline int64_t fan_in(const Shape& s) {
  if (s.dim() < 2) throw std::invalid_argument("fan_in: needs a weight with >= 2 dims, got " + s.str());
  return s[1] * receptive_field(s);
}
inline int64_t fan_out(const Shape& s) {
  if (s.dim() < 2) throw std::invalid_argument("fan_out: needs a weight with >= 2 dims, got " + s.str());
  return s[0] * receptive_field(s);
}

inline double kaiming_gain(double a) { return std::sqrt(2.0 / (1.0 + a * a)); }

template <class T>
void kaiming_normal_(Tensor<T>& t, Rng& rng, double a = 0.0, int64_t fan = 0) {
  const int64_t f = fan > 0 ? fan : fan_in(t.shape());
  normal_(t, 0.0, kaiming_gain(a) / std::sqrt(double(f)), rng);
}

template <class T>
void kaiming_uniform_(Tensor<T>& t, Rng& rng, double a = 0.0, int64_t fan = 0) {
  const int64_t f = fan > 0 ? fan : fan_in(t.shape());
  const double bound = kaiming_gain(a) * std::sqrt(3.0 / double(f));
  uniform_(t, -bound, bound, rng);
}

template <class T>
void xavier_uniform_(Tensor<T>& t, Rng& rng, double gain = 1.0) {
  const double bound = gain * std::sqrt(6.0 / double(fan_in(t.shape()) + fan_out(t.shape())));
  uniform_(t, -bound, bound, rng);
}

template <class T>
void xavier_normal_(Tensor<T>& t, Rng& rng, double gain = 1.0) {
  normal_(t, 0.0, gain * std::sqrt(2.0 / double(fan_in(t.shape()) + fan_out(t.shape()))), rng);
}

namespace detail {
inline bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
}  // namespace detail

template <class T>
void init_pix2pix(Module<T>& m, Rng& rng, double gain = 0.02) {
  for (auto& [name, p] : m.named_parameters()) {
    Tensor<T>& v = p.value();
    if (detail::ends_with(name, "weight")) {
      normal_(v, v.dim() >= 2 ? 0.0 : 1.0, gain, rng);
    } else if (detail::ends_with(name, "bias")) {
      v.zero();
    }
  }
}

}  // namespace nns
