#pragma once
// Mesh scenes for `render-dataset --scene FILE`: Wavefront OBJ (tinyobjloader, with
// its .mtl: Kd -> albedo, Ke -> emission) and glTF 2.0 .gltf/.glb (tinygltf: the
// default scene's node hierarchy, baseColorFactor -> albedo, emissiveFactor ->
// emission; textures are ignored). Normals are the flat geometric ones.
//
// A mesh file carries no lights the renderer understands, so the scene gets a sun
// (elevation 50 deg) and a gradient sky; cameras go anywhere inside the middle of the
// bounding box. aoRadius is 1 scene unit, or a tenth of the bounding-box diagonal if
// the scene is smaller than 10 units across.
#include <string>
#include <vector>

#include "render/scene.h"

namespace nns::render {

// Throws "<file>: <problem>" for unreadable, unsupported or empty files, and for
// vertices that are not finite (after the glTF node transforms).
Scene load_mesh_scene(const std::string& path);

// The scene name a mesh file gets: its file name without the extension.
std::string mesh_scene_name(const std::string& path);

// Views are named and split by scene, so two files with one name (a/scene.obj,
// b/scene.gltf) would merge into one scene that lands in both splits: throws naming
// both files.
void check_unique_scene_names(const std::vector<std::string>& paths);

}  // namespace nns::render
