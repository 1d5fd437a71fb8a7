// The error of a GI estimator against a converged reference, per scene family: the
// measure behind the renderer's efficiency table (docs/renderer.md, "Throughput").
//   indirect_error [--channel indirect] REF_A REF_B EST...
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
//             references rendered by different estimators check each other).
// A plain program, not a Google Benchmark: it reads files and times nothing.
#include <cmath>
#include <cstdio>
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
std::map<std::string, Front> fronts(const std::string& root) {
  DatasetListing l = list_dataset(root);
  std::map<std::string, Front> out;
  for (const SplitListing* s : {&l.train, &l.test, &l.holdout})
    for (const FrameEntry& f : s->frames) {
      if (f.faces[0].empty()) continue;
      Front fr;
      fr.view = read_view(f.faces[0]);
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

}  // namespace

int main(int argc, char** argv) {
  std::string channel = "indirect";
  std::vector<std::string> dirs;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--channel") == 0 && i + 1 < argc) channel = argv[++i];
    else dirs.push_back(argv[i]);
  }
  if (dirs.size() < 3) {
    std::fprintf(stderr, "usage: indirect_error [--channel indirect] REF_A REF_B EST...\n");
    return 1;
  }
  try {
    std::vector<std::map<std::string, Front>> sets;
    for (auto& d : dirs) sets.push_back(fronts(d));
    const auto& A = sets[0];
    const auto& B = sets[1];
    const char* rgb[3] = {".R", ".G", ".B"};
    // family -> per pixel (channel means): [0] ref, [1] A - B, [2] (A - B)^2 / 4, then per
    // EST the squared error, then per EST the error
    std::map<std::string, std::vector<Stat>> fam;
    std::map<std::string, int> frames;
    const size_t E = sets.size() - 2;
    for (auto& [key, fa] : A) {
      auto b = B.find(key);
      if (b == B.end()) throw std::runtime_error(dirs[1] + ": no frame " + key);
      std::vector<const View*> est;
      for (size_t e = 0; e < E; ++e) {
        auto it = sets[e + 2].find(key);
        if (it == sets[e + 2].end()) throw std::runtime_error(dirs[e + 2] + ": no frame " + key);
        if (it->second.view.channel("Z") != fa.view.channel("Z"))
          throw std::runtime_error(dirs[e + 2] + ": frame " + key + " is not the reference's view (Z differs)");
        est.push_back(&it->second.view);
      }
      if (b->second.view.channel("Z") != fa.view.channel("Z"))
        throw std::runtime_error(dirs[1] + ": frame " + key + " is not the reference's view (Z differs)");
      for (const std::string& f : {fa.family, std::string("all")}) {
        auto& st = fam[f];
        st.resize(3 + 2 * E);
        ++frames[f];
        const auto& z = fa.view.channel("Z");
        const std::vector<float>* a[3];
        const std::vector<float>* bb[3];
        std::vector<const std::vector<float>*> ec(3 * E);
        for (int c = 0; c < 3; ++c) {
          a[c] = &fa.view.channel(channel + rgb[c]);
          bb[c] = &b->second.view.channel(channel + rgb[c]);
          for (size_t e = 0; e < E; ++e) ec[e * 3 + size_t(c)] = &est[e]->channel(channel + rgb[c]);
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
    std::printf("channel %s; reference = mean of %s and %s\n", channel.c_str(), dirs[0].c_str(), dirs[1].c_str());
    for (auto& [f, st] : fam) {
      double var_ref = st[2].mean();
      std::printf("%-12s frames %d, pixels %.0f, ref mean %.5g; A-B %+.3g +- %.2g (%.2f se); ref variance %.4g\n",
                  f.c_str(), frames[f], st[0].n, st[0].mean(), st[1].mean(), st[1].se(),
                  st[1].se() > 0 ? st[1].mean() / st[1].se() : 0.0, var_ref);
      for (size_t e = 0; e < E; ++e) {
        const Stat& sq = st[3 + e];  // per pixel: mean over channels of the squared error
        const Stat& s = st[3 + E + e];  // per pixel: mean over channels of the error
        double mse = sq.mean() - var_ref;
        std::printf("    %-40s MSE %.5g (raw %.5g, rel %.4g)  bias %+.3g +- %.2g (%.2f se)\n", dirs[e + 2].c_str(), mse,
                    sq.mean(), st[0].mean() != 0 ? mse / (st[0].mean() * st[0].mean()) : 0.0, s.mean(), s.se(),
                    s.se() > 0 ? s.mean() / s.se() : 0.0);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "indirect_error: %s\n", e.what());
    return 1;
  }
  return 0;
}
