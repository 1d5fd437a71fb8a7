#pragma once
// Sum of all elements, deterministic: fixed chunks (independent of the thread count)
// summed in double, then the chunk sums combined in chunk order.
//   inp (n) -> one value;  backward: dinp (n) += dout * scale.
#include <cstdint>
#include <vector>

#include "core/kernels/map.h"

namespace nns {

inline constexpr int64_t kReduceChunk = 1 << 14;

// sum_i f(i) over [0, n), f returning double: the building block of every loss.
template <class F>
double chunked_sum(int64_t n, F f) {
  const int64_t nchunks = (n + kReduceChunk - 1) / kReduceChunk;
  if (nchunks <= 1) {
    double s = 0;
    for (int64_t i = 0; i < n; ++i) s += f(i);
    return s;
  }
  std::vector<double> partial(size_t(nchunks), 0.0);
  parallel_chunks(n, kReduceChunk, [&](int64_t c, int64_t b, int64_t e) {
    double s = 0;
    for (int64_t i = b; i < e; ++i) s += f(i);
    partial[size_t(c)] = s;
  });
  double s = 0;
  for (double p : partial) s += p;
  return s;
}

template <class T>
void sum_forward(T* out, const T* inp, int64_t n) {
  *out = T(chunked_sum(n, [inp](int64_t i) { return double(inp[i]); }));
}
// Backward of sum (scale 1) and mean (scale 1/n).
template <class T>
void sum_backward(T* dinp, const T* dout, int64_t n, T scale) {
  const T g0 = *dout * scale;
  parallel_for(
      n,
      [=](int64_t b, int64_t e) {
        const T g = g0;  // a local: a captured float could alias dinp and block vectorizing
        T* d = dinp;
        for (int64_t i = b; i < e; ++i) d[i] += g;
      },
      kElementwiseGrain, 16);
}

}  // namespace nns
