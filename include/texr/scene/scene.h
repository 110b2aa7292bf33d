// What a scene file describes, after parsing: camera, lights, textures, materials and
// objects. Everything here is plain data; the renderer reads it, nothing writes it back.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "texr/core/color.h"
#include "texr/core/error.h"
#include "texr/texture/image.h"
#include "texr/texture/intermediate.h"
#include "texr/texture/mipmap.h"
#include "texr/texture/procedural.h"
#include "texr/texture/sampler.h"

namespace texr {

struct Camera {
    glm::dvec3 eye{0.0, 0.0, 3.0};
    glm::dvec3 target{0.0, 0.0, 0.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
    double fov_y_degrees = 60.0;  // vertical field of view
    double near = 0.1, far = 100.0;
};

struct Texture {
    std::string name;
    std::string path;
    std::shared_ptr<const Image> image;
    std::shared_ptr<MipMap> mipmap;  // levels built on first minified lookup
    Sampler sampler;
    // A procedural texture (texture/procedural.h) instead: then image and mipmap are null,
    // path is empty and the sampler is unused.
    std::shared_ptr<const Procedural> procedural;
};

enum class Lighting { none, lambert };

struct Material {
    std::string name;
    Color color{1.0f, 1.0f, 1.0f};  // multiplies the texture, if any
    int texture = -1;               // index into Scene::textures, or -1
    Lighting lighting = Lighting::none;
    bool vertex_colors = false;     // multiply by the interpolated per-vertex colour
    // Bump mapping (texture/bump.h): the texture whose first channel, times bump_height
    // (world units), is the height B(u, v) the surface is virtually displaced by; -1: none.
    int bump = -1;
    double bump_height = 0.0;
    // Reflection mapping (texture/environment.h): this share of the colour is the scene's
    // environment map along the reflected view ray, the rest the material's own shading.
    double reflect = 0.0;
    // Opacity as an alpha test: where the texture's alpha is below this, the surface is a hole
    // (the lecture's billboards "often with opacity texture"); 0: opaque everywhere.
    float cutout = 0.0f;
    // Slope-based mapping (the lecture's): alpha = n . direction (clamped to [0, 1]), the colour
    // multiplied by alpha flat + (1 - alpha) steep.
    bool slope = false;
    Color slope_flat{1.0f}, slope_steep{1.0f};
    glm::dvec3 slope_direction{0.0, 1.0, 0.0};
    // A light map (the lecture's "Light Maps"): its texture is the irradiance E, read at
    // (u, v) / lightmap_repeat, and multiplies the colour (B = rho E); -1: none.
    int lightmap = -1;
    double lightmap_repeat = 1.0;
    int projector = -1;  // its texture is read where this projector throws it; -1: at the mesh's (u, v)
    // Or at the (u, v) of an intermediate surface (texture/intermediate.h); kind none: the mesh's.
    IntermediateMapping mapping;
};

// A slide projector (the lecture's "Projective Textures"): a material that names it reads
// its texture at the (u, v) the projector throws on each surface point, not at the mesh's.
struct Projector {
    std::string name;
    glm::dvec3 eye{0.0, 0.0, 3.0}, target{0.0}, up{0.0, 1.0, 0.0};
    bool parallel = false;
    double fov_y_degrees = 30.0;  // perspective: the vertical field of view
    double aspect = 1.0;          // width over height of the projected image
    double height = 1.0;          // parallel: the projected image's height in world units
    // World position -> clip space of the projector (OpenGL's; the image is x, y in [-w, w]).
    glm::dmat4 matrix{1.0};
    glm::dvec3 forward{0.0, 0.0, -1.0};  // unit, eye to target: a point is ahead where (P - eye) . forward > 0
};

struct Light {
    enum class Kind { directional, point } kind = Kind::directional;
    glm::dvec3 vector{0.0, -1.0, 0.0};  // direction the light travels, or its position
    Color color{1.0f, 1.0f, 1.0f};
};

struct Vertex {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    glm::dvec2 uv{0.0};  // double: texture coordinates far from 0 keep their fraction
    Color color{1.0f};
};

struct Mesh {
    std::string source;  // "file:line" of the line that made it, for messages
    std::vector<Vertex> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<int> triangle_material;  // per triangle, index into Scene::materials
    bool has_uv = false, has_normals = false, has_colors = false;  // has_uv: every triangle has texture coordinates
    // Where has_uv is false: per triangle, whether it has none (an OBJ face without vt; empty:
    // none of the triangles has any).
    std::vector<bool> triangle_without_uv;
    std::vector<std::string> material_files;  // the .mtl files an OBJ file's mtllib lines read
};

struct Object {
    int mesh = -1;
    glm::dmat4 transform{1.0};  // object -> world
    bool cull_back = false;     // drop triangles facing away from the camera
};

struct Scene {
    std::string path;  // the scene file
    // Every file the scene was read from: the scene file, OBJ and .mtl files, images (so that
    // texr render can refuse to write its frame over one of them).
    std::vector<std::string> files;
    int width = 640, height = 480;
    Camera camera;
    Color background{0.0f, 0.0f, 0.0f};
    int environment = -1;  // the environment map (a texture's index), seen behind everything; -1: none
    Color ambient{0.0f, 0.0f, 0.0f};
    std::vector<Texture> textures;
    std::vector<Material> materials;
    std::vector<Light> lights;
    std::vector<Projector> projectors;
    std::vector<Mesh> meshes;
    std::vector<Object> objects;
};

// The largest colour value a scene (or a .mtl Kd) may give. The bound keeps products of
// colours, lights and texels finite: 10000 is about 4e9 linear, where 1e17 would be
// infinite and turn an unlit pixel into NaN.
constexpr double max_color = 10000.0;
// max_color as messages print it.
inline std::string max_color_text() { return std::to_string(int(max_color)); }

// Largest frame texr renders: each side at most 16384 and at most 64 Mpixel in all.
constexpr int max_image_side = 16384;
constexpr long long max_image_pixels = 64LL * 1024 * 1024;

// A frame size as --size takes it (texr render, explain and bench): "WxH", digits only. Sets
// width and height and returns "", or returns the message for the user.
inline std::string parse_frame_size(const std::string& text, int& width, int& height) {
    const std::string limits = "each side from 1 to " + std::to_string(max_image_side);
    const std::string malformed = "--size expects WxH (for example 640x480), " + limits + ", got " + shown_token(text);
    const std::size_t x = text.find('x');
    if (x == std::string::npos) return malformed;
    const std::string parts[2] = {text.substr(0, x), text.substr(x + 1)};
    long long side[2] = {0, 0};
    for (int i = 0; i < 2; ++i) {
        if (parts[i].empty() || parts[i].size() > 9) return malformed;  // (9 digits cannot overflow)
        for (char ch : parts[i]) {
            if (ch < '0' || ch > '9') return malformed;
            side[i] = side[i] * 10 + (ch - '0');
        }
    }
    if (side[0] < 1 || side[1] < 1 || side[0] > max_image_side || side[1] > max_image_side || side[0] * side[1] > max_image_pixels)
        return "--size " + text + " is out of range: " + limits + " and the frame at most " + std::to_string(max_image_pixels) +
               " pixels, got '" + text + "'";
    width = int(side[0]), height = int(side[1]);
    return "";
}

}  // namespace texr
