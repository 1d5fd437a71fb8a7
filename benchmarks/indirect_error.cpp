// The error of a GI estimator against a converged reference, per scene family: the
// measure behind the renderer's efficiency table (docs/renderer.md, "Throughput").
//   indirect_error [--channel indirect] [--face front] [--block K] REF_A REF_B EST...
//   --face F: a side face instead of front (its AO or env against two renders at the
//   same settings: "ref variance" x 2 is then one render's per-pixel noise variance);
//   --block K: every plane averaged over K x K pixels first (the error per area of a
//   face K times smaller: face 128 with --block 2 against the data of face 64).
// Every argument is a surround dataset of the same frames (render-dataset with the same
// --seed, preset, families and views; REF_A and REF_B at a high --gi-spp with two
// different --noise-seed values, each EST with a noise seed of its own). Over the
// front faces' geometry pixels (finite Z) and the three colour channels:
//   ref     = (A + B) / 2, whose own variance is estimated as mean((A - B)^2) / 4;
//   MSE     = mean((EST - ref)^2) - that variance (the estimate's own error; the raw
//             figure is printed too);
//   bias    = mean(EST - ref) with its standard error (over pixels, of each pixel's
//             mean over the channels: a pixel's three channels come from the same
//             paths): an unbiased estimator is within a few standard errors of 0. A - B is printed the same way (two
//             references rendered by different estimators check each other);
//   allocation bound = mean(V) / mean(sqrt V)^2, V = an estimate's squared error smoothed
//             over 5x5 pixels: what spending its paths in proportion to each pixel's
//             error instead of evenly could gain at most (adaptive sampling's ceiling).
// A plain program, not a Google Benchmark: it reads files and times nothing.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "data/dataset.h"
#include "data/exr_io.h"

using namespace nns;
using namespace nns::data;

namespace {

struct Front {
  std::string family;
  View view;
};

// Front faces by frame path relative to the dataset root, in listing order.
// The view with every channel averaged over blocks of k x k pixels; a block with any
// sky pixel is sky (Z = inf). The error per block is what a k-times smaller face of
// the same frame would see: a face of 128 against the data of a face of 64, per area.
View block_average(const View& v, int k) {
  if (k <= 1) return v;
  View out = v;
  out.width = v.width / k, out.height = v.height / k;
  for (auto& [name, plane] : v.channels) {
    std::vector<float>& dst = out.channels[name];
    dst.assign(size_t(out.width) * size_t(out.height), 0.0f);
    for (int y = 0; y < out.height; ++y)
      for (int x = 0; x < out.width; ++x) {
        double sum = 0;
        bool sky = false;
        for (int dy = 0; dy < k; ++dy)
          for (int dx = 0; dx < k; ++dx) {
            const size_t i = size_t(y * k + dy) * size_t(v.width) + size_t(x * k + dx);
            sum += plane[i];
            sky |= !std::isfinite(v.channel("Z")[i]);
          }
        dst[size_t(y) * size_t(out.width) + size_t(x)] = name == "Z" && sky ? INFINITY : float(sum / (k * k));
      }
  }
  return out;
}

std::map<std::string, Front> fronts(const std::string& root, size_t face, int block) {
  DatasetListing l = list_dataset(root);
  std::map<std::string, Front> out;
  for (const SplitListing* s : {&l.train, &l.test, &l.holdout})
    for (const FrameEntry& f : s->frames) {
      if (f.faces[face].empty()) continue;
      Front fr;
      fr.view = block_average(read_view(f.faces[face]), block);
      std::string name = fr.view.scene;
      size_t dash = name.find_last_of('-');
      fr.family = dash == std::string::npos ? name : name.substr(0, dash);
      std::string key = f.dir.substr(root.size());
      out.emplace(key, std::move(fr));
    }
  if (out.empty()) throw std::runtime_error(root + ": no surround frames");
  return out;
}

struct Stat {  // running sums over pixels x channels
  double n = 0, sum = 0, sum2 = 0;
  void add(double x) { n += 1, sum += x, sum2 += x * x; }
  double mean() const { return n > 0 ? sum / n : 0; }
  double mean_sq() const { return n > 0 ? sum2 / n : 0; }
  // Standard error of the mean (pixels treated as independent: the noise is).
  double se() const { return n > 1 ? std::sqrt(std::max(0.0, mean_sq() - mean() * mean()) / (n - 1)) : 0; }
};

// Per family ("all" too): per pixel (channel means) [0] ref, [1] A - B, [2] (A - B)^2 / 4,
// then per EST the squared error, then per EST the error; and per EST the smoothed
// squared error and its root (for the allocation bound).
struct Sums {
  std::map<std::string, std::vector<Stat>> fam, alloc;
  std::map<std::string, int> frames;
};

// Per estimate, each pixel's squared error smoothed over its 5x5 geometry neighbours
// (-1 on sky): a map of the estimator's variance, for the allocation bound.
std::vector<std::vector<double>> smoothed_squared_error(const View& a, const View& b,
                                                        const std::vector<const View*>& est,
                                                        const std::string (&names)[3]) {
  const auto& zf = a.channel("Z");
  const int W = a.width, H = a.height;
  std::vector<std::vector<double>> smooth(est.size(), std::vector<double>(zf.size(), -1.0));
  for (size_t e = 0; e < est.size(); ++e) {
    std::vector<double> sq(zf.size(), 0.0);
    for (size_t i = 0; i < zf.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        const std::string ch = names[c];
        double ref = 0.5 * (double(a.channel(ch)[i]) + double(b.channel(ch)[i]));
        double x = double(est[e]->channel(ch)[i]) - ref;
        sq[i] += x * x / 3;
      }
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        if (!std::isfinite(zf[size_t(y * W + x)])) continue;
        double sum = 0;
        int n = 0;
        for (int qy = std::max(0, y - 2); qy <= std::min(H - 1, y + 2); ++qy)
          for (int qx = std::max(0, x - 2); qx <= std::min(W - 1, x + 2); ++qx)
            if (std::isfinite(zf[size_t(qy * W + qx)])) sum += sq[size_t(qy * W + qx)], ++n;
        smooth[e][size_t(y * W + x)] = sum / n;
      }
  }
  return smooth;
}

// One frame's pixels into its family's sums and into "all".
void add_frame(Sums& sums, const Front& fa, const View& b, const std::vector<const View*>& est,
               const std::string (&names)[3]) {
  const size_t E = est.size();
  const std::vector<std::vector<double>> smooth = smoothed_squared_error(fa.view, b, est, names);
  for (const std::string& f : {fa.family, std::string("all")}) {
    auto& al = sums.alloc[f];
    al.resize(2 * E);
    for (size_t e = 0; e < E; ++e)
      for (double v : smooth[e])
        if (v >= 0) al[2 * e].add(v), al[2 * e + 1].add(std::sqrt(v));
    auto& st = sums.fam[f];
    st.resize(3 + 2 * E);
    ++sums.frames[f];
    const auto& z = fa.view.channel("Z");
    const std::vector<float>* a[3];
    const std::vector<float>* bb[3];
    std::vector<const std::vector<float>*> ec(3 * E);
    for (int c = 0; c < 3; ++c) {
      a[c] = &fa.view.channel(names[c]);
      bb[c] = &b.channel(names[c]);
      for (size_t e = 0; e < E; ++e) ec[e * 3 + size_t(c)] = &est[e]->channel(names[c]);
    }
    for (size_t i = 0; i < z.size(); ++i) {
      if (!std::isfinite(z[i])) continue;
      // Squared errors per channel; differences (bias) per pixel, averaged over
      // the channels, since a pixel's three channels come from the same paths.
      double dsum = 0;
      std::vector<double> esum(E, 0.0), esq(E, 0.0);
      double ref_sum = 0, var_sum = 0;
      for (int c = 0; c < 3; ++c) {
        double ref = 0.5 * (double((*a[c])[i]) + double((*bb[c])[i])), d = double((*a[c])[i]) - double((*bb[c])[i]);
        ref_sum += ref, dsum += d, var_sum += d * d / 4;
        for (size_t e = 0; e < E; ++e) {
          double x = double((*ec[e * 3 + size_t(c)])[i]) - ref;
          esum[e] += x, esq[e] += x * x;
        }
      }
      st[0].add(ref_sum / 3);
      st[1].add(dsum / 3);
      st[2].add(var_sum / 3);
      for (size_t e = 0; e < E; ++e) st[3 + E + e].add(esum[e] / 3), st[3 + e].add(esq[e] / 3);
    }
  }
}

void print_results(const Sums& sums, const std::vector<std::string>& dirs, const std::string& channel) {
  const size_t E = dirs.size() - 2;
  std::printf("channel %s; reference = mean of %s and %s\n", channel.c_str(), dirs[0].c_str(), dirs[1].c_str());
  for (auto& [f, st] : sums.fam) {
    double var_ref = st[2].mean();
    std::printf("%-12s frames %d, pixels %.0f, ref mean %.5g; A-B %+.3g +- %.2g (%.2f se); ref variance %.4g\n",
                f.c_str(), sums.frames.at(f), st[0].n, st[0].mean(), st[1].mean(), st[1].se(),
                st[1].se() > 0 ? st[1].mean() / st[1].se() : 0.0, var_ref);
    for (size_t e = 0; e < E; ++e) {
      const Stat& sq = st[3 + e];     // per pixel: mean over channels of the squared error
      const Stat& s = st[3 + E + e];  // per pixel: mean over channels of the error
      double mse = sq.mean() - var_ref;
      std::printf("    %-40s MSE %.5g (raw %.5g, rel %.4g)  bias %+.3g +- %.2g (%.2f se)\n", dirs[e + 2].c_str(), mse,
                  sq.mean(), st[0].mean() != 0 ? mse / (st[0].mean() * st[0].mean()) : 0.0, s.mean(), s.se(),
                  s.se() > 0 ? s.mean() / s.se() : 0.0);
      // Paths spent per pixel in proportion to its sigma instead of evenly would
      // divide the MSE by mean(V) / mean(sqrt V)^2 (V: the smoothed squared error);
      // an optimistic bound for any adaptive allocation (the smoothing keeps some noise).
      const Stat& v = sums.alloc.at(f)[2 * e];
      const Stat& r = sums.alloc.at(f)[2 * e + 1];
      if (r.mean() > 0)
        std::printf("        allocation bound: an adaptive allocation could divide this MSE by at most ~%.2f\n",
                    v.mean() / (r.mean() * r.mean()));
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string channel = "indirect", face_name = "front";
  int block = 1;
  std::vector<std::string> dirs;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--channel") == 0 && i + 1 < argc) channel = argv[++i];
    else if (std::strcmp(argv[i], "--face") == 0 && i + 1 < argc) face_name = argv[++i];
    else if (std::strcmp(argv[i], "--block") == 0 && i + 1 < argc) block = std::max(1, std::atoi(argv[++i]));
    else dirs.push_back(argv[i]);
  }
  if (dirs.size() < 3) {
    std::fprintf(stderr, "usage: indirect_error [--channel indirect] [--face front] [--block K] REF_A REF_B EST...\n");
    return 1;
  }
  try {
    std::vector<std::map<std::string, Front>> sets;
    size_t face = kFaceNames.size();
    for (size_t f = 0; f < kFaceNames.size(); ++f)
      if (face_name == kFaceNames[f]) face = f;
    if (face == kFaceNames.size()) throw std::runtime_error("--face: '" + face_name + "' is not a cube face name");
    for (auto& d : dirs) sets.push_back(fronts(d, face, block));
    // RGB channels, or a single one (AO) counted as three equal ones.
    std::string names[3];
    const bool single = sets[0].begin()->second.view.has(channel);
    const char* rgb[3] = {".R", ".G", ".B"};
    for (int c = 0; c < 3; ++c) names[c] = single ? channel : channel + rgb[c];
    Sums sums;
    for (auto& [key, fa] : sets[0]) {
      // Every other set must hold the same view of this frame.
      std::vector<const View*> others;
      for (size_t k = 1; k < sets.size(); ++k) {
        auto it = sets[k].find(key);
        if (it == sets[k].end()) throw std::runtime_error(dirs[k] + ": no frame " + key);
        if (it->second.view.channel("Z") != fa.view.channel("Z"))
          throw std::runtime_error(dirs[k] + ": frame " + key + " is not the reference's view (Z differs)");
        others.push_back(&it->second.view);
      }
      add_frame(sums, fa, *others[0], std::vector<const View*>(others.begin() + 1, others.end()), names);
    }
    print_results(sums, dirs, channel);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "indirect_error: %s\n", e.what());
    return 1;
  }
  return 0;
}
