// libFuzzer target: the classical-parameters file eval-ao --classical-params and
// tune-classical-ao --start read (classical_ao/params.h). Findings: a crash, an error
// that does not name the file, a value outside its parameter's interval, or parameters
// that do not survive being written and read again.
#include "classical_ao/params.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = nns::fuzz::scratch_path("classical-params.txt");
  nns::fuzz::write_bytes(path, data, size);
  nns::classical_ao::ClassicalParams p;
  try {
    p = nns::classical_ao::read_classical_params(path);
  } catch (const std::runtime_error& e) {
    nns::fuzz::expect_named(e, path);
    return 0;
  }
  for (auto& t : nns::classical_ao::tunables(p))
    if (!(*t.value >= t.lo && *t.value <= t.hi)) nns::fuzz::finding(t.method + "." + t.name + " outside its interval");
  const std::string text = nns::classical_ao::format_classical_params(p);
  nns::fuzz::write_bytes(path, reinterpret_cast<const uint8_t*>(text.data()), text.size());
  if (nns::classical_ao::format_classical_params(nns::classical_ao::read_classical_params(path)) != text)
    nns::fuzz::finding("parameters do not survive format + read");
  return 0;
}
