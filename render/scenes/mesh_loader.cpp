#include "render/scenes/mesh_loader.h"

#include <tiny_gltf.h>
#include <tiny_obj_loader.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>

namespace nns::render {

namespace {
std::runtime_error error(const std::string& path, const std::string& what) {
  return std::runtime_error(path + ": " + what);
}

// tinyobjloader reads "nan", "inf" or "abc" as a vertex coordinate of 0 and says
// nothing; refuse them before it does, naming the line.
void check_obj_vertices(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int64_t no = 1; std::getline(in, line); ++no) {
    size_t p = line.find_first_not_of(" \t");
    if (p == std::string::npos || line[p] != 'v' || p + 1 >= line.size() || (line[p + 1] != ' ' && line[p + 1] != '\t'))
      continue;
    std::istringstream tokens(line.substr(p + 1));
    std::string tok;
    for (int k = 0; k < 3 && tokens >> tok; ++k) {
      char* end = nullptr;
      double x = std::strtod(tok.c_str(), &end);
      if (end != tok.c_str() + tok.size())
        throw error(path, "line " + std::to_string(no) + ": vertex coordinate '" + tok + "' is not a number");
      if (!std::isfinite(x))
        throw error(path, "line " + std::to_string(no) + ": vertex coordinate '" + tok + "' is non-finite");
    }
  }
}

void load_obj(const std::string& path, Scene& s) {
  check_obj_vertices(path);
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = true;
  cfg.mtl_search_path = std::filesystem::path(path).parent_path().string();
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, cfg)) throw error(path, "cannot read OBJ: " + reader.Error());
  const auto& attrib = reader.GetAttrib();
  for (size_t i = 0; i + 2 < attrib.vertices.size(); i += 3)
    s.positions.push_back({attrib.vertices[i], attrib.vertices[i + 1], attrib.vertices[i + 2]});
  uint32_t fallback = s.add_material({});
  uint32_t first = uint32_t(s.materials.size());
  for (auto& m : reader.GetMaterials())
    s.add_material({{float(m.diffuse[0]), float(m.diffuse[1]), float(m.diffuse[2])},
                    {float(m.emission[0]), float(m.emission[1]), float(m.emission[2])}});
  for (auto& shape : reader.GetShapes()) {
    const auto& mesh = shape.mesh;
    for (size_t f = 0; f * 3 + 2 < mesh.indices.size(); ++f) {
      int mid = f < mesh.material_ids.size() ? mesh.material_ids[f] : -1;
      Triangle t{{uint32_t(mesh.indices[3 * f].vertex_index), uint32_t(mesh.indices[3 * f + 1].vertex_index),
                  uint32_t(mesh.indices[3 * f + 2].vertex_index)},
                 mid >= 0 ? first + uint32_t(mid) : fallback};
      s.triangles.push_back(t);
    }
  }
}

// Column-major 4x4 (glTF's layout) applied to a point.
using Mat4 = std::array<double, 16>;
Mat4 mul(const Mat4& a, const Mat4& b) {
  Mat4 r{};
  for (int c = 0; c < 4; ++c)
    for (int rr = 0; rr < 4; ++rr)
      for (int k = 0; k < 4; ++k) r[c * 4 + rr] += a[k * 4 + rr] * b[c * 4 + k];
  return r;
}
Mat4 node_matrix(const tinygltf::Node& n) {
  Mat4 m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  if (n.matrix.size() == 16) {
    for (int i = 0; i < 16; ++i) m[i] = n.matrix[i];
    return m;
  }
  Mat4 t = m, r = m, sc = m;
  if (n.translation.size() == 3) t[12] = n.translation[0], t[13] = n.translation[1], t[14] = n.translation[2];
  if (n.rotation.size() == 4) {
    double x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
    r = {1 - 2 * (y * y + z * z),
         2 * (x * y + z * w),
         2 * (x * z - y * w),
         0,
         2 * (x * y - z * w),
         1 - 2 * (x * x + z * z),
         2 * (y * z + x * w),
         0,
         2 * (x * z + y * w),
         2 * (y * z - x * w),
         1 - 2 * (x * x + y * y),
         0,
         0,
         0,
         0,
         1};
  }
  if (n.scale.size() == 3) sc[0] = n.scale[0], sc[5] = n.scale[1], sc[10] = n.scale[2];
  return mul(t, mul(r, sc));
}

// Reads accessor element i, component c, as a double (float or integer components).
double read_component(const tinygltf::Model& model, const tinygltf::Accessor& acc, size_t i, int c) {
  const auto& view = model.bufferViews.at(size_t(acc.bufferView));
  const auto& buf = model.buffers.at(size_t(view.buffer));
  int stride = acc.ByteStride(view);
  int size = tinygltf::GetComponentSizeInBytes(uint32_t(acc.componentType));
  if (stride <= 0 || size <= 0) throw std::out_of_range("accessor with an invalid type or stride");
  size_t off = view.byteOffset + acc.byteOffset + i * size_t(stride) + size_t(c) * size_t(size);
  if (off + size_t(size) > buf.data.size()) throw std::out_of_range("accessor reads past its buffer");
  const unsigned char* p = buf.data.data() + off;
  switch (acc.componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return *p;
    default:
      throw std::runtime_error("unsupported accessor component type " + std::to_string(acc.componentType));
  }
}

// tinygltf's own reader opens whatever a buffer's "uri" names and sizes it by seeking
// to the end: a directory (uri "data" beside a dataset folder) reads as 2^63 - 1 bytes
// and the allocation aborts the process (found by fuzz/fuzz_scene.cpp). Only regular
// files of a sane size are read; anything else is an error that names the file.
constexpr uintmax_t kMaxGltfFileBytes = uintmax_t(4) << 30;
bool read_regular_file(std::vector<unsigned char>* out, std::string* err, const std::string& file, void*) {
  std::error_code ec;
  auto fail = [&](const std::string& what) {
    if (err) *err += file + ": " + what + "\n";
    return false;
  };
  if (!std::filesystem::is_regular_file(file, ec)) return fail("not a regular file");
  const uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) return fail("cannot read its size");
  if (size > kMaxGltfFileBytes) return fail("larger than 4 GiB");
  std::ifstream in(file, std::ios::binary);
  out->resize(size_t(size));
  if (!in || !in.read(reinterpret_cast<char*>(out->data()), std::streamsize(size))) return fail("cannot be read");
  return true;
}

void load_gltf(const std::string& path, Scene& s) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks(
      {&tinygltf::FileExists, &tinygltf::ExpandFilePath, &read_regular_file, &tinygltf::WriteWholeFile, nullptr});
  std::string err, warn;
  bool binary = std::filesystem::path(path).extension() == ".glb";
  bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                   : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok) throw error(path, "cannot read glTF: " + err);
  uint32_t fallback = s.add_material({});
  uint32_t first = uint32_t(s.materials.size());
  for (auto& m : model.materials) {
    auto& bc = m.pbrMetallicRoughness.baseColorFactor;
    Vec3 albedo = bc.size() >= 3 ? Vec3(float(bc[0]), float(bc[1]), float(bc[2])) : Vec3(0.7f);
    Vec3 emission = m.emissiveFactor.size() == 3
                        ? Vec3(float(m.emissiveFactor[0]), float(m.emissiveFactor[1]), float(m.emissiveFactor[2]))
                        : Vec3();
    s.add_material({albedo, emission});
  }
  // glTF nodes form a forest: a node reached a second time (its own ancestor, or a child
  // of two parents) would recurse forever or multiply the work of its subtree.
  std::vector<uint8_t> reached(model.nodes.size(), 0);
  int depth = 0;
  std::function<void(int, const Mat4&)> visit = [&](int node_index, const Mat4& parent) {
    const tinygltf::Node& node = model.nodes.at(size_t(node_index));
    if (reached[size_t(node_index)]++)
      throw error(path, "node " + std::to_string(node_index) +
                            " is reached twice in the node hierarchy (a cycle, or two parents)");
    if (++depth > 256) throw error(path, "node hierarchy deeper than 256 levels");
    Mat4 world = mul(parent, node_matrix(node));
    if (node.mesh >= 0) {
      for (const auto& prim : model.meshes.at(size_t(node.mesh)).primitives) {
        if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) continue;
        auto it = prim.attributes.find("POSITION");
        if (it == prim.attributes.end()) continue;
        const auto& pos = model.accessors.at(size_t(it->second));
        uint32_t base = uint32_t(s.positions.size());
        for (size_t i = 0; i < pos.count; ++i) {
          double x = read_component(model, pos, i, 0), y = read_component(model, pos, i, 1),
                 z = read_component(model, pos, i, 2);
          s.positions.push_back({float(world[0] * x + world[4] * y + world[8] * z + world[12]),
                                 float(world[1] * x + world[5] * y + world[9] * z + world[13]),
                                 float(world[2] * x + world[6] * y + world[10] * z + world[14])});
        }
        uint32_t mat = prim.material >= 0 ? first + uint32_t(prim.material) : fallback;
        if (prim.indices >= 0) {
          const auto& idx = model.accessors.at(size_t(prim.indices));
          // glTF's indices are unsigned integers; a float accessor read as one made an
          // out-of-range float-to-integer conversion (undefined behaviour) before the
          // vertex check below could refuse it.
          if (idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
              idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
              idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            throw error(path, "the triangle indices (accessor " + std::to_string(prim.indices) +
                                  ") are not unsigned integers (component type " + std::to_string(idx.componentType) +
                                  ")");
          auto vertex = [&](size_t i) {
            const double v = read_component(model, idx, i, 0);
            if (v >= double(pos.count))
              throw error(path, "triangle index " + std::to_string(uint64_t(v)) + " (accessor " +
                                    std::to_string(prim.indices) + ") is past its primitive's " +
                                    std::to_string(pos.count) + " vertices");
            return base + uint32_t(v);
          };
          for (size_t t = 0; t + 2 < idx.count; t += 3)
            s.triangles.push_back({{vertex(t), vertex(t + 1), vertex(t + 2)}, mat});
        } else {
          for (uint32_t t = 0; t + 2 < pos.count; t += 3)
            s.triangles.push_back({{base + t, base + t + 1, base + t + 2}, mat});
        }
      }
    }
    for (int child : node.children) visit(child, world);
    --depth;
  };
  const Mat4 identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  if (!model.scenes.empty()) {
    const auto& sc = model.scenes.at(size_t(model.defaultScene >= 0 ? model.defaultScene : 0));
    for (int n : sc.nodes) visit(n, identity);
  } else {
    // No scene: every node that is nobody's child is a root.
    std::vector<uint8_t> is_child(model.nodes.size(), 0);
    for (auto& node : model.nodes)
      for (int c : node.children)
        if (c >= 0 && size_t(c) < is_child.size()) is_child[size_t(c)] = 1;
    for (size_t n = 0; n < model.nodes.size(); ++n)
      if (!is_child[n]) visit(int(n), identity);
  }
}
}  // namespace

Scene load_mesh_scene(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw error(path, "no such file");
  Scene s;
  s.name = mesh_scene_name(path);
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& c : ext) c = char(std::tolower(c));
  try {
    if (ext == ".obj") load_obj(path, s);
    else if (ext == ".gltf" || ext == ".glb") load_gltf(path, s);
    else throw error(path, "unsupported scene format '" + ext + "' (expected .obj, .gltf or .glb)");
  } catch (const std::out_of_range& e) {
    throw error(path, std::string("malformed file: ") + e.what());
  } catch (const std::runtime_error& e) {
    // Every reader error names the file (fuzz_scene found a glTF accessor type that did not).
    const std::string m = e.what();
    if (m.rfind(path, 0) == 0) throw;
    throw error(path, m);
  }
  if (s.triangles.empty()) throw error(path, "no triangles");
  for (size_t i = 0; i < s.positions.size(); ++i) {
    const Vec3& p = s.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw error(path, "vertex " + std::to_string(i + 1) + " has a non-finite coordinate (" + std::to_string(p.x) +
                            ", " + std::to_string(p.y) + ", " + std::to_string(p.z) + ")");
  }
  for (auto& t : s.triangles)
    for (uint32_t v : t.v)
      if (v >= s.positions.size()) throw error(path, "a face refers to a vertex that does not exist");
  Vec3 lo, hi;
  s.bounds(lo, hi);
  Vec3 ext3 = hi - lo;
  float diag = length(ext3);
  s.ao_radius = diag >= 10 ? 1.0f : diag / 10;
  s.cameras.min = lo + Vec3(ext3.x * 0.15f, ext3.y * 0.1f, ext3.z * 0.15f);
  s.cameras.max = hi - Vec3(ext3.x * 0.15f, ext3.y * 0.4f, ext3.z * 0.15f);
  float el = 50 * 3.14159265f / 180, az = 0.5f;
  s.suns.push_back(
      {{std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az)}, {3, 2.9f, 2.7f}, 0.0093f});
  s.sky = Sky{{0.25f, 0.45f, 0.9f}, {0.7f, 0.8f, 0.95f}, {0.15f, 0.13f, 0.1f}};
  return s;
}

std::string mesh_scene_name(const std::string& path) { return std::filesystem::path(path).stem().string(); }

void check_unique_scene_names(const std::vector<std::string>& paths) {
  std::map<std::string, std::string> first;  // name -> file
  for (auto& p : paths) {
    auto [it, fresh] = first.emplace(mesh_scene_name(p), p);
    if (!fresh)
      throw std::invalid_argument("scene files '" + it->second + "' and '" + p + "' both give the scene name '" +
                                  it->first + "' (the file name without its extension); rename one of them");
  }
}

}  // namespace nns::render
