// libFuzzer target: OUT/metrics.jsonl as a resumed run re-reads it (runs/metrics_log.h,
// the one metrics format of both trainers). The first two bytes are the checkpoint's
// step; the rest is the file. Findings: a crash, a kept line past the checkpoint's
// step, or a kept record that does not survive being written and read again.
#include <cstring>

#include "fuzz/fuzz_support.h"
#include "runs/metrics_log.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const int64_t step = int64_t(data[0]) | int64_t(data[1]) << 8;
  static const std::string path = nns::fuzz::scratch_path("metrics.jsonl");
  nns::fuzz::write_bytes(path, data + 2, size - 2);
  nns::runs::MetricsLog log(path, step);
  for (auto& r : log.records()) {
    if (r.step > step) nns::fuzz::finding("kept a line past the checkpoint's step");
    auto again = nns::runs::parse_metrics_line(nns::runs::format_metrics_line(r));
    if (!again || again->step != r.step || again->epoch != r.epoch || again->values.size() != r.values.size())
      nns::fuzz::finding("a kept record does not survive format + parse");
  }
  // What the resumed log holds now is exactly its records, one line each.
  if (nns::runs::read_metrics(path).size() != log.records().size()) nns::fuzz::finding("rewritten log differs");
  return 0;
}
