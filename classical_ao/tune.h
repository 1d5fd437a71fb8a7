#pragma once
// Fitting a classical method's free parameters (params.h) to ray-traced AO, as XeGTAO
// fits its presets to a ray-traced reference: minimise the MSE over the non-sky pixels of
// a set of views (the training split: the test split stays unseen), averaged over the
// method's sample counts, so one parameter set serves them all.
//
// The search is coordinate descent: for each parameter in turn, step up (or, failing
// that, down) while the error falls; after every round the steps halve. It needs no
// gradient (the methods are piecewise constant in some parameters) and evaluates
// ~2 x parameters x rounds parameter sets plus the moves.
#include <algorithm>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "data/view.h"
#include "classical_ao/params.h"

namespace nns::classical_ao {

using screen_space::GBuffer;
using screen_space::gbuffer_from_view;

// The MSE of `method` with parameters p over views (each with Z, N.*, AO), pooled over
// the non-sky pixels of all views, averaged over the sample counts.
inline double classical_mse(const std::string& method, const std::vector<int>& counts, const ClassicalParams& p,
                            const std::vector<data::View>& views) {
  double total = 0;
  std::vector<float> out;
  for (int n : counts) {
    double se = 0;
    int64_t px = 0;
    for (const auto& v : views) {
      const GBuffer g = gbuffer_from_view(v);
      const auto& gt = v.channel("AO");
      out.resize(size_t(g.pixels()));
      run_classical(method, p, g, n, out.data());
      for (int64_t i = 0; i < g.pixels(); ++i) {
        if (g.sky(i)) continue;
        const double e = double(out[size_t(i)]) - gt[size_t(i)];
        se += e * e;
        ++px;
      }
    }
    total += px ? se / double(px) : 0;
  }
  return counts.empty() ? 0 : total / double(counts.size());
}

struct TuneResult {
  double mse_before = 0, mse_after = 0;
  int evaluations = 0;
};

// Moves method's parameters in p to a (local) minimum of classical_mse; `log` gets a line
// per improvement.
inline TuneResult tune_classical(const std::string& method, const std::vector<int>& counts,
                                 const std::vector<data::View>& views, ClassicalParams& p, int rounds,
                                 const std::function<void(const std::string&)>& log = {}) {
  std::vector<Tunable> ts = tunables(p, method);
  TuneResult r;
  double best = classical_mse(method, counts, p, views);
  r.mse_before = best;
  r.evaluations = 1;
  std::vector<float> step;
  for (auto& t : ts) step.push_back((t.hi - t.lo) / 8);
  for (int round = 0; round < rounds; ++round) {
    for (size_t i = 0; i < ts.size(); ++i) {
      for (float dir : {1.0f, -1.0f}) {
        bool moved = false;
        for (;;) {
          const float old = *ts[i].value;
          const float cand = std::clamp(old + dir * step[i], ts[i].lo, ts[i].hi);
          if (cand == old) break;
          *ts[i].value = cand;
          const double e = classical_mse(method, counts, p, views);
          ++r.evaluations;
          if (!(e < best)) {
            *ts[i].value = old;
            break;
          }
          best = e, moved = true;
          if (log) log(method + "." + ts[i].name + " = " + std::to_string(cand) + ": MSE " + std::to_string(e));
        }
        if (moved) break;  // the other direction only helps if this one did not
      }
    }
    for (float& s : step) s *= 0.5f;
  }
  r.mse_after = best;
  return r;
}

}  // namespace nns::classical_ao
