#pragma once
// The one SSIM (Wang et al. 2004), with the reference constants: an 11x11 Gaussian window (sigma 1.5), C1 = (0.01 L)^2
// and C2 = (0.03 L)^2 for data range L = 1 (values in [0, 1]). Like Wang's reference code the window only visits
// positions where it fits ('valid'), so each plane yields an (H-10) x (W-10) SSIM map; the result is the mean over all
// maps. That is the loss's policy (DSSIM, differentiable, ssim_forward/ssim_backward); evaluation uses the same window
// and formula with a renormalised border (ssim_map_renormalised below).
//   x, y, dx, dy (P, H, W), P = N*C planes, H, W >= 11.
// Statistics per window: mx, my (means), sxx, syy, sxy (biased (co)variances, as
// E[xx] - mx^2 etc.), and
//   SSIM = (2 mx my + C1)(2 sxy + C2) / ((mx^2 + my^2 + C1)(sxx + syy + C2)).
// Every filtered map is a linear function of x, y, x*x, y*y, x*y, so the backward pass
// is the transposed (scatter) filter of the per-window partial derivatives.
// Planes run in parallel; per-plane sums combine in plane order (deterministic).
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/thread_pool.h"

namespace nns {

inline constexpr int kSsimWindow = 11;
inline constexpr double kSsimSigma = 1.5, kSsimC1 = 0.01 * 0.01, kSsimC2 = 0.03 * 0.03;

namespace detail {
inline const double* ssim_gauss() {
  static const std::vector<double> g = [] {
    std::vector<double> w(kSsimWindow);
    double s = 0;
    for (int k = 0; k < kSsimWindow; ++k) {
      const double d = k - kSsimWindow / 2;
      s += w[size_t(k)] = std::exp(-d * d / (2 * kSsimSigma * kSsimSigma));
    }
    for (auto& v : w) v /= s;
    return w;
  }();
  return g.data();
}

// The five window statistics of one plane, each (Ho, Wo).
struct SsimMaps {
  int64_t H, W, Ho, Wo;
  std::vector<double> mx, my, exx, eyy, exy;
  SsimMaps(int64_t h, int64_t w)
      : H(h),
        W(w),
        Ho(h - kSsimWindow + 1),
        Wo(w - kSsimWindow + 1),
        mx(size_t(Ho * Wo)),
        my(mx.size()),
        exx(mx.size()),
        eyy(mx.size()),
        exy(mx.size()) {}

  template <class T>
  void compute(const T* x, const T* y) {
    const double* g = ssim_gauss();
    // Horizontal pass into (H, Wo) rows of the five quantities, then vertical.
    std::vector<double> h(size_t(5 * H * Wo));
    double* hq[5];
    for (int q = 0; q < 5; ++q) hq[q] = h.data() + q * H * Wo;
    for (int64_t i = 0; i < H; ++i)
      for (int64_t j = 0; j < Wo; ++j) {
        double s[5] = {0, 0, 0, 0, 0};
        for (int k = 0; k < kSsimWindow; ++k) {
          const double a = double(x[i * W + j + k]), b = double(y[i * W + j + k]);
          s[0] += g[k] * a;
          s[1] += g[k] * b;
          s[2] += g[k] * a * a;
          s[3] += g[k] * b * b;
          s[4] += g[k] * a * b;
        }
        for (int q = 0; q < 5; ++q) hq[q][i * Wo + j] = s[q];
      }
    double* out[5] = {mx.data(), my.data(), exx.data(), eyy.data(), exy.data()};
    for (int q = 0; q < 5; ++q)
      for (int64_t i = 0; i < Ho; ++i)
        for (int64_t j = 0; j < Wo; ++j) {
          double s = 0;
          for (int k = 0; k < kSsimWindow; ++k) s += g[k] * hq[q][(i + k) * Wo + j];
          out[q][i * Wo + j] = s;
        }
  }
};

// gin (H, W) += transpose of the valid filter applied to gout (Ho, Wo).
inline void ssim_filter_transpose(double* gin, const double* gout, int64_t H, int64_t W, int64_t Ho, int64_t Wo) {
  const double* g = ssim_gauss();
  std::vector<double> t(size_t(H * Wo), 0.0);
  for (int64_t i = 0; i < Ho; ++i)
    for (int k = 0; k < kSsimWindow; ++k)
      for (int64_t j = 0; j < Wo; ++j) t[size_t((i + k) * Wo + j)] += g[k] * gout[i * Wo + j];
  for (int64_t i = 0; i < H; ++i)
    for (int64_t j = 0; j < Wo; ++j)
      for (int k = 0; k < kSsimWindow; ++k) gin[i * W + j + k] += g[k] * t[size_t(i * Wo + j)];
}
}  // namespace detail

// SSIM from the five windowed moments (biased (co)variances as E[xx] - mx^2): the one
// formula of both edge policies.
inline double ssim_from_moments(double mx, double my, double exx, double eyy, double exy) {
  const double sxx = exx - mx * mx, syy = eyy - my * my, sxy = exy - mx * my;
  return (2 * mx * my + kSsimC1) * (2 * sxy + kSsimC2) / ((mx * mx + my * my + kSsimC1) * (sxx + syy + kSsimC2));
}

// The evaluation policy: a per-pixel SSIM map (H, W) for one plane, the window truncated
// at the border and renormalised over the pixels that exist, so every pixel of an
// image (and of a mask over it: sky excluded from AO scores) has a value. Same window,
// sigma and constants as the loss above, which instead keeps Wang's 'valid' positions.
template <class T>
std::vector<float> ssim_map_renormalised(const T* x, const T* y, int64_t H, int64_t W) {
  const double* g = detail::ssim_gauss();
  const int R = kSsimWindow / 2;
  const int64_t n = H * W;
  // Five moments, blurred separably: horizontal pass into tmp, vertical into out.
  std::vector<double> src(size_t(n) * 5), tmp(size_t(n) * 5), out(size_t(n) * 5);
  for (int64_t i = 0; i < n; ++i) {
    const double a = double(x[i]), b = double(y[i]);
    double* q = &src[size_t(i) * 5];
    q[0] = a, q[1] = b, q[2] = a * a, q[3] = b * b, q[4] = a * b;
  }
  auto blur = [&](const std::vector<double>& in, std::vector<double>& o, bool horizontal) {
    for (int64_t yy = 0; yy < H; ++yy)
      for (int64_t xx = 0; xx < W; ++xx) {
        double acc[5] = {0, 0, 0, 0, 0}, wsum = 0;
        for (int k = -R; k <= R; ++k) {
          const int64_t sx = horizontal ? xx + k : xx, sy = horizontal ? yy : yy + k;
          if (sx < 0 || sy < 0 || sx >= W || sy >= H) continue;
          const double* p = &in[size_t(sy * W + sx) * 5];
          for (int c = 0; c < 5; ++c) acc[c] += g[k + R] * p[c];
          wsum += g[k + R];
        }
        double* q = &o[size_t(yy * W + xx) * 5];
        for (int c = 0; c < 5; ++c) q[c] = acc[c] / wsum;
      }
  };
  blur(src, tmp, true);
  blur(tmp, out, false);
  std::vector<float> map(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) {
    const double* m = &out[size_t(i) * 5];
    map[size_t(i)] = float(ssim_from_moments(m[0], m[1], m[2], m[3], m[4]));
  }
  return map;
}

// Mean SSIM over all planes and window positions.
template <class T>
double ssim_forward(const T* x, const T* y, int64_t P, int64_t H, int64_t W) {
  std::vector<double> plane_sum(size_t(P), 0.0);
  parallel_for(P, [&](int64_t p0, int64_t p1) {
    for (int64_t p = p0; p < p1; ++p) {
      detail::SsimMaps m(H, W);
      m.compute(x + p * H * W, y + p * H * W);
      double s = 0;
      for (size_t i = 0; i < m.mx.size(); ++i) {
        s += ssim_from_moments(m.mx[i], m.my[i], m.exx[i], m.eyy[i], m.exy[i]);
      }
      plane_sum[size_t(p)] = s;
    }
  });
  double s = 0;
  for (double v : plane_sum) s += v;
  return s / double(P * (H - kSsimWindow + 1) * (W - kSsimWindow + 1));
}

// dx += g * d(mean SSIM)/dx, dy likewise (either may be null).
template <class T>
void ssim_backward(T* dx, T* dy, double g, const T* x, const T* y, int64_t P, int64_t H, int64_t W) {
  const int64_t Ho = H - kSsimWindow + 1, Wo = W - kSsimWindow + 1;
  const double w = g / double(P * Ho * Wo);
  parallel_for(P, [&](int64_t p0, int64_t p1) {
    for (int64_t p = p0; p < p1; ++p) {
      const T* xp = x + p * H * W;
      const T* yp = y + p * H * W;
      detail::SsimMaps m(H, W);
      m.compute(xp, yp);
      // Partial derivatives of each window's SSIM w.r.t. mx, my, E[xx], E[yy], E[xy].
      const size_t n = m.mx.size();
      std::vector<double> gmx(n), gmy(n), gxx(n), gyy(n), gxy(n);
      for (size_t i = 0; i < n; ++i) {
        const double mx = m.mx[i], my = m.my[i];
        const double sxx = m.exx[i] - mx * mx, syy = m.eyy[i] - my * my, sxy = m.exy[i] - mx * my;
        const double A1 = 2 * mx * my + kSsimC1, A2 = 2 * sxy + kSsimC2;
        const double B1 = mx * mx + my * my + kSsimC1, B2 = sxx + syy + kSsimC2;
        const double S = A1 * A2 / (B1 * B2);
        gmx[i] = w * S * (2 * my / A1 - 2 * my / A2 - 2 * mx / B1 + 2 * mx / B2);
        gmy[i] = w * S * (2 * mx / A1 - 2 * mx / A2 - 2 * my / B1 + 2 * my / B2);
        gxx[i] = gyy[i] = -w * S / B2;
        gxy[i] = w * 2 * S / A2;
      }
      std::vector<double> bmx(size_t(H * W), 0.0), bmy(bmx.size(), 0.0), bxx(bmx.size(), 0.0), byy(bmx.size(), 0.0),
          bxy(bmx.size(), 0.0);
      if (dx) {
        detail::ssim_filter_transpose(bmx.data(), gmx.data(), H, W, Ho, Wo);
        detail::ssim_filter_transpose(bxx.data(), gxx.data(), H, W, Ho, Wo);
      }
      if (dy) {
        detail::ssim_filter_transpose(bmy.data(), gmy.data(), H, W, Ho, Wo);
        detail::ssim_filter_transpose(byy.data(), gyy.data(), H, W, Ho, Wo);
      }
      detail::ssim_filter_transpose(bxy.data(), gxy.data(), H, W, Ho, Wo);
      for (int64_t i = 0; i < H * W; ++i) {
        const double a = double(xp[i]), b = double(yp[i]);
        if (dx) dx[p * H * W + i] += T(bmx[size_t(i)] + 2 * a * bxx[size_t(i)] + b * bxy[size_t(i)]);
        if (dy) dy[p * H * W + i] += T(bmy[size_t(i)] + 2 * b * byy[size_t(i)] + a * bxy[size_t(i)]);
      }
    }
  });
}

}  // namespace nns
