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

#include "render/scene.h"

namespace nns::data {

// Throws "<file>: <problem>" for unreadable, unsupported or empty files.
Scene load_mesh_scene(const std::string& path);

}  // namespace nns::data
