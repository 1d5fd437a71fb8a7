#pragma once
// ꟻLIP, the LDR version: Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild,
// "FLIP: A Difference Evaluator for Alternating Images", HPG 2020 (PACMCGIT 3(2), 15).
// A per-pixel map in [0, 1] of how different two images look when one flips between them,
// for an observer who sees `ppd` pixels per degree of visual angle; its mean (over the
// selected pixels) is the number reported, lower is better. Written from the paper; the
// constants were checked against the authors' reference code (NVlabs/flip, python/flip_api.py).
//
//   colour pipeline (paper §4)  linear RGB -> YyCxCz (opponent, linear in XYZ); each channel
//                               filtered by its contrast sensitivity function (a sum of
//                               Gaussians, Table 1); back to linear RGB, clamped to [0,1];
//                               CIELAB, Hunt-adjusted; HyAB distance ^ qc, remapped to [0,1]
//                               with cmax, pc, pt                            -> deltaE_c
//   feature pipeline (paper §5) edges and points of the achromatic channel: first and
//                               second derivatives of a Gaussian of peak-to-trough w = 0.082°;
//                               the larger difference of their magnitudes, (./√2)^qf -> deltaE_f
//   final (paper §6)            deltaE = deltaE_c ^ (1 - deltaE_f)
//
// Images are planar RGB (3, h, w), row 0 at the top. flip_map takes linear RGB in [0, 1]
// (the display's light before its transfer curve); flip_map_srgb takes sRGB-encoded values
// and decodes them first, as the paper's pipeline starts. Borders replicate the edge pixel
// (as the reference code). Every filter is separable and run as two 1-D passes; no
// threads, so the map is the same whatever the thread count.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "report/image_metrics.h"

namespace nns::report {

// Pixels per degree for a monitor `width_m` wide with `resolution` pixels across, seen from
// `distance_m` (paper §4.1): p = d * (r / w) * pi / 180.
inline double flip_pixels_per_degree(double distance_m, double width_m, double resolution) {
  return distance_m * (resolution / width_m) * 3.14159265358979323846 / 180.0;
}
// The paper's default observer: a 0.7 m wide 3840-pixel (4K) monitor seen from 0.7 m, 67.02 ppd.
inline const double kFlipDefaultPpd = flip_pixels_per_degree(0.7, 0.7, 3840);

namespace flip {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr float kQc = 0.7f;                 // colour exponent qc on the HyAB distance (paper §4.3)
inline constexpr float kPc = 0.4f;                 // remap knee: errors below pc * cmax map linearly to [0, pt] (§4.3)
inline constexpr float kPt = 0.95f;                // ... and the rest to (pt, 1]
inline constexpr float kQf = 0.5f;                 // feature exponent qf (§5)
inline constexpr double kFeatureWidthDeg = 0.082;  // w: peak-to-trough of the edge detector, 2 sd (§5)

// Contrast sensitivity function of one opponent channel (§4.1, Table 1), in the spatial
// domain: S(x) = a1 sqrt(pi/b1) exp(-pi^2 x^2 / b1) + a2 sqrt(pi/b2) exp(-pi^2 x^2 / b2),
// x in degrees. The achromatic and red-green channels have a2 = 0.
struct CsfConstants {
  double a1, b1, a2, b2;
};
inline constexpr CsfConstants kCsfAchromatic{1.0, 0.0047, 0.0, 0.0};
inline constexpr CsfConstants kCsfRedGreen{1.0, 0.0053, 0.0, 0.0};
inline constexpr CsfConstants kCsfBlueYellow{34.1, 0.04, 13.5, 0.025};
// Every channel's kernel has the radius of the widest Gaussian (b = 0.04): 3 standard
// deviations, sd = sqrt(b / (2 pi^2)) degrees.
inline constexpr double kCsfWidestB = 0.04;

// linear sRGB (D65) -> XYZ, the exact rational form of the IEC 61966-2-1 matrix (the
// reference code's). Its rows sum to the D65 white, so the middle row sums to 1 exactly.
inline constexpr double kRgbToXyz[3][3] = {{10135552.0 / 24577794, 8788810.0 / 24577794, 4435075.0 / 24577794},
                                           {2613072.0 / 12288897, 8788810.0 / 12288897, 887015.0 / 12288897},
                                           {1425312.0 / 73733382, 8788810.0 / 73733382, 70074185.0 / 73733382}};

inline std::array<double, 3> d65_white() {
  std::array<double, 3> w{};
  for (int r = 0; r < 3; ++r) w[size_t(r)] = kRgbToXyz[r][0] + kRgbToXyz[r][1] + kRgbToXyz[r][2];
  return w;
}

// The inverse of kRgbToXyz (cofactors over the determinant), computed rather than typed.
inline std::array<std::array<double, 3>, 3> xyz_to_rgb() {
  const auto& m = kRgbToXyz;
  std::array<std::array<double, 3>, 3> inv{};
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
      inv[size_t(r)][size_t(c)] = (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det;
    }
  return inv;
}

inline float srgb_to_linear(float s) { return s > 0.04045f ? std::pow((s + 0.055f) / 1.055f, 2.4f) : s / 12.92f; }

// CIELAB from XYZ normalised by the white: the cube root with its linear toe below (6/29)^3.
inline float lab_f(float t) {
  constexpr float d = 6.0f / 29.0f;
  return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0f / 29.0f;
}

// Hunt-adjusted CIELAB (§4.2: a* and b* scaled by 0.01 L*, as chroma is seen less at low
// luminance) of a linear RGB colour.
inline std::array<float, 3> hunt_lab(const std::array<double, 3>& rgb) {
  static const std::array<double, 3> white = d65_white();
  double xyz[3];
  for (int r = 0; r < 3; ++r)
    xyz[r] = (kRgbToXyz[r][0] * rgb[0] + kRgbToXyz[r][1] * rgb[1] + kRgbToXyz[r][2] * rgb[2]) / white[size_t(r)];
  const float fx = lab_f(float(xyz[0])), fy = lab_f(float(xyz[1])), fz = lab_f(float(xyz[2]));
  const float L = 116 * fy - 16;
  return {L, 0.01f * L * 500 * (fx - fy), 0.01f * L * 200 * (fy - fz)};
}

// HyAB (§4.3): city-block in lightness plus Euclidean in the chroma plane.
inline float hyab(const std::array<float, 3>& p, const std::array<float, 3>& q) {
  return std::abs(p[0] - q[0]) + std::hypot(p[1] - q[1], p[2] - q[2]);
}

// cmax (§4.3): the largest colour difference, that of green against blue, raised to qc.
inline float cmax() {
  static const float c = std::pow(hyab(hunt_lab({0, 1, 0}), hunt_lab({0, 0, 1})), kQc);
  return c;
}

// HyAB^qc remapped to [0, 1] (§4.3): [0, pc cmax) -> [0, pt) linearly, [pc cmax, cmax] -> [pt, 1].
inline float remap_colour_error(float e) {
  const float knee = kPc * cmax();
  return e < knee ? kPt / knee * e : kPt + (e - knee) / (cmax() - knee) * (1 - kPt);
}

// One separable term of a 2-D kernel: weight * taps(x) * taps(y), taps indexed -r..r.
struct SeparableTerm {
  double weight = 1;
  std::vector<double> taps;  // 2r + 1
};

// A channel's CSF as separable terms whose 2-D weights sum to 1 (the reference code
// normalises the sampled kernel; each Gaussian of S is separable in x and y).
inline std::vector<SeparableTerm> csf_kernel(const CsfConstants& k, double ppd) {
  const int r = int(std::ceil(3 * std::sqrt(kCsfWidestB / (2 * kPi * kPi)) * ppd));
  std::vector<SeparableTerm> terms;
  double total = 0;
  for (auto [a, b] : {std::pair{k.a1, k.b1}, std::pair{k.a2, k.b2}}) {
    if (a == 0) continue;
    SeparableTerm t;
    t.taps.resize(size_t(2 * r + 1));
    double sum = 0;
    for (int x = -r; x <= r; ++x) {
      const double deg = x / ppd;
      sum += t.taps[size_t(x + r)] = std::exp(-kPi * kPi * deg * deg / b);
    }
    t.weight = a * std::sqrt(kPi / b);
    total += t.weight * sum * sum;
    terms.push_back(std::move(t));
  }
  for (auto& t : terms) t.weight /= total;
  return terms;
}

// The feature detectors of §5 as separable pairs: derivative(x) * gaussian(y) and its
// transpose. sd = w/2 * ppd pixels, radius 3 sd. The edge detector is the first
// derivative of the Gaussian, the point detector the second, (x^2/sd^2 - 1) g(x); each is
// normalised so its positive weights sum to 1 and its negative weights to -1 (the
// Gaussian across sums to 1, which keeps that true of the 2-D kernel).
struct FeatureKernels {
  std::vector<double> gaussian, edge, point;  // 2r + 1 taps each
};

inline FeatureKernels feature_kernels(double ppd) {
  const double sd = 0.5 * kFeatureWidthDeg * ppd;
  const int r = int(std::ceil(3 * sd));
  FeatureKernels k;
  double gsum = 0;
  for (int x = -r; x <= r; ++x) {
    const double g = std::exp(-double(x) * x / (2 * sd * sd));
    k.gaussian.push_back(g), k.edge.push_back(-x * g), k.point.push_back((double(x) * x / (sd * sd) - 1) * g);
    gsum += g;
  }
  for (double& g : k.gaussian) g /= gsum;
  for (auto* taps : {&k.edge, &k.point}) {
    double pos = 0, neg = 0;
    for (double t : *taps) (t > 0 ? pos : neg) += t;
    for (double& t : *taps) t = t > 0 ? t / pos : t / -neg;
  }
  return k;
}

inline int clamp_index(int i, int n) { return i < 0 ? 0 : (i >= n ? n - 1 : i); }

// out = correlation of `in` (h x w) with taps_x along rows then taps_y along columns,
// borders replicated.
inline std::vector<float> filter_separable(const std::vector<float>& in, int w, int h,
                                           const std::vector<double>& taps_x, const std::vector<double>& taps_y) {
  const int rx = int(taps_x.size() / 2), ry = int(taps_y.size() / 2);
  std::vector<float> tmp(in.size()), out(in.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int k = -rx; k <= rx; ++k)
        s += taps_x[size_t(k + rx)] * in[size_t(y) * size_t(w) + size_t(clamp_index(x + k, w))];
      tmp[size_t(y) * size_t(w) + size_t(x)] = float(s);
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int k = -ry; k <= ry; ++k)
        s += taps_y[size_t(k + ry)] * tmp[size_t(clamp_index(y + k, h)) * size_t(w) + size_t(x)];
      out[size_t(y) * size_t(w) + size_t(x)] = float(s);
    }
  return out;
}

inline std::vector<float> filter_csf(const std::vector<float>& in, int w, int h,
                                     const std::vector<SeparableTerm>& csf) {
  std::vector<float> out(in.size(), 0.0f);
  for (const SeparableTerm& t : csf) {
    const std::vector<float> f = filter_separable(in, w, h, t.taps, t.taps);
    for (size_t i = 0; i < out.size(); ++i) out[i] += float(t.weight) * f[i];
  }
  return out;
}

// What the metric needs of one image: its Hunt-adjusted L*a*b* after the CSFs (3 planes)
// and the magnitudes of its edge and point responses (2 planes).
struct Prepared {
  std::vector<float> lab;            // 3 * n
  std::vector<float> edges, points;  // n each
};

inline Prepared prepare(const float* rgb, int w, int h, double ppd) {
  const size_t n = size_t(w) * size_t(h);
  static const std::array<double, 3> white = d65_white();
  static const auto inverse = xyz_to_rgb();
  // YyCxCz (§4.1): the CIELAB formulas without the cube root, so linear in XYZ and the
  // filtering can be undone exactly: Yy = 116 y - 16, Cx = 500 (x - y), Cz = 200 (y - z).
  std::vector<float> yy(n), cx(n), cz(n), luminance(n);
  for (size_t i = 0; i < n; ++i) {
    double xyz[3];
    for (int r = 0; r < 3; ++r) {
      xyz[r] = 0;
      for (int c = 0; c < 3; ++c) xyz[r] += kRgbToXyz[r][c] * double(std::clamp(rgb[size_t(c) * n + i], 0.0f, 1.0f));
      xyz[r] /= white[size_t(r)];
    }
    yy[i] = float(116 * xyz[1] - 16), cx[i] = float(500 * (xyz[0] - xyz[1])), cz[i] = float(200 * (xyz[1] - xyz[2]));
    // The feature pipeline reads the achromatic channel as (Yy + 16) / 116 (§5, with the
    // paper's erratum: 116, not 100), i.e. the luminance relative to white.
    luminance[i] = float(xyz[1]);
  }
  yy = filter_csf(yy, w, h, csf_kernel(kCsfAchromatic, ppd));
  cx = filter_csf(cx, w, h, csf_kernel(kCsfRedGreen, ppd));
  cz = filter_csf(cz, w, h, csf_kernel(kCsfBlueYellow, ppd));
  Prepared p;
  p.lab.resize(3 * n);
  for (size_t i = 0; i < n; ++i) {
    const double y = (double(yy[i]) + 16) / 116;
    const double xyz[3] = {(y + double(cx[i]) / 500) * white[0], y * white[1], (y - double(cz[i]) / 200) * white[2]};
    std::array<double, 3> lin{};
    for (int r = 0; r < 3; ++r)
      lin[size_t(r)] = std::clamp(
          inverse[size_t(r)][0] * xyz[0] + inverse[size_t(r)][1] * xyz[1] + inverse[size_t(r)][2] * xyz[2], 0.0, 1.0);
    const std::array<float, 3> lab = hunt_lab(lin);
    for (size_t c = 0; c < 3; ++c) p.lab[c * n + i] = lab[c];
  }
  const FeatureKernels k = feature_kernels(ppd);
  const auto ex = filter_separable(luminance, w, h, k.edge, k.gaussian);
  const auto ey = filter_separable(luminance, w, h, k.gaussian, k.edge);
  const auto px = filter_separable(luminance, w, h, k.point, k.gaussian);
  const auto py = filter_separable(luminance, w, h, k.gaussian, k.point);
  p.edges.resize(n), p.points.resize(n);
  for (size_t i = 0; i < n; ++i) p.edges[i] = std::hypot(ex[i], ey[i]), p.points[i] = std::hypot(px[i], py[i]);
  return p;
}

}  // namespace flip

// The per-pixel ꟻLIP map (h * w, values in [0, 1]) of `test` against `reference`, both
// planar linear RGB (3, h, w) in [0, 1] (values outside are clamped).
inline std::vector<float> flip_map(const float* reference, const float* test, int w, int h,
                                   double ppd = kFlipDefaultPpd) {
  const size_t n = size_t(w) * size_t(h);
  const flip::Prepared r = flip::prepare(reference, w, h, ppd), t = flip::prepare(test, w, h, ppd);
  std::vector<float> out(n);
  for (size_t i = 0; i < n; ++i) {
    const float hy = flip::hyab({r.lab[i], r.lab[n + i], r.lab[2 * n + i]}, {t.lab[i], t.lab[n + i], t.lab[2 * n + i]});
    const float colour = flip::remap_colour_error(std::pow(hy, flip::kQc));
    // deltaE_f = (max(|edge_r - edge_t|, |point_r - point_t|) / sqrt 2) ^ qf (§5).
    const float feature_diff = std::max(std::abs(r.edges[i] - t.edges[i]), std::abs(r.points[i] - t.points[i]));
    const float feature = std::pow(feature_diff / std::sqrt(2.0f), flip::kQf);
    out[i] = std::pow(colour, 1 - feature);  // §6
  }
  return out;
}

// The same for sRGB-encoded images in [0, 1] (the paper's input).
inline std::vector<float> flip_map_srgb(const float* reference, const float* test, int w, int h,
                                        double ppd = kFlipDefaultPpd) {
  const size_t n = 3 * size_t(w) * size_t(h);
  std::vector<float> r(n), t(n);
  for (size_t i = 0; i < n; ++i) r[i] = flip::srgb_to_linear(reference[i]), t[i] = flip::srgb_to_linear(test[i]);
  return flip_map(r.data(), t.data(), w, h, ppd);
}

// Mean ꟻLIP over the selected pixels (mask == nullptr: all); NaN when none is selected.
inline double masked_flip(const float* reference, const float* test, const uint8_t* mask, int w, int h,
                          double ppd = kFlipDefaultPpd) {
  const std::vector<float> map = flip_map(reference, test, w, h, ppd);
  return masked_mean(map.data(), mask, int64_t(w) * h);
}

}  // namespace nns::report
