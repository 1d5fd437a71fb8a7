// libFuzzer target: a user's image (data/image_read.h, through OpenImageIO), then the view
// nnao-infer and gi-infer assemble from it with --channel. The first byte picks the
// format by the file name (0 PNG, 1 TIFF, 2 HDR, 3 EXR); the rest is the file.
#include "data/image_read.h"
#include "fuzz/fuzz_support.h"

using namespace nns;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const std::string paths[4] = {fuzz::scratch_path("image.png"), fuzz::scratch_path("image.tif"),
                                       fuzz::scratch_path("image.hdr"), fuzz::scratch_path("image.exr")};
  const std::string& path = paths[data[0] % 4];
  fuzz::write_bytes(path, data + 1, size - 1);
  try {
    data::Image im = data::read_image(path);
    if (im.width <= 0 || im.height <= 0 || im.channels.empty() ||
        im.pixels.size() != size_t(im.width) * size_t(im.height) * im.channels.size())
      fuzz::finding("an image whose pixels do not match its size");
    // The whole file as every target it could fill (the rules pick channels or refuse).
    data::ImageViewOptions o;
    o.fov_y_deg = 60;
    o.depth_scale = 10;
    o.targets = {"depth", "normal"};
    o.optional = {"albedo", "direct", "emission", "env"};
    std::vector<data::ChannelMapping> m;
    for (const char* t : {"depth", "normal", "albedo"})
      m.push_back(data::parse_channel_mapping(std::string(t) + "=" + path));
    data::View v = data::view_from_images(m, o);
    for (auto& [name, plane] : v.channels)
      if (plane.size() != size_t(v.width) * size_t(v.height)) fuzz::finding("plane " + name + " of the wrong size");
  } catch (const std::exception& e) {
    fuzz::expect_named(e, path);
  }
  return 0;
}
