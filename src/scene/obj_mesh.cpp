// OBJ loading with tinyobjloader (see include/texr/scene/obj_mesh.h).
#include "texr/scene/obj_mesh.h"

#include <tiny_obj_loader.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include "texr/core/error.h"

namespace texr {

namespace {

std::string folder_of(const std::string& path) {
    const auto slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

// First line of tinyobjloader's message, without its trailing newline.
std::string first_line(const std::string& text) {
    const auto end = text.find('\n');
    return end == std::string::npos ? text : text.substr(0, end);
}

// The `usemtl` name in force for each triangle, in file order (a face of k vertices is k - 2
// triangles, as tinyobjloader triangulates it).
std::vector<std::string> usemtl_per_triangle(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> names;
    std::string line, current;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword == "usemtl") {
            std::getline(words >> std::ws, current);
            while (!current.empty() && (current.back() == '\r' || current.back() == ' ')) current.pop_back();
        } else if (keyword == "f") {
            std::size_t corners = 0;
            for (std::string corner; words >> corner && corner[0] != '#';) ++corners;
            for (std::size_t k = 2; k < corners; ++k) names.push_back(current);
        }
    }
    return names;
}

}  // namespace

Mesh load_obj(const std::string& path, const ObjMaterialResolver& resolve) {
    if (!std::ifstream(path)) throw InputError(path, 0, "cannot open OBJ file");
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    config.mtl_search_path = folder_of(path);
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config))
        throw InputError(path, 0, "not a readable OBJ file: " + first_line(reader.Error()));

    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    const auto& obj_materials = reader.GetMaterials();

    // Each triangle's material, by name: the name its face's `usemtl` gave, whether or not
    // a .mtl file describes it (tinyobjloader forgets names it found no .mtl entry for).
    const std::vector<std::string> names = usemtl_per_triangle(path);
    std::map<std::string, const tinyobj::material_t*> described;
    for (const tinyobj::material_t& m : obj_materials) described[m.name] = &m;
    std::map<std::string, int> material_of;  // name -> scene material index, resolved on first use
    auto scene_material = [&](const std::string& name) {
        auto it = material_of.find(name);
        if (it != material_of.end()) return it->second;
        ObjMaterialInfo info;
        info.name = name;
        auto found = described.find(name);
        if (!name.empty() && found != described.end()) {
            const tinyobj::material_t& m = *found->second;
            info.diffuse = {float(m.diffuse[0]), float(m.diffuse[1]), float(m.diffuse[2])};
            if (!m.diffuse_texname.empty())  // relative to the OBJ's folder unless absolute
                info.diffuse_texture = m.diffuse_texname[0] == '/' ? m.diffuse_texname : folder_of(path) + m.diffuse_texname;
        }
        const int index = resolve(info);
        material_of.emplace(name, index);
        return index;
    };

    std::size_t total_triangles = 0;
    for (const tinyobj::shape_t& shape : reader.GetShapes()) total_triangles += shape.mesh.num_face_vertices.size();

    Mesh mesh;
    mesh.source = path;
    mesh.has_uv = !attrib.texcoords.empty();
    mesh.has_normals = !attrib.normals.empty();
    std::map<std::tuple<int, int, int>, std::uint32_t> vertex_of;
    const int position_count = int(attrib.vertices.size() / 3);
    const int normal_count = int(attrib.normals.size() / 3);
    const int uv_count = int(attrib.texcoords.size() / 2);
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        const auto& indices = shape.mesh.indices;
        for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            std::array<std::uint32_t, 3> triangle{};
            bool face_has_uv = true, face_has_normal = true;
            for (int k = 0; k < 3; ++k) {
                const tinyobj::index_t& idx = indices[3 * f + std::size_t(k)];
                if (idx.vertex_index < 0 || idx.vertex_index >= position_count)
                    throw InputError(path, 0, "face refers to a vertex that does not exist");
                if (idx.normal_index >= normal_count)
                    throw InputError(path, 0, "face refers to a normal (vn) that does not exist");
                if (idx.texcoord_index >= uv_count)
                    throw InputError(path, 0, "face refers to a texture coordinate (vt) that does not exist");
                face_has_uv = face_has_uv && idx.texcoord_index >= 0;
                face_has_normal = face_has_normal && idx.normal_index >= 0;
                const auto key = std::make_tuple(idx.vertex_index, idx.normal_index, idx.texcoord_index);
                auto found = vertex_of.find(key);
                if (found == vertex_of.end()) {
                    Vertex v;
                    const std::size_t p = 3 * std::size_t(idx.vertex_index);
                    v.position = {attrib.vertices[p], attrib.vertices[p + 1], attrib.vertices[p + 2]};
                    if (idx.normal_index >= 0) {
                        const std::size_t n = 3 * std::size_t(idx.normal_index);
                        v.normal = {attrib.normals[n], attrib.normals[n + 1], attrib.normals[n + 2]};
                    }
                    if (idx.texcoord_index >= 0) {
                        const std::size_t t = 2 * std::size_t(idx.texcoord_index);
                        v.uv = {attrib.texcoords[t], attrib.texcoords[t + 1]};
                    }
                    found = vertex_of.emplace(key, std::uint32_t(mesh.vertices.size())).first;
                    mesh.vertices.push_back(v);
                }
                triangle[std::size_t(k)] = found->second;
            }
            mesh.has_uv = mesh.has_uv && face_has_uv;
            mesh.has_normals = mesh.has_normals && face_has_normal;
            mesh.triangles.push_back(triangle);
            std::string name;
            if (names.size() == total_triangles) {
                name = names[mesh.triangles.size() - 1];
            } else {  // faces we could not count the same way: fall back to tinyobjloader's ids
                const int id = f < shape.mesh.material_ids.size() ? shape.mesh.material_ids[f] : -1;
                if (id >= 0 && id < int(obj_materials.size())) name = obj_materials[std::size_t(id)].name;
            }
            mesh.triangle_material.push_back(scene_material(name));
        }
    }
    if (mesh.triangles.empty()) throw InputError(path, 0, "OBJ file has no faces");
    return mesh;
}

}  // namespace texr
