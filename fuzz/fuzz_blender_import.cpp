// libFuzzer target: import-blender's conversion without the EXR around it (fuzz_exr
// reaches it only through OpenEXR's decoder): the capture note (data/blender_capture_note.h)
// and data/blender_import.h's convert on the planes it would read. One input: a byte
// each for the width and height (1 to 8), the note up to the first NUL, then the float
// planes Depth.Z, Normal.X, Normal.Y, Normal.Z, AO.R (missing values are 0). Findings: a
// crash, an error that does not name the file, or a converted view with a depth that is
// neither positive nor sky, or a surface normal that is not of unit length.
#include <cmath>
#include <cstring>

#include "data/blender_import.h"
#include "fuzz/fuzz_support.h"

using namespace nns::data;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const std::string file = "<fuzz>.exr";
  View in;
  in.width = 1 + data[0] % 8, in.height = 1 + data[1] % 8;
  in.source = file;
  const uint8_t* p = data + 2;
  const uint8_t* end = data + size;
  const uint8_t* nul = static_cast<const uint8_t*>(std::memchr(p, 0, size_t(end - p)));
  const std::string note(reinterpret_cast<const char*>(p), size_t((nul ? nul : end) - p));
  p = nul ? nul + 1 : end;
  const size_t n = size_t(in.width) * size_t(in.height);
  for (const char* c :
       {"ViewLayer.Depth.Z", "ViewLayer.Normal.X", "ViewLayer.Normal.Y", "ViewLayer.Normal.Z", "ViewLayer.AO.R"}) {
    auto& plane = in.add_channel(c);
    for (size_t i = 0; i < n && p + 4 <= end; ++i, p += 4) std::memcpy(&plane[i], p, 4);
  }
  try {
    blender::ImportSettings flags;
    const auto parsed = blender::parse_capture_note(note, file);
    std::vector<std::string> overrides;
    const blender::ImportSettings s = blender::with_capture_note(flags, parsed, &overrides);
    const View out = blender::convert(in, s);
    const auto& z = out.channel("Z");
    for (size_t i = 0; i < n; ++i) {
      if (!(z[i] > 0)) nns::fuzz::finding("a converted depth is neither positive nor sky");
      if (std::isinf(z[i])) continue;
      const double len = std::sqrt(double(out.channel("N.X")[i]) * out.channel("N.X")[i] +
                                   double(out.channel("N.Y")[i]) * out.channel("N.Y")[i] +
                                   double(out.channel("N.Z")[i]) * out.channel("N.Z")[i]);
      if (!(std::fabs(len - 1) < 1e-3)) nns::fuzz::finding("a surface normal is not of unit length");
    }
  } catch (const std::runtime_error& e) {
    nns::fuzz::expect_named(e, file);
  }
  return 0;
}
