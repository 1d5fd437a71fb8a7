#pragma once
// Finding the views of a dataset on disk (docs/dataset-format.md, "Files and folders").
//
//   DatasetListing d = list_dataset("DATA");        // train/ + test/, or one flat split
//   if (d.flat) d = split_flat_by_scene(d, 0.2);    // test gets whole scenes, never pixels
//   for (auto& path : d.train.views) ...            // single views, sorted
//   for (auto& frame : d.train.frames) read_frame(frame);   // surround: six faces
#include <array>
#include <string>
#include <vector>

#include "data/view.h"

namespace nns::data {

// Face order used everywhere a frame's six views appear together.
enum class Face { front = 0, back, left, right, up, down };
inline constexpr std::array<const char*, 6> kFaceNames = {"front", "back", "left", "right", "up", "down"};

// The split folders of a dataset (docs/dataset-format.md), in the order every listing,
// report and metadata file gives them.
inline constexpr std::array<const char*, 3> kSplitNames = {"train", "test", "holdout"};

// A surround frame: a folder holding <face>.exr for each face.
struct FrameEntry {
  std::string dir;
  std::array<std::string, 6> faces;  // paths in Face order; empty where missing
  std::vector<std::string> missing;  // face names without a file
  bool complete() const { return missing.empty(); }
};

struct SplitListing {
  std::string dir;
  std::vector<std::string> views;  // <view>.exr files, sorted by name
  std::vector<FrameEntry> frames;  // sub-folders with at least one <face>.exr, sorted
  size_t size() const { return views.size() + frames.size(); }
};

struct DatasetListing {
  std::string root;
  bool flat = false;  // no train/ and test/: everything is in `train`
  SplitListing train, test;
  // holdout/: views of whole scene families kept out of train/ and test/
  // (render-dataset --holdout-families); trainers never read it.
  SplitListing holdout;
  bool has_holdout = false;
  std::vector<std::string> notes;  // e.g. "DATA/train/x: folder without face files, ignored"
};

// Throws "<root>: ..." if root is not a readable folder. Files written half-way
// ("*.partial-*") and non-EXR files are skipped.
DatasetListing list_dataset(const std::string& root);

// For a flat listing: moves whole scenes (header attribute `scene`; a view without one
// is its own scene) to `test` until it holds about `test_fraction` of the items. Scenes
// are ordered by a hash of their name, so the split is deterministic and independent of
// file order. With a single scene everything stays in train and a note says so.
DatasetListing split_flat_by_scene(const DatasetListing& flat, double test_fraction);

// The frame in folder `dir`: the <face>.exr files present, the names of those missing.
FrameEntry frame_entry(const std::string& dir);
// The six faces of a complete frame in Face order. Throws "<file>: ..." on a missing
// face, an unreadable file, or faces that are not square or not all the same size.
std::array<View, 6> read_frame(const FrameEntry& frame);
// The size rule of a frame, however it was read: throws "<face's source>: ..." unless
// every face is square and the size of the front face.
void check_frame_sizes(const std::array<View, 6>& faces);

// The scene of a view or frame (front face), read from the header alone; "" if none.
std::string scene_of(const std::string& view_path);

}  // namespace nns::data
