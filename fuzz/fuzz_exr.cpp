// libFuzzer target: one EXR dataset view (data/exr_io.cpp, header pre-check
// data/exr_header_check.cpp) and the validator's checks on what it read; and the same
// bytes as a Blender render for import-blender (its capture note in the header's "Note",
// data/blender_capture_note.h, then the conversion).
#include "data/blender_import.h"
#include "data/exr_io.h"
#include "data/validate.h"
#include "fuzz/fuzz_support.h"

using namespace nns;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = fuzz::scratch_path("view.exr");
  fuzz::write_bytes(path, data, size);
  data::ReadOptions o;
  o.require_attributes = false;
  o.warn_half_depth = false;
  for (bool header_only : {true, false}) {
    o.header_only = header_only;
    try {
      data::ExrInfo info;
      data::View v = data::read_view(path, o, &info);
      if (!header_only) {
        data::ValidationReport r;
        data::ProblemSink sink(r, 10);
        data::check_view(v, &info, true, {}, sink, &r);
        auto note = info.strings.find("Note");
        data::blender::ImportSettings flags;
        flags.fov_y = 40;  // so a file without a note still reaches the conversion
        data::blender::convert(
            v, data::blender::with_capture_note(flags, note == info.strings.end()
                                                           ? std::nullopt
                                                           : data::blender::parse_capture_note(note->second, path)));
      }
    } catch (const std::exception& e) {
      fuzz::expect_named(e, path);
      return 0;
    }
  }
  return 0;
}
