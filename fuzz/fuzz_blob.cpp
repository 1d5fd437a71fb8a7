// libFuzzer target: core/blob.h's parser (every weights file and checkpoint).
#include "fuzz/fuzz_support.h"

using namespace nns;

namespace {
void exercise(const std::string& bytes) {
  Blob b;
  try {
    b = Blob::parse(bytes, "<fuzz>");
  } catch (const std::runtime_error& e) {
    fuzz::expect_named(e, "blob '<fuzz>'");
    return;
  }
  // What a loader does next: typed reads of every tensor, numeric config values.
  for (auto& [name, t] : b.tensors()) {
    Shape shape(t.dims.begin(), t.dims.end());
    if (t.numel() > (int64_t(1) << 24)) continue;
    try {
      if (t.dtype == DType::U64) (void)b.tensor<uint64_t>(name, shape);
      else if (t.dtype == DType::I64) (void)b.tensor<int64_t>(name, shape);
      else (void)b.tensor<double>(name, shape);
      (void)b.tensor<float>(name, shape);
    } catch (const std::runtime_error& e) {
      fuzz::expect_named(e, "blob '<fuzz>'");
    }
  }
  for (auto& [k, v] : b.config()) {
    try {
      (void)b.config_int(k);
    } catch (const std::runtime_error& e) {
      fuzz::expect_named(e, "<fuzz>");
    }
    try {
      (void)b.config_double(k);
    } catch (const std::runtime_error& e) {
      fuzz::expect_named(e, "<fuzz>");
    }
  }
  // A blob that parsed writes back to bytes that parse to the same content.
  Blob again = Blob::parse(b.serialize(), "<again>");
  if (again.kind() != b.kind() || again.config() != b.config() || again.tensors().size() != b.tensors().size())
    fuzz::finding("blob does not survive serialize + parse");
  for (size_t i = 0; i < b.tensors().size(); ++i)
    if (again.tensors()[i].first != b.tensors()[i].first ||
        again.tensors()[i].second.bytes != b.tensors()[i].second.bytes ||
        again.tensors()[i].second.dims != b.tensors()[i].second.dims)
      fuzz::finding("tensor changed in serialize + parse");
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  exercise(std::string(reinterpret_cast<const char*>(data), size));
  exercise(fuzz::with_valid_envelope(data, size));
  return 0;
}
