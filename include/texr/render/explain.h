// texr explain: the story of one pixel, step by step as the lecture tells it: which
// triangle covers it, the triangle's homography M^-1 = U diag(1/w) adj(S) / det(S) and its inverse M,
// (u', v', q) at the pixel centre, u = u'/q and v = v'/q, the exact derivatives, the level
// of detail, the mip levels the texture's filter reads and its value, the shading (material
// colour, vertex colour, normal, each light), and the colour written.
#pragma once
#include <array>
#include <string>

#include "texr/raster/homography.h"
#include "texr/raster/plane.h"
#include "texr/raster/span_modes.h"
#include "texr/render/needs.h"
#include "texr/scene/scene.h"
#include "texr/texture/bump.h"

namespace texr {

struct PixelExplanation {
    int x = 0, y = 0;
    int width = 0, height = 0;  // the frame's (the ray through the pixel, for an environment map)
    bool covered = false;      // false: the background shows
    int object = -1;           // index into Scene::objects
    std::size_t triangle = 0;  // index into that object's mesh
    int material = -1;
    bool clipped = false;      // the triangle was cut by a clipping plane (this is one piece)
    std::array<glm::dvec2, 3> screen{};  // the piece's vertices in pixels, snapped to 1/256
    TextureHomography h;       // for the piece, with its UVs re-based by whole periods:
    glm::dvec2 uv_shift{0.0};  // the periods subtracted from u and v (repeat and mirror wraps)
    // The piece's other attributes over w (normal, vertex colour, world position), as planes;
    // meaningful only for those its material needs.
    std::array<Plane, 3> normal{}, vertex_color{}, world{};
    SurfaceTangents tangents;  // O_u and O_v, for a bump-mapped material
    double depth = 0.0;
    Color color{0.0f};         // linear, as written to the frame
    // The (u, v) the span walk gave the texture lookup (a span mode other than exact computes
    // them its own way), when the caller captured them (RenderOptions::capture_uv).
    SpanMode span_mode = SpanMode::exact;
    bool uv_read_known = false;
    glm::dvec2 uv_read{0.0};
    // Likewise the world position a solid procedural texture read (stepped along the span).
    bool world_read_known = false;
    glm::dvec3 world_read{0.0};
};

// The explanation as text for a person reading along with the lecture.
std::string describe(const PixelExplanation& e, const Scene& scene);

}  // namespace texr
