#pragma once
// gi-infer: a trained generator on one frame that has no ground truth.
//
//   InferResult r = infer_gi({.model = "gan-out/G.blob", .in = "frame7", .out = "f7.exr"});
//
// The frame is a single G-buffer view (front-mode model) or a folder of six faces,
// front/back/left/right/up/down.exr (surround model); a front-mode model given a folder
// takes its front.exr and says so. Each view must meet the dataset contract of a
// surround face (docs/dataset-format.md: Z, N.*, albedo.*, direct.*, emission/env
// optional, no ground truth needed) and is box-filtered to the model's face size by an
// integer factor exactly as training and eval-gi do (gi_samples.h), so the prediction is
// eval-gi's prediction for the same frame. The output is at the input's size: a frame
// larger than the model's faces gets the prediction's indirect light brought up by the
// guided upsample (models/gi/upsampled_light.h, eval-gi's --upsample-from), the way an
// engine brings up half-resolution GI; --output-size model keeps the model's size.
// Instead of view EXRs, the frame can be a user's own images (--channel), one file per
// input or several inputs from one file: for a front-mode model one view
// (data/image_read.h: depth=FILE ...), for a surround model six faces
// (data/frame_images.h: front.depth=FILE, back.normal=FILE, ...; 90 degrees). The faces
// from images take the very path of the folder's faces (sizes, check_input,
// downsample_view, assemble_surround), so the prediction is the same for the same data.
//
// Output, all written to temporary names and renamed only once everything succeeded
// (an error leaves no output at all):
//   OUT.exr           light.R/G/B     predicted total diffuse light (direct + env + indirect)
//                     indirect.R/G/B  light - (direct + env), signed (see below)
//                     shaded.R/G/B    albedo * light + emission, the lit image
//                     Z               the input's depth at the output size (the input's, or
//                                     the model's with --output-size model)
//                     header: fovY, scene (and worldToCamera) of the input's front view
//   OUT_shaded.png, OUT_indirect.png  previews (exposure 1/k, the model's HDR scale)
// Negative indirect light: the true indirect light is >= 0, but the network predicts the
// total light, which can fall below direct + env. The EXR keeps the signed difference,
// so light = direct + env + indirect holds and the shortfall stays visible; the PNG
// clamps it at 0; InferResult counts the geometry pixels where it happened.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <vector>

#include "data/dataset.h"
#include "data/exr_io.h"
#include "data/frame_images.h"
#include "data/image_read.h"
#include "data/validate.h"
#include "models/gi/gi_model_io.h"
#include "models/gi/upsampled_light.h"
#include "runs/gi/gi_samples.h"
#include "runs/gi/gi_previews.h"
#include "runs/gi/model_light.h"

namespace nns::runs {

struct InferOptions {
  std::string model, in;
  // Instead of `in`: the frame from a user's images; targets FACE.TARGET for a surround
  // model (data/frame_images.h), TARGET for a front-mode one (data/image_read.h).
  std::vector<data::ChannelMapping> channels;
  data::ImageViewOptions images;
  std::string out;             // "": <name of the input>_gi.exr in the current folder
  bool bn_batch_stats = true;  // test-time BatchNorm, as eval-gi (docs/gan.md)
  bool dropout_on = false;
  bool mirror_average = false;  // the light averaged with the mirrored frame's (model_light.h)
  // Faces larger than the model's: true, the output at their size (guided upsample of the
  // indirect light); false, at the model's face size.
  bool output_at_input_size = true;
};

struct InferResult {
  std::string exr, shaded_png, indirect_png;
  std::string mode;                          // the model's: front | surround
  std::string front_file;                    // the view whose light was predicted
  int in_width = 0, in_height = 0;           // the front view as stored
  int width = 0, height = 0, reduction = 1;  // the output's size; the input's box filter
  bool upsampled = false;                    // the indirect light brought up to the input's size
  std::vector<std::string> notes;            // e.g. the front.exr a front-mode model used
  int64_t geometry_pixels = 0;
  int64_t negative_indirect_pixels = 0;  // geometry pixels with some indirect channel < 0
  float min_indirect = 0;
  double ms = 0;           // the network alone
  double upsample_ms = 0;  // the guided upsample (0 without)
};

namespace infer_detail {

// What view_planes and fill_front_shading read from every view; emission and env are
// optional (zero when absent), indirect is the ground truth gi-infer does without.
inline const std::vector<std::string>& required_channels() {
  static const std::vector<std::string> c = {"Z",        "N.X",      "N.Y",      "N.Z",      "albedo.R",
                                             "albedo.G", "albedo.B", "direct.R", "direct.G", "direct.B"};
  return c;
}

// Every missing channel in one message, then the errors of the dataset contract (NaN or
// Inf, NaN or non-positive depth, non-unit normals, header attributes): the checks
// training ran on its data (data/validate.h), so the network sees inputs of the kind it
// learned from. The contract's warnings (albedo outside [0, 1], negative light) pass, as
// they do for training.
inline void check_input(const data::View& v) {
  std::string missing;
  for (auto& c : required_channels())
    if (!v.has(c)) missing += (missing.empty() ? "'" : ", '") + c + "'";
  if (!missing.empty())
    throw std::runtime_error(v.source + ": missing channel " + missing +
                             " (the GI model's inputs: Z, N.X/Y/Z, albedo.R/G/B, direct.R/G/B; "
                             "emission and env are optional)");
  data::ValidationReport report;
  data::ValidateOptions o;
  o.purpose = data::Purpose::gi;
  data::ProblemSink sink(report, 5);
  data::check_view(v, nullptr, /*is_front=*/false, o, sink);
  if (report.errors == 0) return;
  std::string msg = v.source + ": not a valid G-buffer view (" + std::to_string(report.errors) + " problem" +
                    (report.errors == 1 ? "" : "s") + "; `dataset-info` lists them all):";
  for (auto& p : report.problems)
    if (!p.warning) msg += "\n  " + p.str();
  throw std::runtime_error(msg);
}

// The integer box reduction of gi_samples.h's reduction_for, with a message that names the
// sizes (gi-infer has no --size flag: the size is the model's).
inline int reduction_to_model(const data::View& v, int size, const std::string& model) {
  if (size <= 0) return 1;  // a model trained on views as stored
  const std::string got = std::to_string(v.width) + "x" + std::to_string(v.height);
  const std::string want = std::to_string(size);
  const bool fits = (v.width == v.height || v.width == size) && v.width >= size && v.width % size == 0;
  if (!fits)
    throw std::runtime_error(v.source + ": view is " + got + " but the model " + model + " takes faces of " + want +
                             "x" + want +
                             "; gi-infer only box-filters square views down by an "
                             "integer factor (sizes " +
                             want + ", " + std::to_string(2 * size) + ", " + std::to_string(3 * size) +
                             ", ...), it never enlarges or crops");
  return reduction_for(v, size, v.source);
}

inline std::string default_out(const std::string& in) {
  std::filesystem::path p = std::filesystem::path(in).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();  // "frame7/" -> "frame7"
  std::string name = std::filesystem::is_directory(in) ? p.filename().string() : p.stem().string();
  return (name.empty() || name == "." || name == ".." ? std::string("frame") : name) + "_gi.exr";
}

// OUT.exr and its two PNGs, named after the input (the depth image, when the frame
// comes from images) unless --out names them.
inline void name_outputs(const InferOptions& o, InferResult& r) {
  std::string in = o.in;
  if (!o.channels.empty()) {
    for (auto& m : o.channels)
      if (m.target == "depth" || m.target == "front.depth") in = m.file;
    if (in.empty()) in = o.channels[0].file;
  }
  r.exr = o.out.empty() ? default_out(in) : o.out;
  if (r.exr.size() < 5 || r.exr.compare(r.exr.size() - 4, 4, ".exr") != 0)
    throw std::runtime_error(r.exr + ": the output must be an .exr file name");
  const std::string stem = r.exr.substr(0, r.exr.size() - 4);
  r.shaded_png = stem + "_shaded.png";
  r.indirect_png = stem + "_indirect.png";
}

inline gi::LoadedGenerator load_named_generator(const std::string& model) {
  try {
    return gi::load_generator(model);
  } catch (const std::exception& e) {
    std::string what = e.what();
    throw std::runtime_error(what.find(model) == std::string::npos ? model + ": cannot load the generator: " + what
                                                                   : what);
  }
}

// The network's input and the front view the output is aligned with; `inputs`: every
// file read, so the output cannot overwrite one; `full_front`: the front view as read,
// before the box filter.
struct FrameInput {
  gi::GiSample sample;
  data::View front, full_front;
  std::vector<std::string> inputs;
};

inline FrameInput read_surround_input(const InferOptions& o, const gi::GiInputConfig& cfg, bool folder,
                                      InferResult& r) {
  FrameInput in;
  std::array<data::View, 6> faces;
  std::string frame_name = o.in;
  if (!o.channels.empty()) {
    try {
      faces = data::frame_from_images(o.channels, o.images);  // sizes checked as read_frame's
    } catch (const std::exception& e) {
      throw std::runtime_error(o.model + " is a surround model: " + e.what());
    }
    for (auto& m : o.channels) in.inputs.push_back(m.file);
    frame_name = r.front_file = faces[0].source;
  } else {
    if (!folder)
      throw std::runtime_error(o.in + ": the model " + o.model +
                               " is a surround model; it needs a folder "
                               "of six faces (front.exr, back.exr, left.exr, right.exr, up.exr, down.exr), "
                               "not a single view, or the faces as images: --channel FACE.TARGET=FILE");
    data::FrameEntry e = data::frame_entry(o.in);
    if (!e.complete()) {
      std::string names;
      for (auto& m : e.missing) names += (names.empty() ? "" : ", ") + m + ".exr";
      throw std::runtime_error(o.in + ": a surround frame needs six faces; missing " + names);
    }
    faces = data::read_frame(e);  // same size, square, or an error naming the face
    in.inputs.assign(e.faces.begin(), e.faces.end());
    r.front_file = e.faces[0];
  }
  for (auto& f : faces) check_input(f);
  r.in_width = faces[0].width, r.in_height = faces[0].height;
  r.reduction = reduction_to_model(faces[0], cfg.size, o.model);
  in.full_front = faces[0];
  for (auto& f : faces) f = downsample_view(f, r.reduction);
  in.sample = assemble_surround(faces, cfg, frame_name, /*targets=*/false);
  in.front = faces[0];
  return in;
}

inline FrameInput read_front_input(const InferOptions& o, const gi::GiInputConfig& cfg, bool folder, InferResult& r) {
  namespace fs = std::filesystem;
  const bool from_images = !o.channels.empty();
  for (auto& m : o.channels)
    if (data::face_prefixed(m))
      throw std::runtime_error("--channel '" + m.text + "': the model " + o.model +
                               " is a front-mode model "
                               "and reads one view; give its targets without a face (--channel depth=FILE, "
                               "normal=FILE, ...): FACE.TARGET is for surround models");
  std::string path = o.in;
  if (folder) {
    std::error_code ec;
    path = (fs::path(o.in) / "front.exr").string();
    if (!fs::is_regular_file(path, ec))
      throw std::runtime_error(o.in + ": the model " + o.model +
                               " is a front-mode model and reads one view; "
                               "the folder has no front.exr");
    r.notes.push_back("front-mode model: using " + path + " (the other faces are not inputs of this model)");
  }
  data::View v = from_images ? data::view_from_images(o.channels, o.images) : data::read_view(path);
  if (from_images) path = v.source;
  check_input(v);
  r.in_width = v.width, r.in_height = v.height;
  r.reduction = reduction_to_model(v, cfg.size, o.model);
  FrameInput in;
  in.front = downsample_view(v, r.reduction);
  in.full_front = std::move(v);
  in.sample = assemble_front(in.front, cfg, /*targets=*/false);
  in.sample.name = path;
  if (from_images)
    for (auto& m : o.channels) in.inputs.push_back(m.file);
  else in.inputs.push_back(path);
  r.front_file = path;
  return in;
}

inline void refuse_overwriting_inputs(const std::vector<std::string>& inputs, const InferResult& r) {
  namespace fs = std::filesystem;
  std::error_code ec;
  for (auto& in : inputs)
    for (auto* target : {&r.exr, &r.shaded_png, &r.indirect_png})
      if (fs::exists(*target, ec) && fs::equivalent(*target, in, ec))
        throw std::runtime_error(*target + ": is an input of this run; choose another --out");
}

// The network alone, timed.
inline Tensor<float> predict_light(const InferOptions& o, gi::LoadedGenerator& g, const gi::GiSample& s,
                                   InferResult& r) {
  auto t0 = std::chrono::steady_clock::now();
  Tensor<float> light;
  try {
    light = model_light(g, s, o.bn_batch_stats, o.dropout_on, o.mirror_average);
  } catch (const std::exception& e) {
    throw std::runtime_error((!o.channels.empty() ? r.front_file : o.in) + ": the model " + o.model +
                             " cannot run on this " + std::to_string(s.input.size(3)) + "x" +
                             std::to_string(s.input.size(2)) + " input (" + e.what() + ")");
  }
  r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return light;
}

// The frame at the input's size, `light` (predicted at the model's) brought up to it by the
// guided upsample; the shading planes (albedo, emission, direct + env) become the input's own.
inline Tensor<float> upsample_to_input(FrameInput& in, const Tensor<float>& light, InferResult& r) {
  auto t0 = std::chrono::steady_clock::now();
  gi::GiSample full;
  full.name = in.sample.name;
  full.scene = in.sample.scene;
  full.front_geometry = gi::geometry_of(in.full_front);
  gi::fill_front_shading(full, in.full_front);
  Tensor<float> up = gi::upsampled_light(light, in.sample, full);
  in.sample = std::move(full);
  in.front = std::move(in.full_front);
  r.upsampled = true;
  r.upsample_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return up;
}

// The output view (light, signed indirect, shaded, Z) and the two previews' planes.
struct LightOutputs {
  data::View exr;
  std::vector<float> shaded, indirect_png;  // (3, h, w), the PNGs' indirect clamped at 0
};

inline LightOutputs light_outputs(const InferOptions& o, const Tensor<float>& light, const FrameInput& in,
                                  InferResult& r) {
  const gi::GiSample& s = in.sample;
  const data::View& front = in.front;
  const int w = front.width, h = front.height;
  const int64_t n = int64_t(w) * h;
  r.width = w, r.height = h;
  LightOutputs out;
  data::View& v = out.exr;
  v.width = w, v.height = h;
  v.fov_y_deg = front.fov_y_deg;
  v.scene = front.scene;
  v.world_to_camera = front.world_to_camera;
  v.channels["Z"] = front.channel("Z");
  out.indirect_png.resize(size_t(3 * n));
  out.shaded.resize(size_t(3 * n));
  r.min_indirect = INFINITY;
  std::vector<uint8_t> negative(size_t(n), 0);
  for (int c = 0; c < 3; ++c) {
    const std::string ch(1, "RGB"[c]);
    auto &L = v.add_channel("light." + ch), &I = v.add_channel("indirect." + ch), &S = v.add_channel("shaded." + ch);
    for (int64_t i = 0; i < n; ++i) {
      const int64_t k = c * n + i;
      const float l = light[k];
      if (!std::isfinite(l))
        throw std::runtime_error(o.model + ": predicted a non-finite light at pixel " + std::to_string(i % w) + "," +
                                 std::to_string(i / w) + " of " + r.front_file);
      L[size_t(i)] = l;
      I[size_t(i)] = l - s.direct_env[k];
      S[size_t(i)] = s.albedo[k] * l + s.emission[k];
      out.shaded[size_t(k)] = S[size_t(i)];
      out.indirect_png[size_t(k)] = std::max(I[size_t(i)], 0.0f);
      if (s.geometry[size_t(i)]) {
        r.min_indirect = std::min(r.min_indirect, I[size_t(i)]);
        if (I[size_t(i)] < 0) negative[size_t(i)] = 1;
      }
    }
  }
  for (int64_t i = 0; i < n; ++i) {
    r.geometry_pixels += s.geometry[size_t(i)];
    r.negative_indirect_pixels += negative[size_t(i)];
  }
  if (r.geometry_pixels == 0) r.min_indirect = 0;
  return out;
}

// The EXR and its two PNGs together (core/atomic_file.h): all three or none.
inline void write_outputs_together(const LightOutputs& out, float hdr_scale, const InferResult& r) {
  const std::filesystem::path parent = std::filesystem::path(r.exr).parent_path();
  try {
    if (!parent.empty()) std::filesystem::create_directories(parent);
    const gi::HdrMapping hdr(hdr_scale);
    write_paths_atomic({r.exr, r.shaded_png, r.indirect_png}, [&](size_t i, const std::string& tmp) {
      if (i == 0) data::write_view(tmp, out.exr);
      if (i == 1) write_light_png(tmp, out.shaded.data(), r.width, r.height, hdr);
      if (i == 2) write_light_png(tmp, out.indirect_png.data(), r.width, r.height, hdr);
    });
  } catch (const std::exception& e) {
    throw std::runtime_error(r.exr + ": cannot write the output (" + e.what() + "); nothing was written");
  }
}

}  // namespace infer_detail

inline InferResult infer_gi(const InferOptions& o) {
  namespace fs = std::filesystem;
  using namespace infer_detail;
  const bool from_images = !o.channels.empty();
  if (from_images == !o.in.empty())
    throw std::runtime_error("give the frame either as --in or as --channel images, not " +
                             std::string(from_images ? "both" : "neither"));
  InferResult r;
  name_outputs(o, r);
  // What a killed earlier run into these names left (the folder is the user's: only
  // our three names' temporaries).
  for (const std::string& f : {r.exr, r.shaded_png, r.indirect_png}) remove_stale_temporaries_of(f);
  gi::LoadedGenerator g = load_named_generator(o.model);
  r.mode = gi::mode_name(g.inputs.mode);
  std::error_code ec;
  if (!from_images && !fs::exists(o.in, ec)) throw std::runtime_error(o.in + ": no such file or folder");
  const bool folder = !from_images && fs::is_directory(o.in, ec);
  FrameInput in = g.inputs.mode == gi::GiMode::surround ? read_surround_input(o, g.inputs, folder, r)
                                                        : read_front_input(o, g.inputs, folder, r);
  refuse_overwriting_inputs(in.inputs, r);
  Tensor<float> light = predict_light(o, g, in.sample, r);
  if (r.reduction > 1 && o.output_at_input_size) light = upsample_to_input(in, light, r);
  write_outputs_together(light_outputs(o, light, in, r), g.inputs.norm.hdr_scale, r);
  return r;
}

}  // namespace nns::runs
