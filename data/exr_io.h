#pragma once
// Reading and writing one G-buffer view as a single-part OpenEXR file
// (docs/dataset-format.md).
//
//   View v = read_view("train/0001.exr");            // throws "<file>: <problem>"
//   write_view("out/0001.exr", v);                    // Z FLOAT, the rest FLOAT, ZIP
//   write_view("out/0001.exr", v, {.half = true});    // the rest HALF, half the size
//
// Reading accepts what OpenEXR reads: scanline or tiled, HALF/FLOAT/UINT channels, any
// compression, a data window anywhere (pixel (0,0) of the View is its top-left corner).
// Deep and multi-part files are refused with a message saying so.
#include <map>
#include <string>
#include <vector>

#include "data/view.h"

namespace nns::data {

struct ReadOptions {
  // Missing `fovY` or `scene` is an error (the trainers need them); the validator turns
  // this off so it can list every problem of a file instead of the first.
  bool require_attributes = true;
  // A HALF `Z` loses the depth differences the features are made of: say so on stderr.
  bool warn_half_depth = true;
  // Read only these channels (empty: all). Saves decoding when a trainer needs 4 of 16.
  std::vector<std::string> only_channels;
  // Read the header only (size, attributes, ExrInfo); the View gets no planes.
  bool header_only = false;
};

// What the file looked like, for dataset-info's summary and the validator.
struct ExrInfo {
  struct Channel {
    std::string name;
    bool half = false;  // stored as HALF (else FLOAT or UINT)
  };
  std::vector<Channel> channels;  // every channel in the file, sorted by name
  bool tiled = false;
  std::string compression;
  bool has_fov_y = false, has_ao_radius = false, has_scene = false, has_world_to_camera = false;
  // Every string attribute of the header, e.g. Blender's render stamp "Note" that
  // tools/blender_capture.py fills with the camera (data/blender_capture_note.h).
  std::map<std::string, std::string> strings;
};

View read_view(const std::string& path, const ReadOptions& options = {}, ExrInfo* info = nullptr);

struct WriteOptions {
  // Store every channel except `Z` as HALF. Default off: FLOAT keeps the renderer's
  // values bit-exact (AO noise measured at 1e-4 would drown in HALF's 5e-4 steps near 1).
  bool half = false;
};

// Writes to "<path>.tmp.<pid>" and renames (core/atomic_file.h), so a reader never sees
// half a file.
// Throws "<file>: <problem>" if the view is inconsistent (plane sizes) or on I/O errors.
void write_view(const std::string& path, const View& v, const WriteOptions& options = {});

}  // namespace nns::data
