// The frame, top to bottom (DESIGN.md, "One frame"): vertex stage -> homogeneous clipping ->
// viewport and 1/256-pixel snapping -> triangle setup (edge functions, homography, planes)
// -> scanline walk -> shading -> framebuffer.
#include "texr/render/renderer.h"

#include <chrono>
#include <cmath>
#include <thread>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "texr/raster/clip.h"
#include "texr/raster/edges.h"
#include "texr/raster/homography.h"
#include "texr/raster/span_walk.h"
#include "texr/render/explain.h"
#include "texr/render/needs.h"
#include "texr/texture/lookup.h"
#include "texr/texture/reconstruct.h"

namespace texr {

void RenderStats::add_counters(const RenderStats& o) {
    triangles_in += o.triangles_in;
    triangles_clipped += o.triangles_clipped;
    triangles_culled += o.triangles_culled;
    triangles_dropped += o.triangles_dropped;
    triangles_set_up += o.triangles_set_up;
    spans += o.spans;
    pixels_shaded += o.pixels_shaded;
    texels_fetched += o.texels_fetched;
}

glm::dmat4 view_matrix(const Camera& camera) { return glm::lookAtRH(camera.eye, camera.target, camera.up); }

glm::dmat4 projection_matrix(const Camera& camera, double aspect) {
    return glm::perspectiveRH_NO(glm::radians(camera.fov_y_degrees), aspect, camera.near, camera.far);
}

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// The rows one worker thread owns: bands of band_rows rows, dealt round-robin. Every pixel
// belongs to exactly one worker, and each worker draws the triangles in submission order,
// so the frame is the same bytes for any number of threads.
struct RowSet {
    static constexpr int band_rows = 8;
    int index = 0, count = 1;

    bool owns(int y) const { return (y / band_rows) % count == index; }
    // The first row >= y that this worker owns.
    int first_owned(int y) const {
        if (owns(y)) return y;
        const int band = y / band_rows;
        const int ahead = ((index - band % count) + count) % count;  // > 0: band is not ours
        return (band + ahead) * band_rows;
    }
    int next_owned(int y) const { return first_owned(y + 1); }
};

// What one draw (a material on a mesh) shades with.
struct DrawContext {
    const Scene& scene;
    const Material& material;
    const Texture* texture;  // null for an untextured material
    int spp;                 // > 1: supersampled texture ground truth
    SpanMode span_mode;
    double span_tolerance;
    double* u_scratch;       // a row's worth of (u, v) for span modes other than incremental
    double* v_scratch;
    PixelExplanation* explain;  // texr explain: the pixel to record, or null
    int object, material_index;
    std::size_t triangle;
    bool clipped;
};

// Everything the span walk needs of one screen triangle.
struct TriangleSetup {
    TriangleEdges edges;
    Plane depth;             // window depth, affine in screen space
    TextureHomography h;     // u', v' and q = 1/w (q is also the divisor of every attribute)
    Plane u_affine, v_affine;  // SpanMode::affine only
    std::array<glm::dvec2, 3> screen;  // snapped vertices, for texr explain
    std::array<Plane, 3> normal, color, world;  // a/w planes, only those the draw needs
};

template <Needs N>
Color shade(const DrawContext& d, const Color4& texel, const glm::dvec3& normal, const glm::dvec3& color,
            const glm::dvec3& world) {
    Color c = d.material.color;
    if constexpr ((N & need_uv) != 0) c *= Color(texel);
    if constexpr ((N & need_color) != 0) c *= Color(color);
    if (d.material.lighting == Lighting::lambert) {
        Color irradiance = d.scene.ambient;
        if constexpr ((N & need_normal) != 0) {
            const glm::dvec3 n = glm::normalize(normal);
            for (const Light& light : d.scene.lights) {
                glm::dvec3 to_light = -light.vector;
                if constexpr ((N & need_world_position) != 0)
                    if (light.kind == Light::Kind::point) to_light = glm::normalize(light.vector - world);
                irradiance += light.color * float(std::max(0.0, glm::dot(n, to_light)));
            }
        }
        c *= irradiance;
    }
    (void)texel, (void)normal, (void)color, (void)world;
    return c;
}

// The ground truth for texture filtering: spp x spp stratified sub-pixel positions, each
// with its exact (u, v) from the homography, read bilinearly from the base level.
Color4 supersampled_texel(const DrawContext& d, const TextureHomography& h, int x, int y, std::uint64_t& texels) {
    const int n = d.spp;
    Color4 sum(0.0f);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const glm::dvec2 uv = h.uv_at(x + (i + 0.5) / n, y + (j + 0.5) / n);
            sum += sample_bilinear(d.texture->mipmap->base(), d.texture->sampler, uv.x, uv.y);
        }
    texels += 4 * std::uint64_t(n) * std::uint64_t(n);
    return sum / float(n * n);
}

// The span walk of one row (DESIGN.md, "Determinism and bounded error"): values at the first
// pixel centre come from the plane equations; within the span they are stepped by their
// constant x derivatives: u' += du'/dx, v' += dv'/dx, q += dq/dx.
// Three planes stepped together (a vector attribute over w).
struct SteppedVector {
    SteppedPlane p[3];
    static SteppedVector start(const std::array<Plane, 3>& planes, int x0, int y) {
        return {{SteppedPlane::start(planes[0], x0, y), SteppedPlane::start(planes[1], x0, y),
                 SteppedPlane::start(planes[2], x0, y)}};
    }
    glm::dvec3 value() const { return {p[0].value, p[1].value, p[2].value}; }
    void advance() { p[0].advance(), p[1].advance(), p[2].advance(); }
};

// The span walk of one row (DESIGN.md, "Determinism and bounded error"): values at the first
// pixel centre come from the plane equations; within the span they are stepped by their
// constant x derivatives: u' += du'/dx, v' += dv'/dx, q += dq/dx.
template <Needs N>
void shade_span(const DrawContext& d, const TriangleSetup& s, int y, Span span, Framebuffer& fb, RenderStats& stats) {
    constexpr bool perspective = (N & (need_uv | need_normal | need_color | need_world_position)) != 0;
    const int x0 = span.x0;
    // Texture coordinates: stepped here (incremental), or precomputed for the span by
    // another span mode, which may need no divide per pixel at all.
    const bool stepped_uv = (N & need_uv) != 0 && d.span_mode == SpanMode::incremental;
    if constexpr ((N & need_uv) != 0)
        if (!stepped_uv) {
            SpanTexturing t;
            t.h = &s.h, t.u_affine = s.u_affine, t.v_affine = s.v_affine, t.tolerance = d.span_tolerance;
            t.width = d.texture->mipmap->base().width(), t.height = d.texture->mipmap->base().height();
            span_texture_coordinates(d.span_mode, t, y, x0, span.x1 - x0, d.u_scratch, d.v_scratch);
        }
    // 1/q per pixel is needed by perspective attributes, derivatives and stepped (u, v).
    constexpr bool attributes_need_q = (N & (need_uv_derivatives | need_normal | need_color | need_world_position)) != 0;
    const bool divide = attributes_need_q || stepped_uv;

    SteppedPlane depth = SteppedPlane::start(s.depth, x0, y);
    SteppedPlane u_prime, v_prime, q;
    SteppedVector normal{}, color{}, world{};
    if constexpr (perspective) q = SteppedPlane::start(s.h.q, x0, y);
    if constexpr ((N & need_uv) != 0) u_prime = SteppedPlane::start(s.h.u_prime, x0, y), v_prime = SteppedPlane::start(s.h.v_prime, x0, y);
    if constexpr ((N & need_normal) != 0) normal = SteppedVector::start(s.normal, x0, y);
    if constexpr ((N & need_color) != 0) color = SteppedVector::start(s.color, x0, y);
    if constexpr ((N & need_world_position) != 0) world = SteppedVector::start(s.world, x0, y);

    float* depth_row = &fb.depth[fb.index(0, y)];
    Color* color_row = &fb.color[fb.index(0, y)];
    glm::dvec2* uv_row = fb.uv.empty() ? nullptr : &fb.uv[fb.index(0, y)];
    std::uint64_t shaded = 0, texels = 0;
    for (int x = span.x0; x < span.x1; ++x) {
        if (float(depth.value) < depth_row[x]) {
            depth_row[x] = float(depth.value);
            double inv_q = 1.0;
            if constexpr (perspective)
                if (divide) inv_q = 1.0 / q.value;  // the one divide per pixel
            Color4 texel(1.0f);
            if constexpr ((N & need_uv) != 0) {
                const double u = stepped_uv ? u_prime.value * inv_q : d.u_scratch[x - x0];
                const double v = stepped_uv ? v_prime.value * inv_q : d.v_scratch[x - x0];
                UVDerivatives derivatives{0.0, 0.0, 0.0, 0.0};
                if constexpr ((N & need_uv_derivatives) != 0) derivatives = uv_derivatives(s.h, u, v, q.value);
                texel = d.spp > 1 ? supersampled_texel(d, s.h, x, y, texels)
                                  : lookup(*d.texture, u, v, derivatives, texels);
                if (uv_row) uv_row[x] = {u, v};
            }
            color_row[x] = shade<N>(d, texel, normal.value() * inv_q, color.value() * inv_q, world.value() * inv_q);
            ++shaded;
        }
        depth.advance();
        if constexpr (perspective) q.advance();
        if constexpr ((N & need_uv) != 0) u_prime.advance(), v_prime.advance();
        if constexpr ((N & need_normal) != 0) normal.advance();
        if constexpr ((N & need_color) != 0) color.advance();
        if constexpr ((N & need_world_position) != 0) world.advance();
    }
    stats.pixels_shaded += shaded;
    stats.texels_fetched += texels;
}

void record(const DrawContext& d, const TriangleSetup& s, const Framebuffer& fb) {
    PixelExplanation& e = *d.explain;
    const std::size_t i = fb.index(e.x, e.y);
    e.covered = true;
    e.object = d.object, e.triangle = d.triangle, e.material = d.material_index, e.clipped = d.clipped;
    e.screen = s.screen, e.h = s.h, e.depth = fb.depth[i], e.color = fb.color[i];
}

template <Needs N>
void walk_triangle(const DrawContext& d, const TriangleSetup& s, const RowSet& rows, Framebuffer& fb, RenderStats& stats) {
    int first = 0, last = -1;
    row_range(s.edges, fb.height, first, last);
    for (int y = rows.first_owned(first); y <= last; y = rows.next_owned(y)) {
        const Span span = span_for_row(s.edges, y, fb.width);
        if (span.x0 >= span.x1) continue;
        ++stats.spans;
        // texr explain: did this triangle win the explained pixel?
        const bool explained = d.explain && y == d.explain->y && d.explain->x >= span.x0 && d.explain->x < span.x1;
        const float depth_before = explained ? fb.depth[fb.index(d.explain->x, y)] : 0.0f;
        if (!fb.coverage.empty())  // test instrumentation: every covered pixel, before the depth test
            for (int x = span.x0; x < span.x1; ++x) ++fb.coverage[fb.index(x, y)];
        shade_span<N>(d, s, y, span, fb, stats);
        if (explained && fb.depth[fb.index(d.explain->x, y)] != depth_before) record(d, s, fb);
    }
}

// One compiled walk per Needs set.
using WalkFunction = void (*)(const DrawContext&, const TriangleSetup&, const RowSet&, Framebuffer&, RenderStats&);
template <std::size_t... I>
constexpr std::array<WalkFunction, sizeof...(I)> make_walk_table(std::index_sequence<I...>) {
    return {&walk_triangle<Needs(I)>...};
}
constexpr auto walk_table = make_walk_table(std::make_index_sequence<need_all + 1>());

// Large texture coordinates: for periodic wraps, shift a triangle's coordinates by a whole
// number of periods (1 for repeat, 2 for mirror) so the smallest is in [0, period). The
// texture reads the same, and u', v' keep their precision (a quad with UVs near 1e5
// renders like one near 0). Clamp and border are not periodic and are left alone.
void rebase(std::array<double, 3>& t, Wrap wrap) {
    if (wrap != Wrap::repeat && wrap != Wrap::mirror) return;
    const double period = wrap == Wrap::repeat ? 1.0 : 2.0;
    const double low = std::min({t[0], t[1], t[2]});
    if (!(std::fabs(low) < 1e15)) return;  // beyond that no fraction is left to keep
    const double shift = period * std::floor(low / period);
    for (double& x : t) x -= shift;
}

// Object-space vertex data carried to clip space, per object.
struct TransformedMesh {
    std::vector<glm::dvec4> clip;
    std::vector<glm::dvec3> world, normal;  // filled only when a material needs them
};

// The vertex stage of one object: object -> world -> clip, and only what the materials need.
TransformedMesh transform(const Mesh& mesh, const Object& object, const glm::dmat4& view_projection, Needs needs) {
    const glm::dmat4 to_clip = view_projection * object.transform;
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(object.transform)));
    const std::size_t n = mesh.vertices.size();
    TransformedMesh v;
    v.clip.resize(n);
    v.world.resize((needs & need_world_position) ? n : 0);
    v.normal.resize((needs & need_normal) ? n : 0);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec4 p(glm::dvec3(mesh.vertices[i].position), 1.0);
        v.clip[i] = to_clip * p;
        if (needs & need_world_position) v.world[i] = glm::dvec3(object.transform * p);
        if (needs & need_normal) v.normal[i] = normal_matrix * glm::dvec3(mesh.vertices[i].normal);
    }
    return v;
}

bool finite(const glm::dvec4& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.w);
}

template <typename Get>
std::array<double, 3> vertex_values(const std::array<glm::dvec3, 3>& weights, const std::array<std::uint32_t, 3>& tri,
                                    Get get) {
    std::array<double, 3> out{};
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) out[std::size_t(k)] += weights[std::size_t(k)][j] * double(get(tri[std::size_t(j)]));
    return out;
}

// One worker's share of the frame: every triangle, but only the rows it owns.
class FrameRenderer {
public:
    FrameRenderer(const Scene& scene, const std::vector<Needs>& needs, const RenderOptions& options, const RowSet& rows,
                  Framebuffer& fb, RenderStats& stats)
        : scene_(scene), fb_(fb), stats_(stats), width_(fb.width), height_(fb.height), options_(options),
          band_(guard_band_for(fb.width, fb.height)), needs_(needs), rows_(rows),
          u_scratch_(std::size_t(fb.width)), v_scratch_(std::size_t(fb.width)),
          explain_(fb.explanation && rows.owns(fb.explanation->y) ? fb.explanation.get() : nullptr) {}

    void draw(int object_index, const TransformedMesh& vertices) {
        const Object& object = scene_.objects[std::size_t(object_index)];
        const Mesh& mesh = scene_.meshes[std::size_t(object.mesh)];
        v_ = &vertices;
        object_index_ = object_index;
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) draw_triangle(mesh, t, object.cull_back);
    }

private:
    void draw_triangle(const Mesh& mesh, std::size_t t, bool cull_back) {
        ++triangle_counters_.triangles_in;
        const auto& tri = mesh.triangles[t];
        const glm::dvec4& a = v_->clip[tri[0]];
        const glm::dvec4& b = v_->clip[tri[1]];
        const glm::dvec4& c = v_->clip[tri[2]];
        if (!finite(a) || !finite(b) || !finite(c)) { ++triangle_counters_.triangles_dropped; return; }
        const ClipResult result = clip_triangle(a, b, c, band_, polygon_);
        if (result == ClipResult::outside) { ++triangle_counters_.triangles_culled; return; }
        if (result == ClipResult::clipped) ++triangle_counters_.triangles_clipped;

        const int material = mesh.triangle_material[t];
        const DrawContext d{scene_, scene_.materials[std::size_t(material)],
                            scene_.materials[std::size_t(material)].texture >= 0
                                ? &scene_.textures[std::size_t(scene_.materials[std::size_t(material)].texture)]
                                : nullptr,
                            std::max(1, options_.spp), options_.span_mode, options_.span_tolerance,
                            u_scratch_.data(), v_scratch_.data(), explain_, object_index_, material, t,
                            result == ClipResult::clipped};
        const Needs needs = needs_[std::size_t(material)];
        // The clipped polygon is convex: a fan from its first vertex.
        for (int i = 1; i + 1 < polygon_.count; ++i)
            draw_piece(mesh, tri, {polygon_.vertices[0], polygon_.vertices[std::size_t(i)], polygon_.vertices[std::size_t(i + 1)]},
                       d, needs, cull_back);
    }

    void draw_piece(const Mesh& mesh, const std::array<std::uint32_t, 3>& tri, const std::array<ClipVertex, 3>& piece,
                    const DrawContext& d, Needs needs, bool cull_back) {
        // Viewport: NDC -> pixels (row 0 at the top), snapped to 1/256 pixel.
        std::array<SnappedVertex, 3> snapped;
        std::array<glm::dvec2, 3> screen;
        std::array<double, 3> inv_w, depth;
        std::array<glm::dvec3, 3> weights;
        for (int k = 0; k < 3; ++k) {
            const glm::dvec4& p = piece[std::size_t(k)].position;
            inv_w[std::size_t(k)] = 1.0 / p.w;
            const double x = (p.x * inv_w[std::size_t(k)] * 0.5 + 0.5) * width_;
            const double y = (0.5 - p.y * inv_w[std::size_t(k)] * 0.5) * height_;
            snapped[std::size_t(k)] = {snap(x), snap(y)};
            screen[std::size_t(k)] = {double(snapped[std::size_t(k)].x) / subpixel_scale, double(snapped[std::size_t(k)].y) / subpixel_scale};
            depth[std::size_t(k)] = p.z * inv_w[std::size_t(k)] * 0.5 + 0.5;
            weights[std::size_t(k)] = piece[std::size_t(k)].weights;
        }
        TriangleSetup s;
        if (!triangle_edges(snapped, s.edges)) { ++triangle_counters_.triangles_dropped; return; }
        // Counter-clockwise in NDC (y up) is front facing; y points down on screen, so a
        // front-facing triangle has negative signed area there.
        if (cull_back && twice_signed_area(snapped) > 0) { ++triangle_counters_.triangles_culled; return; }
        if (off_screen(snapped)) { ++triangle_counters_.triangles_culled; return; }
        ++triangle_counters_.triangles_set_up;
        if (!owns_any_row(s.edges)) return;  // all its rows belong to other workers

        s.screen = screen;
        const auto lambda = barycentric_planes(screen);
        s.depth = over_w_plane(lambda, depth, {1.0, 1.0, 1.0});  // depth is affine in screen space
        s.h.q = over_w_plane(lambda, {1.0, 1.0, 1.0}, inv_w);
        if ((needs & need_uv) || d.explain) {  // texr explain shows u and v even when unused
            std::array<double, 3> u = vertex_values(weights, tri, [&](std::uint32_t i) { return mesh.vertices[i].uv.x; });
            std::array<double, 3> v = vertex_values(weights, tri, [&](std::uint32_t i) { return mesh.vertices[i].uv.y; });
            if (d.texture) rebase(u, d.texture->sampler.wrap_u), rebase(v, d.texture->sampler.wrap_v);
            s.h.u_prime = over_w_plane(lambda, u, inv_w);
            s.h.v_prime = over_w_plane(lambda, v, inv_w);
            if (d.span_mode == SpanMode::affine) {  // the wrong answer, for contrast: no 1/w
                s.u_affine = over_w_plane(lambda, u, {1.0, 1.0, 1.0});
                s.v_affine = over_w_plane(lambda, v, {1.0, 1.0, 1.0});
            }
        }
        for (int axis = 0; axis < 3; ++axis) {
            if (needs & need_normal)
                s.normal[std::size_t(axis)] = over_w_plane(lambda, vertex_values(weights, tri, [&](std::uint32_t i) { return v_->normal[i][axis]; }), inv_w);
            if (needs & need_color)
                s.color[std::size_t(axis)] = over_w_plane(lambda, vertex_values(weights, tri, [&](std::uint32_t i) { return mesh.vertices[i].color[axis]; }), inv_w);
            if (needs & need_world_position)
                s.world[std::size_t(axis)] = over_w_plane(lambda, vertex_values(weights, tri, [&](std::uint32_t i) { return v_->world[i][axis]; }), inv_w);
        }
        walk_table[needs](d, s, rows_, fb_, stats_);
    }

    bool off_screen(const std::array<SnappedVertex, 3>& v) const {
        const std::int64_t half = subpixel_scale / 2;  // pixel centres are at 256 k + 128
        const std::int64_t min_x = std::min({v[0].x, v[1].x, v[2].x}), max_x = std::max({v[0].x, v[1].x, v[2].x});
        const std::int64_t min_y = std::min({v[0].y, v[1].y, v[2].y}), max_y = std::max({v[0].y, v[1].y, v[2].y});
        return max_x < half || max_y < half || min_x > (width_ - 1) * subpixel_scale + half ||
               min_y > (height_ - 1) * subpixel_scale + half;
    }

    bool owns_any_row(const TriangleEdges& edges) const {
        int first = 0, last = -1;
        row_range(edges, height_, first, last);
        return rows_.first_owned(first) <= last;
    }

public:
    // Per-triangle decisions are the same in every worker; worker 0's count is the frame's.
    RenderStats triangle_counters_;

private:
    const Scene& scene_;
    Framebuffer& fb_;
    RenderStats& stats_;
    int width_, height_;
    const RenderOptions& options_;
    GuardBand band_;
    const std::vector<Needs>& needs_;
    RowSet rows_;
    const TransformedMesh* v_ = nullptr;
    ClipPolygon polygon_;
    std::vector<double> u_scratch_, v_scratch_;
    PixelExplanation* explain_ = nullptr;
    int object_index_ = 0;
};

}  // namespace

int thread_count(int requested) {
    if (requested > 0) return requested;
    return std::max(1, int(std::thread::hardware_concurrency()));
}

Framebuffer render(const Scene& scene, const RenderOptions& options, RenderStats& stats) {
    const int width = options.width > 0 ? options.width : scene.width;
    const int height = options.height > 0 ? options.height : scene.height;
    Framebuffer fb(width, height, scene.background);
    if (options.count_coverage) fb.coverage.assign(fb.color.size(), 0);
    if (options.capture_uv) fb.uv.assign(fb.color.size(), glm::dvec2(std::nan("")));
    if (options.explain_x >= 0 && options.explain_y >= 0 && options.explain_x < width && options.explain_y < height) {
        fb.explanation = std::make_shared<PixelExplanation>();
        fb.explanation->x = options.explain_x, fb.explanation->y = options.explain_y;
    }
    std::vector<Needs> needs;
    for (const Material& m : scene.materials) needs.push_back(needs_of(m, scene));

    // Vertex stage, once for all workers.
    const auto vertex_start = Clock::now();
    const glm::dmat4 view_projection = projection_matrix(scene.camera, double(width) / double(height)) * view_matrix(scene.camera);
    std::vector<TransformedMesh> transformed;
    for (const Object& object : scene.objects) {
        const Mesh& mesh = scene.meshes[std::size_t(object.mesh)];
        Needs mesh_needs = 0;
        for (int m : mesh.triangle_material) mesh_needs |= needs[std::size_t(m)];
        transformed.push_back(transform(mesh, object, view_projection, mesh_needs));
    }
    stats.seconds_vertex += seconds_since(vertex_start);

    // Raster stage: each worker owns an interleaved set of row bands.
    const auto raster_start = Clock::now();
    const int workers = std::min(thread_count(options.threads), std::max(1, height / RowSet::band_rows));
    std::vector<RenderStats> worker_stats(static_cast<std::size_t>(workers));
    RenderStats triangle_counters;
    auto work = [&](int index) {
        FrameRenderer frame(scene, needs, options, RowSet{index, workers}, fb, worker_stats[std::size_t(index)]);
        for (std::size_t i = 0; i < scene.objects.size(); ++i) frame.draw(int(i), transformed[i]);
        if (index == 0) triangle_counters = frame.triangle_counters_;
    };
    std::vector<std::thread> threads;
    for (int t = 1; t < workers; ++t) threads.emplace_back(work, t);
    work(0);
    for (std::thread& t : threads) t.join();
    stats.add_counters(triangle_counters);
    for (const RenderStats& w : worker_stats) stats.add_counters(w);
    stats.seconds_raster += seconds_since(raster_start);
    return fb;
}

}  // namespace texr
