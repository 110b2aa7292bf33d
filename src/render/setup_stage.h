// Triangle setup (docs/design.md, "One frame": vertex stage, clip, triangle setup): vertices to clip
// space, homogeneous clipping, viewport and 1/256-pixel snapping, culling, edge functions,
// and the plane equations of depth, u', v', q and whatever else the material needs.
// Internal to the renderer: included by src/render/renderer.cpp only.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <glm/matrix.hpp>

#include "scanline.h"
#include "texr/core/scaling.h"
#include "texr/raster/clip.h"
#include "texr/render/renderer.h"
#include "texr/texture/wrap.h"

namespace texr {
namespace {

// Large texture coordinates: for periodic wraps, shift a triangle's coordinates by a whole
// number of periods (1 for repeat, 2 for mirror) so the smallest is in [0, period). The
// texture reads the same, and u', v' keep their precision (a quad with UVs near 1e5
// renders like one near 0). Clamp and border are not periodic and are left alone.
// Returns the shift subtracted (texr explain adds it back to show the scene's coordinates).
double rebase(std::array<double, 3>& t, Wrap wrap) {
    if (wrap != Wrap::repeat && wrap != Wrap::mirror) return 0.0;
    const double period = wrap == Wrap::repeat ? 1.0 : 2.0;
    const double low = std::min({t[0], t[1], t[2]});
    if (!(std::fabs(low) < 1e15)) return 0.0;  // beyond that no fraction is left to keep
    // (1/period is exact: 1 or 1/2; |low| < 1e15 is within fast_floor's range)
    const double shift = period * fast_floor(low * (1.0 / period));
    for (double& x : t) x -= shift;
    return shift;
}

bool finite(const glm::dvec4& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.w);
}

// Object-space vertex data carried to clip space, per object. (Sized per frame but not
// cleared, ScratchVector: transform writes every entry; clearing some 16 MB per frame for a
// 500k-vertex mesh took a millisecond or two before the workers started.)
struct TransformedMesh {
    ScratchVector<glm::dvec4> clip;
    // Per vertex: clip_outcode's bits, and not_finite for a NaN or infinite coordinate.
    ScratchVector<std::uint8_t> code;
    ScratchVector<glm::dvec3> world, normal;  // filled only when a material needs them
    static constexpr std::uint8_t not_finite = 1 << 7;
};

// The vertex stage of one object for vertices [first, last): object -> world -> clip (with
// each vertex's clip code for the frame's guard band), and only what the materials need.
// `v` is already sized.
void transform(const Mesh& mesh, const Object& object, const glm::dmat4& view_projection, const GuardBand& band,
               std::size_t first, std::size_t last, TransformedMesh& v) {
    const glm::dmat4 to_clip = view_projection * object.transform;
    // The inverse transpose of the object's 3x3 part, worked out on that part times the power
    // of two that brings its largest entry into [1, 2): normals are only directions, the
    // scaling is exact, and a uniform scale of 1e-110 or 1e150 no longer overflows or
    // underflows the inverse (it made every normal NaN). Each vertex's normal is then made
    // unit length, so that interpolation weighs the corners' directions by the pixel's
    // weights alone: not by the lengths a file gives them (vn 0 0 5 beside vn 0.6 0.8 0) nor
    // by the lengths a non-uniform scale leaves them (per pixel they are normalised again).
    glm::dmat3 linear(object.transform);
    double largest = 0.0;
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row) largest = std::max(largest, std::fabs(linear[col][row]));
    const int k = unit_scale_exponent(largest);
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row) linear[col][row] = std::ldexp(linear[col][row], k);
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
    for (std::size_t i = first; i < last; ++i) {
        const glm::dvec4 p(glm::dvec3(mesh.vertices[i].position), 1.0);
        v.clip[i] = to_clip * p;
        v.code[i] = std::uint8_t(clip_outcode(v.clip[i], band) | (finite(v.clip[i]) ? 0 : TransformedMesh::not_finite));
        if (!v.world.empty()) v.world[i] = glm::dvec3(object.transform * p);
        if (!v.normal.empty()) v.normal[i] = unit_direction(normal_matrix * glm::dvec3(mesh.vertices[i].normal));
    }
}

// A vertex attribute at the corners of a piece: at each corner, the sum of the triangle's
// values with the corner's weights. An unclipped piece is the triangle: its values as they
// are (the weights are 1, 0, 0 and so on; the sum would also have turned -0 into +0, and an
// infinite value at one corner into NaN at all three). `weights` is read only when clipped.
template <typename Get>
std::array<double, 3> vertex_values(const std::array<const glm::dvec3*, 3>& weights, const std::array<std::uint32_t, 3>& tri,
                                    bool clipped, Get get) {
    if (!clipped) return {double(get(tri[0])), double(get(tri[1])), double(get(tri[2]))};
    std::array<double, 3> out{};
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) out[std::size_t(k)] += (*weights[std::size_t(k)])[j] * double(get(tri[std::size_t(j)]));
    return out;
}

// A triangle (or one piece of a clipped triangle) ready for the span walk.
struct PreparedPiece {
    PreparedPiece() {}  // leaves the setup unfilled: prepare_piece writes what will be read
    TriangleSetup s;
    int object, material;
    std::size_t triangle;
    bool clipped;
};

// Stage one, once per triangle (workers take batches of triangles as they become free):
// clipping, viewport, snapping, culling and triangle setup (docs/design.md, "One frame").
class SetupStage {
public:
    // `band`: the frame's guard band, the one the vertex stage's clip codes were worked out for.
    SetupStage(const Scene& scene, const std::vector<Needs>& needs, const RenderOptions& options, const Framebuffer& fb,
               const GuardBand& band, RenderStats& counters)
        : scene_(scene), needs_(needs), options_(options), width_(fb.width), height_(fb.height), band_(band),
          explaining_(fb.explanation != nullptr), counters_(counters) {}

    // Prepares triangles [first, last) of object `object_index`, appending their pieces.
    void prepare(int object_index, const TransformedMesh& vertices, std::size_t first, std::size_t last,
                 std::vector<PreparedPiece>& out) {
        const Object& object = scene_.objects[std::size_t(object_index)];
        const Mesh& mesh = scene_.meshes[std::size_t(object.mesh)];
        // A transform that mirrors (a negative determinant, such as scale -1 1 1) turns the
        // faces' winding over: their fronts are then clockwise on screen. (Each column scaled
        // to a largest entry of 1 first: the determinant of a scale of 1e-110 underflows to -0.)
        glm::dmat3 axes(object.transform);
        for (int i = 0; i < 3; ++i) {
            const double largest = std::max({std::fabs(axes[i].x), std::fabs(axes[i].y), std::fabs(axes[i].z)});
            if (largest > 0.0) axes[i] /= largest;
        }
        const bool mirrored = glm::determinant(axes) < 0.0;
        for (std::size_t t = first; t < last; ++t) prepare_triangle(object_index, object, mirrored, mesh, vertices, t, out);
    }

private:
    void prepare_triangle(int object_index, const Object& object, bool mirrored, const Mesh& mesh, const TransformedMesh& v,
                          std::size_t t, std::vector<PreparedPiece>& out) {
        ++counters_.triangles_in;
        const auto& tri = mesh.triangles[t];
        const glm::dvec4& a = v.clip[tri[0]];
        const glm::dvec4& b = v.clip[tri[1]];
        const glm::dvec4& c = v.clip[tri[2]];
        // The vertices' codes decide most triangles: what clip_triangle would decide first.
        const int any = v.code[tri[0]] | v.code[tri[1]] | v.code[tri[2]];
        if (any & TransformedMesh::not_finite) { ++counters_.triangles_dropped; return; }
        if (v.code[tri[0]] & v.code[tri[1]] & v.code[tri[2]]) { ++counters_.triangles_culled; return; }  // beyond one plane
        // A piece from its corners' clip-space positions and (when clipped) their weights on
        // the triangle's vertices; built in place (a piece is some 500 bytes) and kept if it
        // survives culling.
        const auto add_piece = [&](const std::array<const glm::dvec4*, 3>& position, const std::array<const glm::dvec3*, 3>& weights,
                                   bool clipped) {
            PreparedPiece& piece = out.emplace_back();
            piece.object = object_index, piece.material = mesh.triangle_material[t], piece.triangle = t;
            piece.clipped = clipped;
            if (!prepare_piece(mesh, v, tri, position, weights, object.cull_back, mirrored, piece)) out.pop_back();
        };
        if (any == 0) {  // inside every plane: the triangle itself is the one piece
            add_piece({&a, &b, &c}, {}, false);
            return;
        }
        const ClipResult result = clip_triangle(a, b, c, band_, polygon_);
        if (result == ClipResult::outside) { ++counters_.triangles_culled; return; }
        if (result == ClipResult::clipped) ++counters_.triangles_clipped;
        // The clipped polygon is convex: a fan from its first vertex.
        const auto& corner = polygon_.vertices;
        for (std::size_t i = 1; i + 1 < std::size_t(polygon_.count); ++i)
            add_piece({&corner[0].position, &corner[i].position, &corner[i + 1].position},
                      {&corner[0].weights, &corner[i].weights, &corner[i + 1].weights}, result == ClipResult::clipped);
    }

    bool prepare_piece(const Mesh& mesh, const TransformedMesh& v, const std::array<std::uint32_t, 3>& tri,
                       const std::array<const glm::dvec4*, 3>& position, const std::array<const glm::dvec3*, 3>& weights,
                       bool cull_back, bool mirrored, PreparedPiece& piece) {
        // Viewport: NDC -> pixels (row 0 at the top), snapped to 1/256 pixel.
        std::array<SnappedVertex, 3> snapped;
        std::array<glm::dvec2, 3> screen;
        std::array<double, 3> inv_w, depth;
        for (int k = 0; k < 3; ++k) {
            const glm::dvec4& p = *position[std::size_t(k)];
            inv_w[std::size_t(k)] = 1.0 / p.w;
            const double x = (p.x * inv_w[std::size_t(k)] * 0.5 + 0.5) * width_;
            const double y = (0.5 - p.y * inv_w[std::size_t(k)] * 0.5) * height_;
            snapped[std::size_t(k)] = {snap(x), snap(y)};
            constexpr double pixels_per_step = 1.0 / subpixel_scale;  // exact: a power of two
            screen[std::size_t(k)] = {double(snapped[std::size_t(k)].x) * pixels_per_step, double(snapped[std::size_t(k)].y) * pixels_per_step};
            depth[std::size_t(k)] = p.z * inv_w[std::size_t(k)] * 0.5 + 0.5;
        }
        TriangleSetup& s = piece.s;
        if (!triangle_edges(snapped, s.edges)) { ++counters_.triangles_dropped; return false; }
        // Counter-clockwise in NDC (y up) is front facing; y points down on screen, so a
        // front-facing triangle has negative signed area there (positive where the object's
        // transform mirrors it).
        if (cull_back) {
            const auto area = twice_signed_area(snapped);
            if (mirrored ? area < 0 : area > 0) { ++counters_.triangles_culled; return false; }
        }
        if (!centre_in_box(s.edges, s.first_row, s.last_row)) { ++counters_.triangles_culled; return false; }
        ++counters_.triangles_set_up;

        const Material& material = scene_.materials[std::size_t(piece.material)];
        const Needs needs = needs_[std::size_t(piece.material)];
        const Texture* texture = material.texture >= 0 ? &scene_.textures[std::size_t(material.texture)] : nullptr;
        s.screen = screen;
        const auto lambda = barycentric_planes(screen);
        s.depth = over_w_plane(lambda, depth, {1.0, 1.0, 1.0});  // depth is affine in screen space
        s.h.q = over_w_plane(lambda, {1.0, 1.0, 1.0}, inv_w);
        if ((needs & need_uv) || explaining_) {  // texr explain shows u and v even when unused
            std::array<double, 3> u = vertex_values(weights, tri, piece.clipped, [&](std::uint32_t i) { return mesh.vertices[i].uv.x; });
            std::array<double, 3> vv = vertex_values(weights, tri, piece.clipped, [&](std::uint32_t i) { return mesh.vertices[i].uv.y; });
            // (a procedural texture has no period to shift by: its pattern is not an image's)
            s.uv_shift = texture && !texture->procedural
                             ? glm::dvec2(rebase(u, texture->sampler.wrap_u), rebase(vv, texture->sampler.wrap_v))
                             : glm::dvec2(0.0);
            s.h.u_prime = over_w_plane(lambda, u, inv_w);
            s.h.v_prime = over_w_plane(lambda, vv, inv_w);
            if (options_.span_mode == SpanMode::affine) {  // the wrong answer, for contrast: no 1/w
                s.u_affine = over_w_plane(lambda, u, {1.0, 1.0, 1.0});
                s.v_affine = over_w_plane(lambda, vv, {1.0, 1.0, 1.0});
            } else {
                s.u_affine = s.v_affine = Plane{0.0, 0.0, 0.0};  // copied into SpanTexturing, never used
            }
        }
        for (int axis = 0; axis < 3 && (needs & (need_normal | need_color | need_world_position)); ++axis) {
            if (needs & need_normal)
                s.normal[std::size_t(axis)] = over_w_plane(lambda, vertex_values(weights, tri, piece.clipped, [&](std::uint32_t i) { return v.normal[i][axis]; }), inv_w);
            if (needs & need_color)
                s.color[std::size_t(axis)] = over_w_plane(lambda, vertex_values(weights, tri, piece.clipped, [&](std::uint32_t i) { return mesh.vertices[i].color[axis]; }), inv_w);
            if (needs & need_world_position)
                s.world[std::size_t(axis)] = over_w_plane(lambda, vertex_values(weights, tri, piece.clipped, [&](std::uint32_t i) { return v.world[i][axis]; }), inv_w);
        }
        // A bump map's O_u and O_v: the whole triangle's (a clipped piece lies in its plane),
        // from its corners' world positions and UVs (whole periods of a rebase change neither).
        s.tangents = SurfaceTangents{};
        if (material.bump >= 0 && (needs & need_world_position)) {
            const glm::dvec3 p[3] = {v.world[tri[0]], v.world[tri[1]], v.world[tri[2]]};
            const double us[3] = {mesh.vertices[tri[0]].uv.x, mesh.vertices[tri[1]].uv.x, mesh.vertices[tri[2]].uv.x};
            const double vs[3] = {mesh.vertices[tri[0]].uv.y, mesh.vertices[tri[1]].uv.y, mesh.vertices[tri[2]].uv.y};
            s.tangents = surface_tangents(p, us, vs);
        }
        return true;
    }

    // Whether the bounding box of the snapped vertices (triangle_edges found it) holds a pixel
    // centre of the frame; its rows are `first` to `last`. A triangle whose box holds none
    // covers none: it is off screen, or small and between the centres (half of the set-up
    // triangles of a 1M-triangle terrain at 1920x1080 were), and needs no planes.
    bool centre_in_box(const TriangleEdges& e, int& first, int& last) const {
        row_range(e, height_, first, last);
        int first_column, last_column;
        column_range(e, width_, first_column, last_column);
        return first <= last && first_column <= last_column;
    }

    const Scene& scene_;
    const std::vector<Needs>& needs_;
    const RenderOptions& options_;
    int width_, height_;
    GuardBand band_;
    bool explaining_;
    RenderStats& counters_;
    ClipPolygon polygon_;
};

}  // namespace
}  // namespace texr
