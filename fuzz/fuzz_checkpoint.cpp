// libFuzzer target: optim/checkpoint.h restoring a run (module parameters, Adam
// moments, an Rng, counters) from a checkpoint blob — what `--resume` reads.
#include "fuzz/fuzz_support.h"
#include "nn/linear.h"
#include "optim/adam.h"
#include "optim/checkpoint.h"

using namespace nns;

namespace {
// Built once: a restore overwrites every registered object or throws, and a partial
// restore before the throw is a state the next input may start from (as after any
// failed --resume, which stops the run).
struct Run {
  Rng init{1};
  Linear<float> net{init, 3, 2};
  Adam<float> opt{net.parameters()};
  Rng data_rng{2};
  int64_t epoch = 0, step = 0;
  Checkpoint<float> ck;
  Run() {
    ck.add_module("net", net)
        .add_optimizer("adam", opt)
        .add_rng("data", data_rng)
        .add_counter("epoch", epoch)
        .add_counter("step", step);
  }
};

void exercise(const std::string& bytes) {
  static Run run;
  Checkpoint<float>& ck = run.ck;
  try {
    Blob b = Blob::parse(bytes, "<fuzz>");
    ck.restore(b);
  } catch (const std::runtime_error& e) {
    fuzz::expect_named(e, "<fuzz>");
    return;
  }
  // A restored state trains on and saves again.
  Blob meta("checkpoint");
  ck.fill(meta);
  (void)Blob::parse(meta.serialize(), "<again>");
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  exercise(std::string(reinterpret_cast<const char*>(data), size));
  exercise(fuzz::with_valid_envelope(data, size));
  return 0;
}
