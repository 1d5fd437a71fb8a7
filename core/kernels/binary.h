#pragma once
// add / sub / mul / div with broadcasting, as kernel pairs.
//   a (plan.numel_a), b (plan.numel_b), out and dout (plan.numel), laid out per `plan`.
// Backward accumulates into da / db (either may be null); where an operand was
// broadcast its gradient is the sum over the repeated positions, done serially in a
// fixed order so it is deterministic.
#include <cstdint>

#include "core/kernels/broadcast.h"
#include "core/kernels/map.h"

namespace nns {

// out = f(a, b) elementwise over the broadcast shape.
template <class T, class F>
void binary_map(T* out, const T* a, const T* b, const BroadcastPlan& p, F f) {
  const int64_t inner = p.inner(), rows = p.rows();
  const int64_t sa = p.inner_stride_a(), sb = p.inner_stride_b();
  auto run_row = [&](T* o, const T* pa, const T* pb, int64_t len) {
    if (sa && sb) {
      for (int64_t k = 0; k < len; ++k) o[k] = f(pa[k], pb[k]);
    } else if (sa) {
      const T vb = *pb;
      for (int64_t k = 0; k < len; ++k) o[k] = f(pa[k], vb);
    } else if (sb) {
      const T va = *pa;
      for (int64_t k = 0; k < len; ++k) o[k] = f(va, pb[k]);
    } else {
      const T v = f(*pa, *pb);
      for (int64_t k = 0; k < len; ++k) o[k] = v;
    }
  };
  if (rows == 1) {  // one long run: split it
    parallel_for(
        inner, [&](int64_t k0, int64_t k1) { run_row(out + k0, a + k0 * sa, b + k0 * sb, k1 - k0); }, kElementwiseGrain,
        16);
    return;
  }
  parallel_for(
      rows,
      [&](int64_t r0, int64_t r1) {
        for (int64_t r = r0; r < r1; ++r) {
          int64_t oa, ob;
          p.row_offsets(r, oa, ob);
          run_row(out + r * inner, a + oa, b + ob, inner);
        }
      },
      inner >= kElementwiseGrain ? 1 : kElementwiseGrain / inner);
}

// d_dst += sum over broadcast positions of h(dout, a, b); dst is operand a or b.
template <class T, class H>
void binary_reduce_into(T* dst, bool dst_is_a, const T* dout, const T* a, const T* b, const BroadcastPlan& p, H h) {
  const int64_t inner = p.inner(), rows = p.rows();
  const int64_t sa = p.inner_stride_a(), sb = p.inner_stride_b();
  const int64_t sd = dst_is_a ? sa : sb;
  const bool dst_full = (dst_is_a ? p.numel_a : p.numel_b) == p.numel;
  auto run_row = [&](int64_t r, int64_t k0, int64_t k1) {
    int64_t oa, ob;
    p.row_offsets(r, oa, ob);
    const T* g = dout + r * inner;
    T* d = dst + (dst_is_a ? oa : ob);
    if (sd) {
      for (int64_t k = k0; k < k1; ++k) d[k] += h(g[k], a[oa + k * sa], b[ob + k * sb]);
    } else {
      double acc = 0;  // a long broadcast sum: accumulate in double
      for (int64_t k = k0; k < k1; ++k) acc += double(h(g[k], a[oa + k * sa], b[ob + k * sb]));
      *d += T(acc);
    }
  };
  if (!dst_full) {  // rows may share destinations: keep one fixed order
    for (int64_t r = 0; r < rows; ++r) run_row(r, 0, inner);
    return;
  }
  if (rows == 1) {
    parallel_for(
        inner, [&](int64_t k0, int64_t k1) { run_row(0, k0, k1); }, kElementwiseGrain, 16);
    return;
  }
  parallel_for(
      rows,
      [&](int64_t r0, int64_t r1) {
        for (int64_t r = r0; r < r1; ++r) run_row(r, 0, inner);
      },
      inner >= kElementwiseGrain ? 1 : kElementwiseGrain / inner);
}

template <class T>
void add_forward(T* out, const T* a, const T* b, const BroadcastPlan& p) {
  binary_map(out, a, b, p, [](T x, T y) { return x + y; });
}
template <class T>
void add_backward(T* da, T* db, const T* dout, const T* a, const T* b, const BroadcastPlan& p) {
  if (da) binary_reduce_into(da, true, dout, a, b, p, [](T g, T, T) { return g; });
  if (db) binary_reduce_into(db, false, dout, a, b, p, [](T g, T, T) { return g; });
}

template <class T>
void sub_forward(T* out, const T* a, const T* b, const BroadcastPlan& p) {
  binary_map(out, a, b, p, [](T x, T y) { return x - y; });
}
template <class T>
void sub_backward(T* da, T* db, const T* dout, const T* a, const T* b, const BroadcastPlan& p) {
  if (da) binary_reduce_into(da, true, dout, a, b, p, [](T g, T, T) { return g; });
  if (db) binary_reduce_into(db, false, dout, a, b, p, [](T g, T, T) { return -g; });
}

template <class T>
void mul_forward(T* out, const T* a, const T* b, const BroadcastPlan& p) {
  binary_map(out, a, b, p, [](T x, T y) { return x * y; });
}
template <class T>
void mul_backward(T* da, T* db, const T* dout, const T* a, const T* b, const BroadcastPlan& p) {
  if (da) binary_reduce_into(da, true, dout, a, b, p, [](T g, T, T y) { return g * y; });
  if (db) binary_reduce_into(db, false, dout, a, b, p, [](T g, T x, T) { return g * x; });
}

template <class T>
void div_forward(T* out, const T* a, const T* b, const BroadcastPlan& p) {
  binary_map(out, a, b, p, [](T x, T y) { return x / y; });
}
template <class T>
void div_backward(T* da, T* db, const T* dout, const T* a, const T* b, const BroadcastPlan& p) {
  if (da) binary_reduce_into(da, true, dout, a, b, p, [](T g, T, T y) { return g / y; });
  if (db) binary_reduce_into(db, false, dout, a, b, p, [](T g, T x, T y) { return -g * x / (y * y); });
}

}  // namespace nns
