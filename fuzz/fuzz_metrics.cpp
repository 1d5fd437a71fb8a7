// libFuzzer target: re-reading OUT/metrics.jsonl on `train-nnao --resume`
// (models/nnao/nnao_metrics.h). The first two bytes are the checkpoint's epoch.
#include <sstream>

#include "fuzz/fuzz_support.h"
#include "models/nnao/nnao_metrics.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const int64_t epochs = int64_t(data[0]) | int64_t(data[1]) << 8;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data + 2), size - 2));
  auto m = nns::nnao::read_resumed_metrics(in, epochs);
  if (int64_t(m.lines.size()) > epochs) nns::fuzz::finding("kept more lines than epochs");
  if (m.epoch.size() != m.train_loss.size() || m.epoch.size() != m.test_mse.size() || m.epoch.size() > m.lines.size())
    nns::fuzz::finding("curves out of step with the lines");
  return 0;
}
