#pragma once
// Concatenation along dim 1 (channels) as a kernel pair.
//   inps[k] (N, channels[k], S), out (N, sum(channels), S), S = product of the dims
//   after dim 1 (H*W for images, 1 for (N, C)).
// Backward accumulates the matching slice of dout into each dinps[k] (null: skip).
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/thread_pool.h"

namespace nns {

template <class T>
void concat_channels_forward(T* out, const std::vector<const T*>& inps, const std::vector<int64_t>& channels, int64_t N,
                             int64_t S) {
  int64_t Ct = 0;
  for (int64_t c : channels) Ct += c;
  parallel_for(
      N,
      [&](int64_t n0, int64_t n1) {
        for (int64_t n = n0; n < n1; ++n) {
          T* o = out + n * Ct * S;
          for (size_t k = 0; k < inps.size(); ++k) {
            const int64_t len = channels[k] * S;
            if (len) std::memcpy(o, inps[k] + n * len, sizeof(T) * size_t(len));
            o += len;
          }
        }
      },
      Ct * S >= (1 << 15) ? 1 : (1 << 15) / (Ct * S + 1));
}

template <class T>
void concat_channels_backward(const std::vector<T*>& dinps, const T* dout, const std::vector<int64_t>& channels,
                              int64_t N, int64_t S) {
  int64_t Ct = 0;
  for (int64_t c : channels) Ct += c;
  parallel_for(
      N,
      [&](int64_t n0, int64_t n1) {
        for (int64_t n = n0; n < n1; ++n) {
          const T* g = dout + n * Ct * S;
          for (size_t k = 0; k < dinps.size(); ++k) {
            const int64_t len = channels[k] * S;
            if (T* d = dinps[k]) {
              d += n * len;
              for (int64_t i = 0; i < len; ++i) d[i] += g[i];
            }
            g += len;
          }
        }
      },
      Ct * S >= (1 << 15) ? 1 : (1 << 15) / (Ct * S + 1));
}

}  // namespace nns
