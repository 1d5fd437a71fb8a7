#pragma once
// How a convolution pass spreads its independent units of work (blocks of output rows of
// one image) over the pool's threads.
#include <cstdint>

#include "core/kernels/conv_geometry.h"
#include "core/tensor.h"
#include "core/thread_pool.h"

namespace nns {

// Runs f(i, scratch) for units i in [0, n), scratch being `scratch_elems` elements of T
// owned by the calling thread. When there are enough units for every thread, each thread
// takes whole units (one pool round-trip per call; the GEMMs inside run single-threaded,
// see core/thread_pool.h); otherwise the units run in order and split their own work.
// f must give the same result either way: units must not add into the same memory.
template <class T, class F>
void for_each_unit(const ConvGeometry& g, int64_t n, int64_t scratch_elems, F&& f) {
  // Below this many multiply-adds a pool round-trip costs more than a second thread saves.
  constexpr double kParallelMinMacs = double(1 << 18);
  const int nt = num_threads();
  if (nt > 1 && g.macs() >= kParallelMinMacs && (n % nt == 0 || n >= 4 * nt)) {
    parallel_for(n, [&](int64_t i0, int64_t i1) {
      Tensor<T> scratch({scratch_elems});
      for (int64_t i = i0; i < i1; ++i) f(i, scratch.data());
    });
    return;
  }
  Tensor<T> scratch({scratch_elems});
  for (int64_t i = 0; i < n; ++i) f(i, scratch.data());
}

}  // namespace nns
