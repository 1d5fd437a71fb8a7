#pragma once
// Broadcasting plan for binary elementwise ops (numpy/PyTorch rules: shapes align at
// the right; a dimension of size 1, or a missing one, is repeated to match).
//
// Why a plan: walking an N-d index per element is slow. Adjacent dimensions in which
// each operand is either fully present or fully broadcast merge into one, so common
// cases collapse to at most a few dims: same shape -> 1 dim, a per-channel (C,1,1)
// bias on (N,C,H,W) -> 3 dims [N, C, H*W] with the bias repeated along the last. The
// kernels then run an inner loop along the last merged dim with operand stride 0 or 1.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "core/shape.h"

namespace nns {

struct BroadcastPlan {
  Shape out;   // the broadcast result shape
  int nd = 0;  // merged dims
  int64_t size[Shape::kMaxDims]{};
  int64_t stride_a[Shape::kMaxDims]{};  // 0 where a is broadcast
  int64_t stride_b[Shape::kMaxDims]{};
  int64_t numel = 0, numel_a = 0, numel_b = 0;

  int64_t inner() const { return nd ? size[nd - 1] : 1; }
  int64_t rows() const { return inner() ? numel / inner() : 0; }
  int64_t inner_stride_a() const { return nd ? stride_a[nd - 1] : 0; }
  int64_t inner_stride_b() const { return nd ? stride_b[nd - 1] : 0; }

  // Offsets of row r (a multi-index over all merged dims but the last) in a and b.
  void row_offsets(int64_t r, int64_t& oa, int64_t& ob) const {
    oa = ob = 0;
    for (int d = nd - 2; d >= 0; --d) {
      int64_t i = r % size[d];
      r /= size[d];
      oa += i * stride_a[d];
      ob += i * stride_b[d];
    }
  }
};

inline BroadcastPlan make_broadcast_plan(const Shape& a, const Shape& b, const char* op) {
  BroadcastPlan p;
  const int n = a.dim() > b.dim() ? a.dim() : b.dim();
  int64_t da[Shape::kMaxDims], db[Shape::kMaxDims];
  for (int i = 0; i < n; ++i) {
    int ia = i - (n - a.dim()), ib = i - (n - b.dim());
    da[i] = ia >= 0 ? a[ia] : 1;
    db[i] = ib >= 0 ? b[ib] : 1;
    if (da[i] != db[i] && da[i] != 1 && db[i] != 1)
      throw std::invalid_argument(std::string(op) + ": shapes " + a.str() + " and " + b.str() + " do not broadcast");
    p.out.push_back(da[i] == 1 ? db[i] : da[i]);
  }
  p.numel = p.out.numel();
  p.numel_a = a.numel();
  p.numel_b = b.numel();
  // Merge dims right to left. Each dim has a kind per operand: present (size > 1 there)
  // or broadcast; size-1 output dims are dropped; equal kinds merge.
  int64_t sa = 1, sb = 1;  // contiguous strides of a and b at the current dim
  int64_t msize[Shape::kMaxDims], msa[Shape::kMaxDims], msb[Shape::kMaxDims];
  bool mpa[Shape::kMaxDims], mpb[Shape::kMaxDims];
  int m = 0;
  for (int i = n - 1; i >= 0; --i) {
    int64_t s = p.out[i];
    if (s == 1) continue;
    bool pa = da[i] != 1, pb = db[i] != 1;
    if (m > 0 && mpa[m - 1] == pa && mpb[m - 1] == pb) {
      msize[m - 1] *= s;
    } else {
      msize[m] = s;
      msa[m] = pa ? sa : 0;
      msb[m] = pb ? sb : 0;
      mpa[m] = pa;
      mpb[m] = pb;
      ++m;
    }
    if (pa) sa *= s;
    if (pb) sb *= s;
  }
  p.nd = m;
  for (int i = 0; i < m; ++i) {  // back to left-to-right order
    p.size[i] = msize[m - 1 - i];
    p.stride_a[i] = msa[m - 1 - i];
    p.stride_b[i] = msb[m - 1 - i];
  }
  return p;
}

}  // namespace nns
