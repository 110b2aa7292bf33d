// OBJ meshes through tinyobjloader: positions, normals, UVs and per-face materials.
#pragma once
#include <functional>
#include <string>

#include "texr/scene/scene.h"

namespace texr {

// Resolves an OBJ material (by its name and its .mtl data) to an index in Scene::materials.
struct ObjMaterialInfo {
    std::string name;
    bool described = false;  // a .mtl file describes it (diffuse and diffuse_texture are its)
    std::string mtl_file;    // that .mtl file's path (described)
    Color diffuse{1.0f};
    std::string diffuse_texture;  // map_Kd, its path resolved from the .mtl file's folder
};
using ObjMaterialResolver = std::function<int(const ObjMaterialInfo&)>;

// Loads `path` as a Mesh. Faces are triangulated; vertices are split by (position, normal,
// uv) index triple. `resolve` gives each face's material (called once per OBJ material and
// once with an empty name for faces without one). Throws InputError on unreadable files.
Mesh load_obj(const std::string& path, const ObjMaterialResolver& resolve);

}  // namespace texr
