#include "data/validate.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/thread_pool.h"
#include "data/dataset.h"

namespace nns::data {
namespace {

std::string where(int64_t count, size_t first, int width) {
  return std::to_string(count) + (count == 1 ? " pixel" : " pixels") +
         " (first at x=" + std::to_string(first % size_t(width)) + ", y=" + std::to_string(first / size_t(width)) + ")";
}

// Counts pixels matching `bad` and remembers the first, for one message per channel.
struct Tally {
  int64_t count = 0;
  size_t first = 0;
  void add(size_t i) {
    if (count++ == 0) first = i;
  }
};

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", x);
  return buf;
}

bool is_lighting(const std::string& ch) {
  for (const char* p : {"direct.", "indirect.", "env.", "emission."})
    if (ch.rfind(p, 0) == 0) return true;
  return false;
}

void summarize(ValidationReport* r, const std::string& ch, const std::vector<float>& plane) {
  if (!r) return;
  ChannelSummary& s = r->channels[ch];
  s.files++;
  for (size_t i = 0; i < plane.size(); ++i) {
    float x = plane[i];
    if (ch == "Z") {
      s.pixels++;
      if (is_sky(x) && !std::isnan(x) && x > 0) {
        s.sky++;
        continue;
      }
    }
    if (!std::isfinite(x)) continue;
    if (!s.any_finite) s.min = s.max = x, s.any_finite = true;
    s.min = std::min(s.min, double(x));
    s.max = std::max(s.max, double(x));
  }
}

std::string strip_prefix(const std::string& message, const std::string& file) {
  return message.rfind(file + ": ", 0) == 0 ? message.substr(file.size() + 2) : message;
}

}  // namespace

std::string Problem::str() const {
  std::string s = file.empty() ? "" : file + ": ";
  if (!channel.empty()) s += "channel '" + channel + "': ";
  return s + (warning ? "warning: " : "") + message + (split.empty() ? "" : " in split '" + split + "'");
}

void check_view(const View& v, const ExrInfo* info, bool is_front, const ValidateOptions& o, ProblemSink& sink,
                ValidationReport* summary) {
  const std::string& f = v.source;
  const size_t n = size_t(v.width) * size_t(v.height);

  std::vector<std::string> required = {"Z", "N.X", "N.Y", "N.Z"};
  std::string why = "required";
  if (o.purpose == Purpose::nnao) {
    required.push_back("AO");
    why = "required for NNAO";
  } else if (o.purpose == Purpose::gi) {
    for (const char* c : {"albedo.R", "albedo.G", "albedo.B", "direct.R", "direct.G", "direct.B"})
      required.push_back(c);
    if (is_front)
      for (const char* c : {"indirect.R", "indirect.G", "indirect.B"}) required.push_back(c);
    why = is_front ? "required for GI" : "required for GI on every surround face";
  }
  for (auto& c : required)
    if (!v.has(c)) sink.error(f, c, "missing (" + (c == "Z" || c[0] == 'N' ? std::string("required") : why) + ")");

  // Header attributes.
  bool has_fov = info ? info->has_fov_y : v.fov_y_deg != 0;
  if (!has_fov) sink.error(f, "", "missing header attribute 'fovY' (float, degrees)");
  else if (!(v.fov_y_deg > 0 && v.fov_y_deg < 180))
    sink.error(f, "", "header attribute 'fovY' is " + fmt(v.fov_y_deg) + ", expected degrees in (0, 180)");
  if (v.scene.empty()) sink.error(f, "", "missing header attribute 'scene' (string)");
  if (v.has("AO")) {
    if (!v.ao_radius) sink.error(f, "AO", "missing header attribute 'aoRadius' (required when AO is present)");
    else if (!(*v.ao_radius > 0 && std::isfinite(*v.ao_radius)))  // import-blender --ao-radius 1e39 wrote inf
      sink.error(f, "AO", "header attribute 'aoRadius' is " + fmt(*v.ao_radius) + ", expected a finite number > 0");
  }
  if (v.world_to_camera)
    for (float x : *v.world_to_camera)
      if (!std::isfinite(x)) {
        sink.error(f, "", "header attribute 'worldToCamera' holds " + fmt(x) + ", expected finite numbers");
        break;
      }
  if (info)
    for (auto& c : info->channels)
      if (c.name == "Z" && c.half)
        sink.warn(f, "Z", "stored as HALF; depth differences lose precision (writers should store FLOAT)");

  for (auto& [ch, plane] : v.channels)
    if (plane.size() != n) {
      sink.error(f, ch, "plane has " + std::to_string(plane.size()) + " values, expected " + std::to_string(n));
      return;  // the checks below index planes by pixel
    }

  // Depth: > 0, +inf (or >= 1e30) for sky; NaN, -inf, zero and negative are errors.
  std::vector<uint8_t> sky(n, 0);
  if (v.has("Z")) {
    const auto& z = v.channel("Z");
    Tally nan, nonpos;
    for (size_t i = 0; i < n; ++i) {
      if (std::isnan(z[i])) nan.add(i);
      else if (!(z[i] > 0)) nonpos.add(i);
      else if (is_sky(z[i])) sky[i] = 1;
    }
    if (nan.count) sink.error(f, "Z", "NaN depth at " + where(nan.count, nan.first, v.width));
    if (nonpos.count)
      sink.error(f, "Z",
                 "depth <= 0 at " + where(nonpos.count, nonpos.first, v.width) + " (sky must be +inf or >= 1e30)");
    summarize(summary, "Z", z);
  }

  // Normals: unit length on geometry; sky may hold zero or a unit vector.
  if (v.has("N.X") && v.has("N.Y") && v.has("N.Z")) {
    const auto &nx = v.channel("N.X"), &ny = v.channel("N.Y"), &nz = v.channel("N.Z");
    Tally nonfinite, nonunit;
    double worst = 1;
    for (size_t i = 0; i < n; ++i) {
      if (!std::isfinite(nx[i]) || !std::isfinite(ny[i]) || !std::isfinite(nz[i])) {
        nonfinite.add(i);
        continue;
      }
      double len = std::sqrt(double(nx[i]) * nx[i] + double(ny[i]) * ny[i] + double(nz[i]) * nz[i]);
      if (sky[i] && len < o.normal_tolerance) continue;
      if (std::abs(len - 1) > o.normal_tolerance) {
        nonunit.add(i);
        if (std::abs(len - 1) > std::abs(worst - 1)) worst = len;
      }
    }
    if (nonfinite.count)
      sink.error(f, "N.X/N.Y/N.Z", "NaN or Inf normal at " + where(nonfinite.count, nonfinite.first, v.width));
    if (nonunit.count)
      sink.error(f, "N.X/N.Y/N.Z",
                 "non-unit normal at " + where(nonunit.count, nonunit.first, v.width) + ", worst length " + fmt(worst) +
                     " (tolerance " + fmt(o.normal_tolerance) + ")");
  }

  for (auto& [ch, plane] : v.channels) {
    if (ch == "Z") continue;
    Tally nonfinite, out_of_range;
    const bool ao = ch == "AO", albedo = ch.rfind("albedo.", 0) == 0, light = is_lighting(ch);
    for (size_t i = 0; i < n; ++i) {
      float x = plane[i];
      if (!std::isfinite(x)) nonfinite.add(i);
      else if ((ao || albedo) ? (x < 0 || x > 1) : (light && x < 0)) out_of_range.add(i);
    }
    if (nonfinite.count) sink.error(f, ch, "NaN or Inf at " + where(nonfinite.count, nonfinite.first, v.width));
    if (out_of_range.count) {
      std::string what = "value " + fmt(plane[out_of_range.first]) + " outside ";
      if (ao) sink.error(f, ch, what + "[0,1] at " + where(out_of_range.count, out_of_range.first, v.width));
      else if (albedo) sink.warn(f, ch, what + "[0,1] at " + where(out_of_range.count, out_of_range.first, v.width));
      else
        sink.warn(f, ch,
                  "negative radiance " + fmt(plane[out_of_range.first]) + " at " +
                      where(out_of_range.count, out_of_range.first, v.width));
    }
    summarize(summary, ch, plane);
  }
}

namespace {

// One file as read, before its checks: the reading (decoding) runs on the pool's workers,
// the checks and the problems they report stay in the listing's order.
struct ReadFile {
  View view;
  ExrInfo info;
  std::string error;  // why it could not be read ("" when read)
};

// Decodes `paths` on the pool's workers, each file whole: a surround frame's six faces at
// face 128 take 2 x 0.1 s on 2 threads instead of 6 x 0.1 s in a row.
std::vector<ReadFile> read_files(const std::vector<std::string>& paths) {
  std::vector<ReadFile> out(paths.size());
  parallel_for_dynamic(int64_t(paths.size()), 1, [&](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i) {
      ReadFile& f = out[size_t(i)];
      const std::string& path = paths[size_t(i)];
      if (path.empty()) continue;
      ReadOptions ro;
      ro.require_attributes = false;
      ro.warn_half_depth = false;  // reported as a warning in the report instead
      try {
        f.view = read_view(path, ro, &f.info);
      } catch (const std::exception& ex) {
        f.error = strip_prefix(ex.what(), path);
      }
    }
  });
  return out;
}

// Checks one file as read; returns false (after reporting) if it could not be read.
bool check_file(const std::string& path, ReadFile& f, bool is_front, const ValidateOptions& o, ProblemSink& sink,
                ValidationReport& r) {
  if (!f.error.empty()) {
    sink.error(path, "", f.error);
    return false;
  }
  r.resolutions[std::to_string(f.view.width) + "x" + std::to_string(f.view.height)]++;
  check_view(f.view, &f.info, is_front, o, sink, &r);
  return true;
}

// Reads DIR/metadata.txt into the report: "key: value" lines, '#' comments and blank
// lines; unknown keys are kept and ignored (newer writers may add some).
void read_metadata(const std::string& root, ValidationReport& r, ProblemSink& sink) {
  std::filesystem::path path = std::filesystem::path(root) / "metadata.txt";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return;
  std::ifstream in(path);
  if (!in) {
    sink.error(path.string(), "", "cannot read");
    return;
  }
  r.has_metadata = true;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty() || line[0] == '#') continue;
    size_t colon = line.find(": ");
    if (colon == std::string::npos || colon == 0) {
      sink.error(path.string(), "", "line " + std::to_string(n) + ": expected 'key: value', got '" + line + "'");
      continue;
    }
    std::string key = line.substr(0, colon), value = line.substr(colon + 2);
    r.metadata[key] = value;
    if (key.rfind("families.", 0) == 0) {
      std::vector<std::string>& list = r.split_families[key.substr(9)];
      std::stringstream ss(value);
      for (std::string f; std::getline(ss, f, ',');)
        if (!f.empty()) list.push_back(f);
    }
  }
}

// metadata.txt's "views.<split>" (render-dataset writes them from its plan before the
// first view) against the views or surround frames the split holds: fewer is a render
// that did not finish, more are views of another render. Without the keys (datasets
// rendered before they existed) there is nothing to compare.
void check_split_counts(const std::string& root, const ValidationReport& r, ProblemSink& sink) {
  const std::string meta = (std::filesystem::path(root) / "metadata.txt").string();
  const auto preset = r.metadata.find("preset");
  const bool surround = preset != r.metadata.end() && preset->second.rfind("surround", 0) == 0;
  for (const char* split : kSplitNames) {
    auto it = r.metadata.find(std::string("views.") + split);
    if (it == r.metadata.end()) continue;
    sink.set_split(split);
    int64_t want = -1;
    try {
      size_t used = 0;
      want = std::stoll(it->second, &used);
      if (used != it->second.size()) want = -1;
    } catch (const std::exception&) {
    }
    if (want < 0) {
      sink.error(meta, "", it->first + ": expected a count of views, got '" + it->second + "'");
      continue;
    }
    const int64_t views = r.views.count(split) ? r.views.at(split) : 0;
    const int64_t frames = r.frames.count(split) ? r.frames.at(split) : 0;
    const bool as_frames = surround || frames > 0;
    const int64_t have = views + frames;
    if (have == want) continue;
    const int64_t diff = have > want ? have - want : want - have;
    sink.error(meta, "",
               std::string(split) + "/: " + std::to_string(have) + (as_frames ? " frames" : " views") +
                   ", metadata.txt says " + std::to_string(want) + ": " + std::to_string(diff) +
                   (have < want ? " missing: a render that did not finish?" : " extra: views of another render?"));
  }
  sink.set_split("");
}

}  // namespace

std::string scene_family_of(const std::string& scene) {
  size_t dash = scene.rfind('-');
  if (dash == std::string::npos || dash + 1 == scene.size()) return scene;
  for (size_t i = dash + 1; i < scene.size(); ++i)
    if (scene[i] < '0' || scene[i] > '9') return scene;
  return scene.substr(0, dash);
}

namespace {

// split -> scene -> the first file of it seen (named in the errors about a scene).
using FirstFiles = std::map<std::string, std::map<std::string, std::string>>;

// Every file of one split: read (on the pool's workers), checked, its scene noted, and
// handed to o.on_view.
void check_split(const std::string& name, const SplitListing& split, const ValidateOptions& o, ProblemSink& sink,
                 ValidationReport& r, FirstFiles& first_file) {
  sink.set_split(name);
  r.views[name] = int64_t(split.views.size());
  r.frames[name] = int64_t(split.frames.size());
  auto note_scene = [&](const View& v) {
    if (v.scene.empty()) return;
    r.scenes[name].insert(v.scene);
    first_file[name].emplace(v.scene, v.source);
  };
  // Views in batches of a few, so that the pool's workers decode side by side.
  constexpr size_t kBatch = 8;
  for (size_t b = 0; b < split.views.size(); b += kBatch) {
    const std::vector<std::string> paths(
        split.views.begin() + std::ptrdiff_t(b),
        split.views.begin() + std::ptrdiff_t(std::min(b + kBatch, split.views.size())));
    std::vector<ReadFile> files = read_files(paths);
    for (size_t i = 0; i < paths.size(); ++i) {
      if (!check_file(paths[i], files[i], true, o, sink, r)) continue;
      note_scene(files[i].view);
      if (o.on_view) o.on_view(std::move(files[i].view));
    }
  }
  for (auto& frame : split.frames) {
    for (auto& face : frame.missing) sink.error(frame.dir + "/" + face + ".exr", "", "surround frame misses this face");
    int front_w = -1, front_h = -1;
    std::string front_file;
    const std::vector<std::string> paths(frame.faces.begin(), frame.faces.end());
    std::vector<ReadFile> files = read_files(paths);
    for (size_t i = 0; i < 6; ++i) {
      if (frame.faces[i].empty()) continue;
      if (!check_file(frame.faces[i], files[i], i == size_t(Face::front), o, sink, r)) continue;
      const View& v = files[i].view;
      if (v.width != v.height)
        sink.error(
            v.source, "",
            "surround face is " + std::to_string(v.width) + "x" + std::to_string(v.height) + ", faces must be square");
      if (front_w < 0) {
        front_w = v.width, front_h = v.height, front_file = v.source;
        note_scene(v);
      } else if (v.width != front_w || v.height != front_h) {
        sink.error(v.source, "",
                   "size " + std::to_string(v.width) + "x" + std::to_string(v.height) + " differs from " + front_file +
                       " (" + std::to_string(front_w) + "x" + std::to_string(front_h) + ") in the same surround frame");
      }
      if (o.on_view) o.on_view(std::move(files[i].view));
    }
  }
}

// No scene in two splits: test/ and holdout/ must come from scenes (holdout/: families)
// the training split never saw.
void check_scenes_apart(const DatasetListing& d, ValidationReport& r, ProblemSink& sink, FirstFiles& first_file) {
  for (auto& scene : r.scenes["test"])
    if (r.scenes["train"].count(scene))
      sink.error(first_file["test"][scene], "",
                 "scene '" + scene + "' is in both train/ and test/ (e.g. " + first_file["train"][scene] +
                     "); test views must come from held-out scenes");
  if (!d.has_holdout) return;
  for (auto& scene : r.scenes["holdout"])
    for (const char* other : {"train", "test"})
      if (r.scenes[other].count(scene))
        sink.error(first_file["holdout"][scene], "",
                   "scene '" + scene + "' is in both holdout/ and " + other + "/ (e.g. " + first_file[other][scene] +
                       "); held-out views must come from held-out families");
}

// Leave-families-out, when metadata.txt names the held-out families: none of their
// scenes in train/ or test/, and nothing else in holdout/.
void check_holdout_families(const std::string& root, const DatasetListing& d, ValidationReport& r, ProblemSink& sink,
                            FirstFiles& first_file) {
  if (!r.split_families.count("holdout")) return;
  const auto& held = r.split_families["holdout"];
  auto is_held = [&](const std::string& scene) {
    return std::find(held.begin(), held.end(), scene_family_of(scene)) != held.end();
  };
  std::string meta = (std::filesystem::path(root) / "metadata.txt").string();
  if (!d.has_holdout)
    sink.error(meta, "", "families.holdout names held-out families but the dataset has no holdout/ folder");
  for (const char* split : {"train", "test"})
    for (auto& scene : r.scenes[split])
      if (is_held(scene))
        sink.error(first_file[split][scene], "",
                   "scene '" + scene + "' belongs to family '" + scene_family_of(scene) +
                       "', held out in metadata.txt, but is in " + split + "/");
  for (auto& scene : r.scenes["holdout"])
    if (!is_held(scene))
      sink.error(first_file["holdout"][scene], "",
                 "scene '" + scene + "' is in holdout/ but its family '" + scene_family_of(scene) +
                     "' is not in metadata.txt's families.holdout");
}

}  // namespace

ValidationReport validate_dataset(const std::string& root, const ValidateOptions& o) {
  ValidationReport r;
  r.root = root;
  ProblemSink sink(r, o.max_problems);
  DatasetListing d;
  try {
    d = list_dataset(root);
  } catch (const std::exception& e) {
    sink.error("", "", e.what());
    return r;
  }
  r.flat = d.flat;
  for (auto& note : d.notes) sink.warn("", "", note);
  read_metadata(root, r, sink);

  FirstFiles first_file;
  if (d.flat) check_split("flat", d.train, o, sink, r, first_file);
  else check_split("train", d.train, o, sink, r, first_file), check_split("test", d.test, o, sink, r, first_file);
  if (!d.flat && d.has_holdout) check_split("holdout", d.holdout, o, sink, r, first_file);
  sink.set_split("");
  check_scenes_apart(d, r, sink, first_file);
  check_holdout_families(root, d, r, sink, first_file);
  if (!d.flat) check_split_counts(root, r, sink);

  int64_t total = 0;
  for (auto& [n, c] : r.views) total += c;
  for (auto& [n, c] : r.frames) total += c;
  if (total == 0) sink.error(root, "", "no views found (expected train/*.exr and test/*.exr, or *.exr)");
  return r;
}

void print_report(std::FILE* out, const ValidationReport& r) {
  std::fprintf(out, "dataset %s (%s)\n", r.root.c_str(),
               r.flat                     ? "flat: no train/ test/ split"
               : r.views.count("holdout") ? "train/ + test/ + holdout/"
                                          : "train/ + test/");
  for (const char* split : {"train", "test", "holdout", "flat"}) {
    if (!r.views.count(split)) continue;
    const int64_t n = r.views.at(split);
    std::fprintf(out, "  %-6s %lld views, %lld surround frames, %zu scenes", split, (long long)n,
                 (long long)r.frames.at(split), r.scenes.count(split) ? r.scenes.at(split).size() : size_t(0));
    if (r.scenes.count(split)) {
      std::string names;
      int shown = 0;
      for (auto& s : r.scenes.at(split)) {
        if (shown++ == 8) {
          names += ", ...";
          break;
        }
        names += (names.empty() ? "" : ", ") + s;
      }
      std::fprintf(out, ": %s", names.c_str());
    }
    std::fprintf(out, "\n");
  }
  if (r.has_metadata) {
    auto get = [&](const std::string& k) { return r.metadata.count(k) ? r.metadata.at(k) : std::string("-"); };
    std::fprintf(out, "  metadata.txt: preset %s, seed %s\n", get("preset").c_str(), get("seed").c_str());
    for (auto& [split, fams] : r.split_families) {
      std::string names;
      for (auto& f : fams) names += (names.empty() ? "" : ", ") + f;
      std::fprintf(out, "    families in %s/: %s\n", split.c_str(), names.c_str());
    }
    if (r.split_families.count("holdout"))
      std::fprintf(out, "    held out (leave-families-out): %zu families, only in holdout/\n",
                   r.split_families.at("holdout").size());
    if (r.metadata.count("view-variation"))
      std::fprintf(out, "    view variation: %s\n", r.metadata.at("view-variation").c_str());
  }
  std::string res;
  if (r.resolutions.size() <= 8) {
    for (auto& [wh, n] : r.resolutions) res += (res.empty() ? "" : ", ") + wh + " (" + std::to_string(n) + " files)";
  } else {  // nnao-v2 gives nearly every view its own size: a range says more than a list
    int64_t files = 0, wmin = INT64_MAX, wmax = 0, hmin = INT64_MAX, hmax = 0;
    for (auto& [wh, n] : r.resolutions) {
      int64_t w = std::stoll(wh.substr(0, wh.find('x'))), h = std::stoll(wh.substr(wh.find('x') + 1));
      files += n, wmin = std::min(wmin, w), wmax = std::max(wmax, w), hmin = std::min(hmin, h),
                  hmax = std::max(hmax, h);
    }
    res = std::to_string(r.resolutions.size()) + " sizes over " + std::to_string(files) + " files, width " +
          std::to_string(wmin) + "-" + std::to_string(wmax) + ", height " + std::to_string(hmin) + "-" +
          std::to_string(hmax);
  }
  std::fprintf(out, "  resolutions: %s\n", res.empty() ? "none" : res.c_str());
  std::fprintf(out, "  channels:       files        min        max\n");
  for (auto& [ch, s] : r.channels) {
    std::fprintf(out, "    %-10s %7lld", ch.c_str(), (long long)s.files);
    if (s.any_finite) std::fprintf(out, " %10.4g %10.4g", s.min, s.max);
    else std::fprintf(out, " %10s %10s", "-", "-");
    if (ch == "Z" && s.pixels) std::fprintf(out, "   sky %.1f%%", 100.0 * double(s.sky) / double(s.pixels));
    std::fprintf(out, "\n");
  }
  if (!r.problems.empty()) std::fprintf(out, "problems:\n");
  for (auto& p : r.problems) std::fprintf(out, "  %s\n", p.str().c_str());
  int64_t hidden = r.errors + r.warnings - int64_t(r.problems.size());
  if (hidden > 0) std::fprintf(out, "  ... and %lld more (raise --max-problems)\n", (long long)hidden);
  if (r.clean()) std::fprintf(out, "OK: no problems found (%lld warnings)\n", (long long)r.warnings);
  else std::fprintf(out, "FAILED: %lld problems found, %lld warnings\n", (long long)r.errors, (long long)r.warnings);
}

}  // namespace nns::data
