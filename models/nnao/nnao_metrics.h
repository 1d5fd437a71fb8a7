#pragma once
// Re-reading OUT/metrics.jsonl on `train-nnao --resume`: the lines of the epochs the
// checkpoint covers are kept (the rest belong to epochs that will be trained again), and
// the loss curves are rebuilt from them for the chart. A line that does not parse keeps
// its place in the file but adds no point to the chart. Its own header so that the
// fuzzer (fuzz/fuzz_metrics.cpp) reaches exactly the code the trainer runs.
#include <cstdint>
#include <cstdio>
#include <istream>
#include <string>
#include <vector>

namespace nns::nnao {

struct ResumedMetrics {
  std::vector<std::string> lines;        // at most `epochs` lines, verbatim
  std::vector<double> epoch, train_loss, test_mse;  // the lines that parsed
};

inline ResumedMetrics read_resumed_metrics(std::istream& in, int64_t epochs) {
  ResumedMetrics m;
  std::string line;
  while (int64_t(m.lines.size()) < epochs && std::getline(in, line)) {
    m.lines.push_back(line);
    double e = 0, tl = 0, tm = 0;
    if (std::sscanf(line.c_str(), "{\"epoch\": %lf, \"train_loss\": %lf, \"test_mse\": %lf", &e, &tl, &tm) == 3)
      m.epoch.push_back(e), m.train_loss.push_back(tl), m.test_mse.push_back(tm);
  }
  return m;
}

}  // namespace nns::nnao
