#include "data/dataset.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "data/exr_io.h"

namespace nns::data {
namespace fs = std::filesystem;
namespace {

bool is_exr(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".exr";
}

std::vector<fs::path> sorted_entries(const fs::path& dir) {
  std::vector<fs::path> out;
  for (auto& e : fs::directory_iterator(dir)) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

SplitListing list_split(const fs::path& dir, std::vector<std::string>& notes) {
  SplitListing s;
  s.dir = dir.string();
  for (auto& p : sorted_entries(dir)) {
    if (fs::is_directory(p)) {
      FrameEntry f = frame_entry(p.string());
      if (f.missing.size() < kFaceNames.size()) s.frames.push_back(std::move(f));
      else notes.push_back(p.string() + ": folder without face files (front.exr ...), ignored");
    } else if (is_exr(p) && p.filename().string().find(".partial-") == std::string::npos) {
      s.views.push_back(p.string());
    }
  }
  return s;
}

// FNV-1a: a fixed hash, unlike std::hash, so splits are the same on every platform.
uint64_t fnv1a(const std::string& s) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

}  // namespace

DatasetListing list_dataset(const std::string& root) {
  std::error_code ec;
  if (!fs::is_directory(root, ec)) throw std::runtime_error(root + ": not a folder");
  DatasetListing d;
  d.root = root;
  try {
    fs::path r(root);
    bool has_train = fs::is_directory(r / "train"), has_test = fs::is_directory(r / "test");
    if (has_train || has_test) {
      if (has_train) d.train = list_split(r / "train", d.notes);
      if (has_test) d.test = list_split(r / "test", d.notes);
      d.has_holdout = fs::is_directory(r / "holdout");
      if (d.has_holdout) d.holdout = list_split(r / "holdout", d.notes);
      if (!has_train) d.notes.push_back(root + ": has test/ but no train/");
      if (!has_test) d.notes.push_back(root + ": has train/ but no test/");
    } else {
      d.flat = true;
      d.train = list_split(r, d.notes);
    }
  } catch (const fs::filesystem_error& e) {
    throw std::runtime_error(root + ": cannot list the dataset (" + e.what() + ")");
  }
  return d;
}

std::string scene_of(const std::string& view_path) {
  ReadOptions o;
  o.header_only = true;
  o.require_attributes = false;
  return read_view(view_path, o).scene;
}

DatasetListing split_flat_by_scene(const DatasetListing& flat, double test_fraction) {
  if (!flat.flat) throw std::invalid_argument(flat.root + ": split_flat_by_scene needs a flat dataset");
  DatasetListing d = flat;
  d.flat = false;
  d.train = SplitListing{flat.train.dir, {}, {}};
  d.test = SplitListing{flat.train.dir, {}, {}};

  // scene -> (views, frames)
  std::map<std::string, SplitListing> by_scene;
  for (auto& v : flat.train.views) {
    std::string s = scene_of(v);
    by_scene[s.empty() ? "file:" + v : s].views.push_back(v);
  }
  for (auto& f : flat.train.frames) {
    std::string front = f.faces[size_t(Face::front)];
    std::string s = front.empty() ? "" : scene_of(front);
    by_scene[s.empty() ? "frame:" + f.dir : s].frames.push_back(f);
  }
  std::vector<std::string> scenes;
  for (auto& [name, items] : by_scene) scenes.push_back(name);
  std::sort(scenes.begin(), scenes.end(), [](const std::string& a, const std::string& b) {
    uint64_t ha = fnv1a(a), hb = fnv1a(b);
    return ha != hb ? ha < hb : a < b;
  });

  const double total = double(flat.train.size());
  size_t in_test = 0;
  for (size_t i = 0; i < scenes.size(); ++i) {
    const SplitListing& items = by_scene[scenes[i]];
    bool last_scene = i + 1 == scenes.size();
    bool to_test = !last_scene && double(in_test) < test_fraction * total;
    SplitListing& dst = to_test ? d.test : d.train;
    dst.views.insert(dst.views.end(), items.views.begin(), items.views.end());
    dst.frames.insert(dst.frames.end(), items.frames.begin(), items.frames.end());
    if (to_test) in_test += items.size();
  }
  // Keep the sorted order within each split.
  for (SplitListing* s : {&d.train, &d.test}) {
    std::sort(s->views.begin(), s->views.end());
    std::sort(s->frames.begin(), s->frames.end(),
              [](const FrameEntry& a, const FrameEntry& b) { return a.dir < b.dir; });
  }
  if (scenes.size() < 2)
    d.notes.push_back(flat.root + ": a single scene; cannot hold out a test scene, everything is train");
  return d;
}

FrameEntry frame_entry(const std::string& dir) {
  FrameEntry f;
  f.dir = dir;
  for (size_t i = 0; i < kFaceNames.size(); ++i) {
    fs::path face = fs::path(dir) / (std::string(kFaceNames[i]) + ".exr");
    std::error_code ec;  // unreadable counts as missing, as for a file that is not there
    if (fs::is_regular_file(face, ec)) f.faces[i] = face.string();
    else f.missing.push_back(kFaceNames[i]);
  }
  return f;
}

std::array<View, 6> read_frame(const FrameEntry& frame) {
  if (!frame.complete())
    throw std::runtime_error(frame.dir + ": surround frame misses face '" + frame.missing.front() + "'");
  std::array<View, 6> faces;
  for (size_t i = 0; i < 6; ++i) faces[i] = read_view(frame.faces[i]);
  check_frame_sizes(faces);
  return faces;
}

void check_frame_sizes(const std::array<View, 6>& faces) {
  for (size_t i = 0; i < 6; ++i) {
    if (faces[i].width != faces[i].height)
      throw std::runtime_error(faces[i].source + ": a surround face must be square, got " +
                               std::to_string(faces[i].width) + "x" + std::to_string(faces[i].height));
    if (faces[i].width != faces[0].width)
      throw std::runtime_error(faces[i].source + ": face is " + std::to_string(faces[i].width) + "x" +
                               std::to_string(faces[i].height) + " but front is " + std::to_string(faces[0].width) +
                               "x" + std::to_string(faces[0].height));
  }
}

}  // namespace nns::data
