// The scanline walk (docs/design.md, "One frame"): for one prepared triangle, the spans
// of the rows a worker owns, pixel by pixel: depth test, (u, v) and the other
// attributes from their planes, texture lookup, shading (the short texture paths take
// spans of 16 pixels or more in batches, with the same arithmetic: shade_span_batched).
// Compiled once per Needs set.
// Internal to the renderer: included by src/render/renderer.cpp only.
#pragma once
#include <array>
#include <cstdint>
#include <utility>

#include "texr/core/scaling.h"
#include "texr/raster/edges.h"
#include "texr/raster/homography.h"
#include "texr/raster/span_modes.h"
#include "texr/raster/span_walk.h"
#include "texr/render/explain.h"
#include "texr/render/framebuffer.h"
#include "texr/render/needs.h"
#include "texr/render/stats.h"
#include "texr/texture/bump.h"
#include "texr/texture/environment.h"
#include "texr/texture/projective.h"
#include "texr/texture/lookup.h"
#include "texr/texture/lod_avx2.h"
#include "texr/texture/minify.h"
#include "texr/texture/reconstruct.h"

namespace texr {
namespace {

// Rows a worker draws: bands of band_rows rows, every count-th band from band `index` on.
// RowSet{w, workers} is worker w's fixed share, dealt round-robin; RowSet{b, band_count}
// is band b alone (a band taken by whichever worker is free). Either way each pixel is
// drawn by one worker, triangles in submission order, so the frame is the same bytes for
// any number of threads.
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
    // The next row after an owned row y: the next row of its band, or the first row of the
    // band `count` bands on (no division: this runs once per row of every triangle).
    int next_owned(int y) const { return (y + 1) % band_rows != 0 ? y + 1 : y + 1 + (count - 1) * band_rows; }
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
    bool finite_shading;  // shading_stays_finite: an 8-bit texel cannot make a NaN
    // avx2_lanes_available(), asked once per frame stage: a call in every span took the
    // grazing square's bilinear frame from 4.6 to 6.5 ms (its registers were lost around it).
    bool avx2_lanes;
};

// Whether shading with material m cannot give a NaN for a texel in [0, 1]: every colour it
// multiplies or adds (material, ambient, lights) is finite and at most 1e10 in magnitude,
// every directional light's vector at most 2 long (a point light's direction is
// normalised), and there are fewer than 1e6 lights, so that every
// product and sum in shade() stays below about 1e27. A parsed scene always passes (colours
// at most max_color, 3.5e9 linear; directions normalised); a scene built in code may not.
inline bool shading_stays_finite(const Scene& scene, const Material& m) {
    const auto small = [](const Color& c) {
        return std::fabs(c.x) <= 1e10f && std::fabs(c.y) <= 1e10f && std::fabs(c.z) <= 1e10f;  // (false for NaN)
    };
    if (!small(m.color) || !small(scene.ambient) || scene.lights.size() >= 1000000) return false;
    for (const Light& light : scene.lights)
        if (!small(light.color) || (light.kind == Light::Kind::directional && !(glm::dot(light.vector, light.vector) <= 4.0)))
            return false;
    return true;
}

// Everything the span walk needs of one screen triangle.
struct TriangleSetup {
    TriangleEdges edges;
    int first_row, last_row;  // rows whose centres it can cover (row_range), found once at setup
    Plane depth;             // window depth, affine in screen space
    TextureHomography h;     // u', v' and q = 1/w (q is also the divisor of every attribute)
    glm::dvec2 uv_shift{0.0};  // whole periods subtracted from the UVs (for texr explain)
    Plane u_affine, v_affine;  // SpanMode::affine only
    std::array<glm::dvec2, 3> screen;  // snapped vertices, for texr explain
    std::array<Plane, 3> normal, color, world;  // a/w planes, only those the draw needs
    SurfaceTangents tangents;  // O_u and O_v in world space, for a bump-mapped material
};

// `ldr_texel`: the texel is an 8-bit texture's, each channel in [0, 1] (the short paths).
// `texels` (where given) grows by the environment map's texels a reflection reads.
template <Needs N, bool ldr_texel = false>
Color shade(const DrawContext& d, const Color4& texel, const glm::dvec3& normal, const glm::dvec3& color,
            const glm::dvec3& world, std::uint64_t* texels = nullptr) {
    Color c = d.material.color;
    // (a solid texture's texel comes with the world position, without (u, v); 1 where no texture)
    if constexpr ((N & (need_uv | need_world_position)) != 0) c *= Color(texel);
    // Slope-based mapping: alpha flat + (1 - alpha) steep, alpha = n . direction in [0, 1].
    if constexpr ((N & need_normal) != 0)
        if (d.material.slope) {
            const float alpha = float(std::clamp(glm::dot(unit_direction(normal), d.material.slope_direction), 0.0, 1.0));
            c *= alpha * d.material.slope_flat + (1.0f - alpha) * d.material.slope_steep;
        }
    if constexpr ((N & need_color) != 0) c *= Color(color);
    if (d.material.lighting == Lighting::lambert) {
        Color irradiance = d.scene.ambient;
        if constexpr ((N & need_normal) != 0) {
            const glm::dvec3 n = unit_direction(normal);  // (corners' unit normals that nearly cancel blend to a tiny one)
            for (const Light& light : d.scene.lights) {
                glm::dvec3 to_light = -light.vector;
                if constexpr ((N & need_world_position) != 0)
                    if (light.kind == Light::Kind::point) to_light = unit_direction(light.vector - world);
                irradiance += light.color * float(std::max(0.0, glm::dot(n, to_light)));
            }
        }
        c *= irradiance;
    }
    // Reflection mapping: the environment map along the view ray reflected about the normal
    // (environment.h), blended in by the material's share.
    if constexpr ((N & need_normal) != 0 && (N & need_world_position) != 0)
        if (d.material.reflect > 0.0 && d.scene.environment >= 0) {
            const glm::dvec3 view = unit_direction(world - d.scene.camera.eye);
            const glm::dvec3 r = reflect_direction(view, unit_direction(normal));
            std::uint64_t read = 0;
            const Color mirrored(environment_value(d.scene.textures[std::size_t(d.scene.environment)], r, read));
            if (texels) *texels += read;
            c = float(1.0 - d.material.reflect) * c + float(d.material.reflect) * mirrored;
        }
    (void)texel, (void)normal, (void)color, (void)world, (void)texels;
    // An infinite texel (a float HDR texel times a bright material) times no light is NaN;
    // such a pixel is written as 0, the limit of its light, not as NaN. An 8-bit texel
    // cannot make one where shading_stays_finite, and the test is skipped there (it was
    // about a third of a nearest-filtered plane's frame).
    if constexpr (ldr_texel)
        if (d.finite_shading) return c;
    return {c.x == c.x ? c.x : 0.0f, c.y == c.y ? c.y : 0.0f, c.z == c.z ? c.z : 0.0f};
}

// A procedural texture's value at a pixel (or sub-pixel position) whose (u, v) and, for a
// solid texture, world position are given, with the footprint: the longer of the pixel's
// two sides in texture or world units (procedural.h: turbulence is band-limited by it).
inline Color4 procedural_texel(const Procedural& p, double u, double v, const glm::dvec3& world, double footprint) {
    return procedural_value(p, p.solid ? world : glm::dvec3(u, v, 0.0), footprint);
}

// The footprint of a pixel in world units: the longer of |dP/dx| and |dP/dy| for the world
// position P = P'/q, from its planes.
inline double world_footprint(const TriangleSetup& s, const glm::dvec3& world, double inv_q) {
    glm::dvec3 dx, dy;
    attribute_derivatives(s.world, s.h.q, world, inv_q, dx, dy);
    return std::max(glm::length(dx), glm::length(dy));
}

// The ground truth for texture filtering: the centres of spp x spp equal sub-pixel cells (a
// regular grid, no jitter), each with its exact (u, v) from the homography, read bilinearly
// from the base level; a procedural texture's pattern is evaluated there in full (every
// octave its `octaves` allows).
Color4 supersampled_texel(const DrawContext& d, const TriangleSetup& s, int x, int y, std::uint64_t& texels) {
    const TextureHomography& h = s.h;
    const int n = d.spp;
    const auto sample = [&](int i, int j) {
        const double sx = x + (i + 0.5) / n, sy = y + (j + 0.5) / n;
        const glm::dvec2 uv = h.uv_at(sx, sy);
        if (d.material.projector >= 0 || d.material.mapping.kind != Intermediate::none) {
            // a projected or mapped texture: where the projector throws it, or the intermediate
            // surface maps it, at each sample
            const double q = h.q.at(sx, sy);
            glm::dvec3 world;
            for (int a = 0; a < 3; ++a) world[a] = s.world[std::size_t(a)].at(sx, sy) / q;
            ProjectedUV thrown;
            if (d.material.projector >= 0) {
                thrown = project(d.scene.projectors[std::size_t(d.material.projector)], world, glm::dvec3(0.0), glm::dvec3(0.0));
            } else {
                const glm::dvec2 mapped = intermediate_uv(d.material.mapping, world);
                thrown.ahead = true, thrown.u = mapped.x, thrown.v = mapped.y;
            }
            if (!thrown.ahead) return d.texture->sampler.border;
            if (d.texture->procedural) return procedural_value(*d.texture->procedural, {thrown.u, thrown.v, 0.0}, 0.0);
            return sample_bilinear(d.texture->mipmap->base(), d.texture->sampler, thrown.u, thrown.v);
        }
        if (const Procedural* p = d.texture->procedural.get()) {
            glm::dvec3 world(0.0);
            if (p->solid) {
                const double q = h.q.at(sx, sy);
                for (int a = 0; a < 3; ++a) world[a] = s.world[std::size_t(a)].at(sx, sy) / q;
            }
            return procedural_texel(*p, uv.x, uv.y, world, 0.0);
        }
        return sample_bilinear(d.texture->mipmap->base(), d.texture->sampler, uv.x, uv.y);
    };
    Color4 sum(0.0f);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) sum += sample(i, j);
    texels += 4 * std::uint64_t(n) * std::uint64_t(n);
    if (!all_finite(sum)) {  // HDR texels near the float maximum overflowed the float sum
        glm::dvec4 total(0.0);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) total += glm::dvec4(sample(i, j));
        return Color4(total / double(n * n));
    }
    return sum / float(n * n);
}

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

// How a triangle's spans read its texture. `general` serves every case; the others are the
// short paths of the default sampler on a power-of-two 8-bit texture (reconstruct.h), taken
// when the spans record nothing: the choice is made once per triangle, so the pixel loop
// carries no test of filter, wrap, registration or instrumentation.
// bilinear_decoded is bilinear on an image that may have a decoded copy (Image::
// decoded_texels): each span reads the copy or, where the copy would not pay
// (span_reads_closely), the bytes.
enum class TexturePath { general, nearest, bilinear, bilinear_decoded, nearest_mip_nearest, bilinear_mip_nearest, trilinear };

// The short paths are compiled for textured materials with or without lighting normals;
// vertex colours or world positions (rarer, and each one more copy of the span loop to
// compile) take the general path. The mip filters need the derivatives.
template <Needs N>
constexpr bool has_short_paths = (N & need_uv) != 0 && (N & (need_color | need_world_position)) == 0;

template <Needs N>
TexturePath texture_path(const DrawContext& d, const Framebuffer& fb) {
    if constexpr (!has_short_paths<N>) return TexturePath::general;
    if (d.spp > 1 || !fb.uv.empty()) return TexturePath::general;
    // (a bump map's or a light map's (u, v) alone; an alpha test; a light map)
    if (!d.texture || d.material.cutout > 0.0f || d.material.lightmap >= 0) return TexturePath::general;
    const Texture& t = *d.texture;
    if (t.procedural || !takes_short_path(*t.image, t.sampler)) return TexturePath::general;
    constexpr bool footprint = (N & need_uv_derivatives) != 0;
    switch (t.sampler.filter) {
        case Filter::nearest: return TexturePath::nearest;
        case Filter::bilinear: return TexturePath::bilinear;
        case Filter::nearest_mip_nearest: return footprint ? TexturePath::nearest_mip_nearest : TexturePath::general;
        case Filter::bilinear_mip_nearest: return footprint ? TexturePath::bilinear_mip_nearest : TexturePath::general;
        case Filter::trilinear: return footprint ? TexturePath::trilinear : TexturePath::general;
        default: return TexturePath::general;
    }
}

// What the short paths read of a triangle's texture, loaded once per triangle: the base
// level, and the mip levels, looked up (and built, the first time) only when a pixel reads
// a level above the base: a texture that is never minified gets no levels.
// The mip filters that blend texels read the levels' decoded copies, where they have them
// (Image::decoded_texels); bilinear chooses span by span; nearest reads one texel, from
// its bytes and the decode table as fast as from a copy.
struct ShortPathTexture {
    LdrLevel base;
    const MipMap* mip = nullptr;
    int last = 0;  // index of the coarsest level
    bool decoded = false;
    const LdrLevel* levels = nullptr;

    const LdrLevel& level(int l) {
        if (l == 0) return base;
        if (!levels) levels = mip->ldr_levels(decoded);
        return levels[l];
    }
};

#if defined(__SSE2__)
// Trilinear between two levels that both have decoded copies: the two cells, the two
// lookups and their blend in SSE lanes, the same operations as trilinear_over's, and its 8
// texels counted. trilinear_decoded_lanes_at takes the level l0 = int(lambda) and the
// fraction float(lambda - l0) worked out, for a lambda its caller has checked to be strictly
// between 0 and the coarsest level (so that l0 + 1 is a level); false (and nothing read)
// when either level has no copy. trilinear_decoded_lanes checks lambda itself: false also
// at either end of the pyramid.
[[gnu::always_inline]] inline bool trilinear_decoded_lanes_at(ShortPathTexture& t, double u, double v, int l0, float fraction,
                                                              __m128& out, std::uint64_t& texels) {
    const LdrLevel &a = t.level(l0), &b = t.level(l0 + 1);
    if (!a.decoded || !b.decoded) return false;
    reconstruct_detail::ShortPathCell ca, cb;
    reconstruct_detail::short_path_cells(a, b, u, v, ca, cb);
    out = lerp_lanes(blend_decoded_lanes(a.decoded + ca.row0, a.decoded + ca.row1, ca.column0, ca.column1, ca.fx, ca.fy),
                     blend_decoded_lanes(b.decoded + cb.row0, b.decoded + cb.row1, cb.column0, cb.column1, cb.fx, cb.fy),
                     fraction);
    texels += 8;
    return true;
}
[[gnu::always_inline]] inline bool trilinear_decoded_lanes(ShortPathTexture& t, double u, double v, double lambda, __m128& out,
                                                           std::uint64_t& texels) {
    if (!(lambda > 0.0 && lambda < double(t.last))) return false;
    const int l0 = int(lambda);
    return trilinear_decoded_lanes_at(t, u, v, l0, float(lambda - l0), out, texels);
}
#endif

// The texture lookup of one pixel on a short path, at level of detail lambda (read by the
// mip filters only). The span's coordinates have been checked against the short paths'
// limit (span_within_short_path_limit).
template <TexturePath P>
[[gnu::always_inline]] inline Color4 short_path_lookup(ShortPathTexture& t, double u, double v, double lambda,
                                                       std::uint64_t& texels) {
    if constexpr (P == TexturePath::nearest) {
        texels += 1;
        return nearest_in(t.base, u, v);
    } else if constexpr (P == TexturePath::bilinear || P == TexturePath::bilinear_decoded) {
        texels += 4;
        return bilinear_in<P == TexturePath::bilinear_decoded ? TexelSource::decoded : TexelSource::bytes>(t.base, u, v);
    } else if constexpr (P == TexturePath::nearest_mip_nearest || P == TexturePath::bilinear_mip_nearest) {
        constexpr bool bilinear = P == TexturePath::bilinear_mip_nearest;
        texels += bilinear ? 4 : 1;
        const LdrLevel& l = t.level(minify_detail::nearest_level(t.last, lambda));
        return bilinear ? bilinear_in(l, u, v) : nearest_in(l, u, v);
    } else {
#if defined(__SSE2__)
        __m128 lanes;
        if (trilinear_decoded_lanes(t, u, v, lambda, lanes, texels)) return color_of_lanes(lanes);
#endif
        texels += std::uint64_t(trilinear_texels(t.last, lambda));
        return minify_detail::trilinear_over(t.last, lambda, [&](int l) { return bilinear_in(t.level(l), u, v); });
    }
}

#if defined(__SSE2__)
// A colour in lanes (r, g, b, and a lane not written) stored as the frame's three floats.
[[gnu::always_inline]] inline void write_colour(Color& out, __m128 c) {
    _mm_storel_pi(reinterpret_cast<__m64*>(&out.x), c);
    _mm_store_ss(&out.z, _mm_movehl_ps(c, c));
}

// Trilinear's pass 3 where the material only multiplies the texel by its colour: the batch's
// levels and fractions first, two at a time (the plane's frame 5.80-5.86 -> 5.36-5.55 ms when
// it came, 1 thread, alternated runs), then each pixel's lookup and colour. Compiled twice:
// for the baseline, and for AVX2 (avx2_lanes_available), where the same SSE operations take
// the VEX encoding's three operands and fewer register copies: 5.12-5.17 -> 4.98-5.04 ms.
[[gnu::always_inline]] inline void trilinear_colour_pass(ShortPathTexture& t, int n, const double* us, const double* vs,
                                                         const double* lambdas, const int* xs, __m128 material_colour,
                                                         Color* color_row, std::uint64_t& texels) {
    int l0s[32];
    float fractions[32];
    trilinear_levels_lanes(lambdas, n, t.last, l0s, fractions);
    for (int k = 0; k < n; ++k) {
        __m128 texel;
        if (l0s[k] < 0 || !trilinear_decoded_lanes_at(t, us[k], vs[k], l0s[k], fractions[k], texel, texels)) {
            // (either end of the pyramid, or a level without a copy: short_path_lookup's way)
            const Color4 c = short_path_lookup<TexturePath::trilinear>(t, us[k], vs[k], lambdas[k], texels);
            texel = _mm_setr_ps(c.x, c.y, c.z, c.w);
        }
        write_colour(color_row[xs[k]], _mm_mul_ps(material_colour, texel));
    }
}
[[gnu::noinline]] void trilinear_colour_pass_sse2(ShortPathTexture& t, int n, const double* us, const double* vs,
                                                  const double* lambdas, const int* xs, __m128 material_colour,
                                                  Color* color_row, std::uint64_t& texels) {
    trilinear_colour_pass(t, n, us, vs, lambdas, xs, material_colour, color_row, texels);
}
__attribute__((target("avx2"), noinline)) void trilinear_colour_pass_avx2(ShortPathTexture& t, int n, const double* us,
                                                                         const double* vs, const double* lambdas,
                                                                         const int* xs, __m128 material_colour,
                                                                         Color* color_row, std::uint64_t& texels) {
    trilinear_colour_pass(t, n, us, vs, lambdas, xs, material_colour, color_row, texels);
}
#endif

// Whether every (u, v) of a span is within the short paths' limit, so that no pixel needs
// the check. Stepped coordinates: u = u'/q with u' and q linear along the span and q > 0,
// so |u| <= max |u'| / min q over the span's two ends. Stepping n pixels drifts each value
// by at most about n 2^-53 times the larger end's magnitude: the factor 2 kept on |u'|
// covers that for u', but for q the drift is relative to the larger q, which can be 1e12
// times the smaller one, so it is subtracted (generously: n 2^-50) before halving.
// Other span modes: the bound their span mode kept on the coordinates it computed.
inline bool span_within_short_path_limit(const ShortPathTexture& t, bool stepped, SteppedPlane u_prime, SteppedPlane v_prime,
                                         SteppedPlane q, int n, const CoordinateBound& given) {
    if (stepped) {
        const double last = double(n - 1);
        const double q_end = q.value + q.step * last;
        const double drift = double(n) * 0x1p-50 * std::max(std::fabs(q.value), std::fabs(q_end));
        const double q_min = 0.5 * (std::min(q.value, q_end) - drift);
        if (!(q_min > 0.0)) return false;
        const double u_max = 2.0 * std::max(std::fabs(u_prime.value), std::fabs(u_prime.value + u_prime.step * last));
        const double v_max = 2.0 * std::max(std::fabs(v_prime.value), std::fabs(v_prime.value + v_prime.step * last));
        return minify_detail::within_short_path_limit(u_max / q_min, v_max / q_min, t.base.width, t.base.height);
    }
    // |u W| + 1 < limit for every pixel (false for NaN), as within_short_path_limit, from the
    // bound the span mode kept while computing them: each |u| is at most given.u (1 + 2^-48).
    // (The limit is shrunk by 2^-46, so that rounding can only send a span to the general path.)
    const double u_limit = (short_path_limit - 1.0) / t.base.width * (1.0 - 0x1p-46);
    const double v_limit = (short_path_limit - 1.0) / t.base.height * (1.0 - 0x1p-46);
    return given.u < u_limit && given.v < v_limit;
}

// Whether bilinear lookups along a span read the decoded copy (TexturePath::
// bilinear_decoded) rather than the bytes: the copy saves work on every lookup, but it is 4
// times the bytes, and a cache line of it holds 4 texels of a row where a line of bytes
// holds 16. It pays where the span's texels are read again soon after:
//   - where neighbours share texels: at most one texel a pixel along the span (|du/dx| W)
//     and two from row to row (|dv/dy| H), so the next row finds them too;
//   - or where the span runs over its texture rows at least once end to end (its length
//     times its smallest |du/dx| W at least the texture's width W): the far rows of a plane
//     receding to the horizon, each of which reads one pair of texture rows over and over.
// Either way the span must cross at most max_rows_per_pixel texture rows a pixel (|dv/dx|
// H): a span that crosses rows (a square at a grazing angle, turned) reads new lines at
// every pixel. The derivatives are taken at the span's two ends (along a row, du/dx and
// dv/dx are c / q^2 for a constant c, so their extremes are there; dv/dy's numerator varies
// along the row, so its value between the ends may be larger: an estimate, which only ever
// changes the time, never the bytes). A NaN derivative reads the bytes.
// Measured, 1 thread, alternated runs, bytes against this choice: the receding plane
// 3.67-3.89 / 2.74-2.90 ms, at 1920x1080 10.06-10.43 / 7.06-7.19 ms; a minified
// 10k-triangle terrain 15.89-16.17 / 16.54-16.81 ms; the grazing square 4.63-4.70 /
// 4.50-4.68 ms. Reading the copy on every span took the terrain to 19-23 ms and the grazing
// square to 4.8-5.2 ms (from 4.5).
constexpr double max_rows_per_pixel = 4.0;
inline bool span_reads_closely(const TextureHomography& h, double width, double height, int y, int x0, int x1) {
    double su_min = 1e300, su_max = 0.0, sv_max = 0.0;
    for (const int x : {x0, x1 - 1}) {
        const double px = x + 0.5, py = y + 0.5;
        const double inv_q = 1.0 / h.q.at(px, py);
        const UVDerivatives d =
            uv_derivatives_from_inverse_q(h, h.u_prime.at(px, py) * inv_q, h.v_prime.at(px, py) * inv_q, inv_q);
        if (!(std::fabs(d.dvdx) * height <= max_rows_per_pixel)) return false;  // (also false for NaN)
        const double su = std::fabs(d.dudx) * width, sv = std::fabs(d.dvdy) * height;
        if (std::isnan(su) || std::isnan(sv)) return false;
        su_min = std::min(su_min, su), su_max = std::max(su_max, su), sv_max = std::max(sv_max, sv);
    }
    if (su_max <= 1.0 && sv_max <= 2.0) return true;  // neighbours share texels
    return double(x1 - x0) * su_min >= width;         // the span runs over its rows
}

// Spans shorter than this are walked pixel by pixel. (The 1M-triangle terrain, whose spans
// are mostly one or two pixels, took 85M more instructions (5%) when every span was batched.)
constexpr int batched_from = 16;

// The span walk of a short path. The same values as shade_span_on's, computed in batches of
// pixels and three passes per batch, so that no pixel's long chain of dependent steps
// (divide, level of detail, texel address, texel loads, blend) waits for the one before:
//   1. in order along the span: the depth test, stepping every value; the pixels that pass
//      keep their stepped values;
//   2. for those pixels: 1/q, (u, v) and the level of detail, each pixel independent;
//   3. for those pixels: the texture lookup and shading.
// A triangle covers each pixel of a span once, so the order of passes 2 and 3 among pixels
// changes nothing: the frame is the same bytes as a pixel-by-pixel walk.
template <Needs N, TexturePath P>
void shade_span_batched(const DrawContext& d, const TriangleSetup& s, int y, Span span, Framebuffer& fb, RenderStats& stats,
                        ShortPathTexture& t, bool stepped_uv, SteppedPlane depth, SteppedPlane q, SteppedPlane u_prime,
                        SteppedPlane v_prime, SteppedVector normal) {
    // Pixels per batch: 32 took the plane's bilinear frame 2% below 64's (3.75-3.79 against
    // 3.84-3.98 ms); 16, 24 and 128 were no better; trilinear and the grazing square were
    // the same for all.
    constexpr int batch = 32;
    constexpr bool lit = (N & need_normal) != 0;
    constexpr bool footprint = P == TexturePath::nearest_mip_nearest || P == TexturePath::bilinear_mip_nearest ||
                               P == TexturePath::trilinear;
    // 1/q is needed by stepped (u, v), the footprint and the normal.
    const bool divide = stepped_uv || footprint || lit;
    float* depth_row = &fb.depth[fb.index(0, y)];
    Color* color_row = &fb.color[fb.index(0, y)];
    std::uint64_t shaded = 0, texels = 0;
#if defined(__SSE2__)
    const bool colour_times_texel = d.material.lighting != Lighting::lambert && d.finite_shading;
    const bool avx2 = d.avx2_lanes;
    const __m128 material_colour = _mm_setr_ps(d.material.color.x, d.material.color.y, d.material.color.z, 0.0f);
#endif
    for (int first = span.x0; first < span.x1; first += batch) {
        const int end = std::min(span.x1, first + batch);
        int xs[batch];
        double qs[batch], us[batch], vs[batch], lambdas[footprint ? batch : 1];
        glm::dvec3 normals[lit ? batch : 1];
        int n = 0;
        for (int x = first; x < end; ++x) {  // pass 1
            if (float(depth.value) < depth_row[x]) {
                depth_row[x] = float(depth.value);
                xs[n] = x, qs[n] = q.value;
                us[n] = stepped_uv ? u_prime.value : d.u_scratch[x - span.x0];  // other span modes: given
                vs[n] = stepped_uv ? v_prime.value : d.v_scratch[x - span.x0];
                if constexpr (lit) normals[n] = normal.value();
                ++n;
            }
            depth.advance(), q.advance(), u_prime.advance(), v_prime.advance();
            if constexpr (lit) normal.advance();
        }
        int k = 0;  // pass 2
#if defined(__SSE2__)
        // Four pixels at a time where the CPU has AVX2 (levels_of_detail_avx2, for the
        // footprint filters), then two at a time, one in each lane of SSE2's doubles, with the
        // same operations as the loop below, so the same bits (level_of_detail_lanes). The
        // divide's and the level of detail's chains then overlap for more pixels. Measured
        // when the SSE2 lanes came, 1 thread, alternated runs: the plane's trilinear frame
        // 7.87-8.23 -> 7.13-7.24 ms, bilinear 2.89-2.95 -> 2.79-2.88 ms.
        if constexpr (footprint)
            if (avx2) k = levels_of_detail_avx2(s.h, int(t.base.width), int(t.base.height), stepped_uv, n, qs, us, vs, lambdas);
        if (divide)
            for (; k + 1 < n; k += 2) {
                const __m128d inv_q = _mm_div_pd(_mm_set1_pd(1.0), _mm_loadu_pd(qs + k));
                _mm_storeu_pd(qs + k, inv_q);
                __m128d u = _mm_loadu_pd(us + k), v = _mm_loadu_pd(vs + k);
                if (stepped_uv) {
                    u = _mm_mul_pd(u, inv_q), v = _mm_mul_pd(v, inv_q);
                    _mm_storeu_pd(us + k, u), _mm_storeu_pd(vs + k, v);
                }
                if constexpr (footprint) {
                    const auto derivative = [&](double d_prime, __m128d value, double dq) {  // uv_derivatives_from_inverse_q
                        return _mm_mul_pd(_mm_sub_pd(_mm_set1_pd(d_prime), _mm_mul_pd(value, _mm_set1_pd(dq))), inv_q);
                    };
                    const __m128d lambda = level_of_detail_lanes(
                        derivative(s.h.u_prime.dx, u, s.h.q.dx), derivative(s.h.v_prime.dx, v, s.h.q.dx),
                        derivative(s.h.u_prime.dy, u, s.h.q.dy), derivative(s.h.v_prime.dy, v, s.h.q.dy),
                        int(t.base.width), int(t.base.height));
                    _mm_storeu_pd(lambdas + k, lambda);
                }
            }
#endif
        for (; k < n; ++k) {
            const double inv_q = divide ? 1.0 / qs[k] : 1.0;  // the one divide per pixel
            qs[k] = inv_q;
            if (stepped_uv) us[k] *= inv_q, vs[k] *= inv_q;
            if constexpr (footprint)  // 1/q is at hand: no second divide
                lambdas[k] = level_of_detail(uv_derivatives_from_inverse_q(s.h, us[k], vs[k], inv_q), int(t.base.width),
                                             int(t.base.height));
        }
#if defined(__SSE2__)
        // The material's colour times the texel, and nothing else to shade (no light, no
        // vertex colour, no NaN to catch): in lanes, as shade() would work it out. (The
        // plane's trilinear frame 6.51-6.74 -> 6.07-6.19 ms when it came, 1 thread,
        // alternated runs.)
        if constexpr ((P == TexturePath::bilinear_decoded || P == TexturePath::trilinear) &&
                      (N & (need_normal | need_color | need_world_position)) == 0)
            if (colour_times_texel) {
                if constexpr (P == TexturePath::trilinear) {
                    if (avx2)
                        trilinear_colour_pass_avx2(t, n, us, vs, lambdas, xs, material_colour, color_row, texels);
                    else
                        trilinear_colour_pass_sse2(t, n, us, vs, lambdas, xs, material_colour, color_row, texels);
                } else {
                    for (int k = 0; k < n; ++k) {  // (bilinear from the copy)
                        texels += 4;
                        const __m128 texel = bilinear_decoded_lanes(t.base, us[k], vs[k]);
                        write_colour(color_row[xs[k]], _mm_mul_ps(material_colour, texel));
                    }
                }
                shaded += std::uint64_t(n);
                continue;
            }
#endif
        for (int k = 0; k < n; ++k) {  // pass 3
            const Color4 texel = short_path_lookup<P>(t, us[k], vs[k], footprint ? lambdas[k] : 0.0, texels);
            const glm::dvec3 normal_k = lit ? normals[k] * qs[k] : glm::dvec3(0.0);
            color_row[xs[k]] = shade<N, true>(d, texel, normal_k, glm::dvec3(0.0), glm::dvec3(0.0));
        }
        shaded += std::uint64_t(n);
    }
    stats.pixels_shaded += shaded;
    stats.texels_fetched += texels;
}

// The span walk of one row (docs/design.md, "Determinism and bounded error"): values at the first
// pixel centre come from the plane equations; within the span they are stepped by their
// constant x derivatives: u' += du'/dx, v' += dv'/dx, q += dq/dx.
template <Needs N, TexturePath P>
void shade_span_on(const DrawContext& d, const TriangleSetup& s, int y, Span span, Framebuffer& fb, RenderStats& stats,
                   ShortPathTexture& short_path) {
    constexpr bool perspective = (N & (need_uv | need_normal | need_color | need_world_position)) != 0;
    constexpr bool general = P == TexturePath::general;
    const int x0 = span.x0;
    // Texture coordinates: stepped here (incremental), or precomputed for the span by
    // another span mode, which may need no divide per pixel at all.
    bool stepped_uv = (N & need_uv) != 0 && d.span_mode == SpanMode::incremental;
    CoordinateBound bound;  // of the precomputed coordinates
    if constexpr ((N & need_uv) != 0)
        if (!stepped_uv) {
            SpanTexturing t;
            t.h = &s.h, t.u_affine = s.u_affine, t.v_affine = s.v_affine, t.tolerance = d.span_tolerance;
            // (texels: a procedural texture's tolerance is in its finest detail's units: a cell of
            // its pattern, or of turbulence's last octave)
            if (!d.texture)  // (a bump map's (u, v): tolerance in units of u and v)
                t.width = t.height = 1.0;
            else if (const Procedural* p = d.texture->procedural.get())
                t.width = t.height = p->pattern == Pattern::turbulence || p->pattern == Pattern::marble
                                         ? std::ldexp(p->scale, p->octaves - 1)
                                         : p->scale;
            else
                t.width = d.texture->mipmap->base().width(), t.height = d.texture->mipmap->base().height();
            if (d.span_mode == SpanMode::adaptive && adaptive_steps_whole_span(t, y, x0, span.x1 - x0))
                stepped_uv = true;  // it would step every pixel: step them here
            else
                span_texture_coordinates(d.span_mode, t, y, x0, span.x1 - x0, d.u_scratch, d.v_scratch, bound);
        }

    SteppedPlane depth = SteppedPlane::start(s.depth, x0, y);
    SteppedPlane u_prime, v_prime, q;
    SteppedVector normal{}, color{}, world{};
    if constexpr (perspective) q = SteppedPlane::start(s.h.q, x0, y);
    if constexpr ((N & need_uv) != 0) u_prime = SteppedPlane::start(s.h.u_prime, x0, y), v_prime = SteppedPlane::start(s.h.v_prime, x0, y);
    if constexpr ((N & need_normal) != 0) normal = SteppedVector::start(s.normal, x0, y);
    if constexpr ((N & need_color) != 0) color = SteppedVector::start(s.color, x0, y);
    if constexpr ((N & need_world_position) != 0) world = SteppedVector::start(s.world, x0, y);
    if constexpr (!general) {
        if (!span_within_short_path_limit(short_path, stepped_uv, u_prime, v_prime, q, span.x1 - x0, bound))
            return shade_span_on<N, TexturePath::general>(d, s, y, span, fb, stats, short_path);
        if (P != TexturePath::nearest && span.x1 - x0 >= batched_from)
            return shade_span_batched<N, P>(d, s, y, span, fb, stats, short_path, stepped_uv, depth, q, u_prime, v_prime, normal);
    }
    {  // pixel by pixel: the general path, nearest (whose short chain gains nothing from
       // batches) and short spans (which would pay more to set a batch up than it saves)
        // 1/q per pixel is needed by perspective attributes, derivatives and stepped (u, v).
        constexpr bool attributes_need_q = (N & (need_uv_derivatives | need_normal | need_color | need_world_position)) != 0;
        const bool divide = attributes_need_q || stepped_uv;
        float* depth_row = &fb.depth[fb.index(0, y)];
        Color* color_row = &fb.color[fb.index(0, y)];
        glm::dvec2* uv_row = !general || fb.uv.empty() ? nullptr : &fb.uv[fb.index(0, y)];
        glm::dvec3* world_row = !general || fb.world_read.empty() ? nullptr : &fb.world_read[fb.index(0, y)];
        // A solid procedural texture reads the world position, not (u, v).
        const Procedural* solid = d.texture && d.texture->procedural && d.texture->procedural->solid ? d.texture->procedural.get() : nullptr;
        // A projector's texture is read where it throws it on the world position.
        const Projector* projector = d.texture && d.material.projector >= 0 ? &d.scene.projectors[std::size_t(d.material.projector)] : nullptr;
        // Or at an intermediate surface's (u, v) of the world position.
        const IntermediateMapping* mapping = d.texture && d.material.mapping.kind != Intermediate::none ? &d.material.mapping : nullptr;
        (void)solid, (void)world_row, (void)projector, (void)mapping;
        std::uint64_t shaded = 0, texels = 0;
        for (int x = span.x0; x < span.x1; ++x) {
            if (float(depth.value) < depth_row[x]) {
                double inv_q = 1.0;
                if constexpr (perspective)
                    if (divide) inv_q = 1.0 / q.value;  // the one divide per pixel
                Color4 texel(1.0f);
                Color irradiance_map(1.0f);  // a light map's E (general path)
                glm::dvec3 pixel_normal = normal.value() * inv_q;
                if constexpr ((N & need_uv) != 0) {
                    const double u = stepped_uv ? u_prime.value * inv_q : d.u_scratch[x - x0];
                    const double v = stepped_uv ? v_prime.value * inv_q : d.v_scratch[x - x0];
                    UVDerivatives derivatives{0.0, 0.0, 0.0, 0.0};
                    if constexpr ((N & need_uv_derivatives) != 0)  // 1/q is at hand: no second divide
                        derivatives = uv_derivatives_from_inverse_q(s.h, u, v, inv_q);
                    if constexpr (general && (N & need_normal) != 0)
                        if (d.material.bump >= 0) {  // (the walk's general path: bump maps need world positions)
                            // Read at the scene's (u, v): the setup moved them by whole periods of
                            // the colour texture's wrap mode, which need not be the bump map's.
                            const Texture& bump = d.scene.textures[std::size_t(d.material.bump)];
                            const BumpSlope slope = bump_slope(bump, d.material.bump_height, u + s.uv_shift.x, v + s.uv_shift.y,
                                                               footprint_length(derivatives), texels);
                            pixel_normal = bumped_normal(unit_direction(pixel_normal), s.tangents, slope);
                        }
                    if constexpr (general) {
                        if (!d.texture || solid || projector || mapping) {
                            // (a material without a texture reads (u, v) for its bump or light map
                            // alone; a solid or projected texture is read below)
                        } else if (d.spp > 1) {
                            texel = supersampled_texel(d, s, x, y, texels);
                        } else if (const Procedural* p = d.texture->procedural.get()) {
                            const double footprint = (N & need_uv_derivatives) == 0 ? 0.0 : footprint_length(derivatives);
                            texel = procedural_value(*p, {u, v, 0.0}, footprint);
                        } else {
                            texel = lookup(*d.texture, u, v, derivatives, texels);
                        }
                        if (uv_row) uv_row[x] = {u, v};
                        if (d.material.lightmap >= 0) {
                            // The light map's irradiance at the scene's (u, v) / repeat (the setup's
                            // shift of whole periods of the colour texture added back).
                            const double r = d.material.lightmap_repeat;
                            const double lu = (u + s.uv_shift.x) / r, lv = (v + s.uv_shift.y) / r;
                            const UVDerivatives scaled{derivatives.dudx / r, derivatives.dvdx / r, derivatives.dudy / r, derivatives.dvdy / r};
                            const Texture& map = d.scene.textures[std::size_t(d.material.lightmap)];
                            irradiance_map = Color(map.procedural ? procedural_value(*map.procedural, {lu, lv, 0.0}, 0.0)
                                                                  : lookup(map, lu, lv, scaled, texels));
                        }
                    } else {
                        constexpr bool footprint = (N & need_uv_derivatives) != 0;
                        const double lambda = footprint ? level_of_detail(derivatives, int(short_path.base.width), int(short_path.base.height)) : 0.0;
                        texel = short_path_lookup<P>(short_path, u, v, lambda, texels);
                    }
                }
                if constexpr (general && (N & need_world_position) != 0)
                    if (solid) {
                        const glm::dvec3 at = world.value() * inv_q;
                        if (d.spp > 1)
                            texel = supersampled_texel(d, s, x, y, texels);
                        else  // (point-sampled patterns need no footprint)
                            texel = procedural_value(*solid, at, band_limited(solid->pattern) ? world_footprint(s, at, inv_q) : 0.0);
                        if (world_row) world_row[x] = at;
                    }
                if constexpr (general && (N & need_world_position) != 0)
                    if (projector || mapping) {
                        const glm::dvec3 at = world.value() * inv_q;
                        glm::dvec3 dp_dx, dp_dy;  // the world position's screen derivatives
                        attribute_derivatives(s.world, s.h.q, at, inv_q, dp_dx, dp_dy);
                        ProjectedUV thrown;
                        if (projector) {
                            thrown = project(*projector, at, dp_dx, dp_dy);
                        } else {  // (an intermediate surface maps every point)
                            const glm::dvec2 uv = intermediate_uv(*mapping, at);
                            thrown.ahead = true, thrown.u = uv.x, thrown.v = uv.y;
                            thrown.d = intermediate_derivatives(*mapping, at, dp_dx, dp_dy);
                        }
                        if (d.spp > 1)
                            texel = supersampled_texel(d, s, x, y, texels);
                        else if (!thrown.ahead)  // (behind the projector: nothing thrown, the texture's border colour)
                            texel = d.texture->sampler.border;
                        else if (d.texture->procedural)
                            texel = procedural_value(*d.texture->procedural, {thrown.u, thrown.v, 0.0}, footprint_length(thrown.d));
                        else
                            texel = lookup(*d.texture, thrown.u, thrown.v, thrown.d, texels);
                        if (world_row) world_row[x] = at;
                    }
                if constexpr (general) texel *= Color4(irradiance_map, 1.0f);
                // A cutout material's texels below its alpha threshold are holes: the pixel keeps
                // what is behind (its depth too). (The short paths never draw such a material.)
                // (within 1e-4: a filter's alpha of opaque texels may round to just below 1, as
                // bicubic's 16 weights do)
                if (!general || d.material.cutout <= 0.0f || texel.w >= d.material.cutout - 1e-4f) {
                    depth_row[x] = float(depth.value);
                    color_row[x] = shade<N, !general>(d, texel, pixel_normal, color.value() * inv_q, world.value() * inv_q, &texels);
                    ++shaded;
                }
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
}

// Whether a span of TexturePath::bilinear_decoded reads the base level's decoded copy: a
// span walked in batches (shorter ones, a fine mesh's, would pay more for the choice than
// they gain) that reads closely, once the copy is made (for the first such span; null over
// budget).
inline bool reads_decoded_copy(const DrawContext& d, const TriangleSetup& s, int y, Span span, ShortPathTexture& t) {
    if (span.x1 - span.x0 < batched_from || !span_reads_closely(s.h, t.base.width, t.base.height, y, span.x0, span.x1))
        return false;
    if (!t.base.decoded) t.base.decoded = d.texture->image->decoded_texels();
    return t.base.decoded != nullptr;
}

template <Needs N>
void shade_span(const DrawContext& d, const TriangleSetup& s, int y, Span span, Framebuffer& fb, RenderStats& stats,
                TexturePath path, ShortPathTexture& t) {
    if constexpr (has_short_paths<N>) {
        switch (path) {
            case TexturePath::nearest: return shade_span_on<N, TexturePath::nearest>(d, s, y, span, fb, stats, t);
            case TexturePath::bilinear: return shade_span_on<N, TexturePath::bilinear>(d, s, y, span, fb, stats, t);
            case TexturePath::bilinear_decoded:
                if (reads_decoded_copy(d, s, y, span, t))
                    return shade_span_on<N, TexturePath::bilinear_decoded>(d, s, y, span, fb, stats, t);
                return shade_span_on<N, TexturePath::bilinear>(d, s, y, span, fb, stats, t);
            case TexturePath::nearest_mip_nearest:
            case TexturePath::bilinear_mip_nearest:
            case TexturePath::trilinear:
                if constexpr ((N & need_uv_derivatives) != 0) {  // texture_path chose them only then
                    if (path == TexturePath::trilinear) return shade_span_on<N, TexturePath::trilinear>(d, s, y, span, fb, stats, t);
                    if (path == TexturePath::nearest_mip_nearest)
                        return shade_span_on<N, TexturePath::nearest_mip_nearest>(d, s, y, span, fb, stats, t);
                    return shade_span_on<N, TexturePath::bilinear_mip_nearest>(d, s, y, span, fb, stats, t);
                }
                break;
            case TexturePath::general: break;
        }
    }
    (void)path;
    shade_span_on<N, TexturePath::general>(d, s, y, span, fb, stats, t);
}

template <Needs N>
void record(const DrawContext& d, const TriangleSetup& s, const Framebuffer& fb) {
    PixelExplanation& e = *d.explain;
    const std::size_t i = fb.index(e.x, e.y);
    e.covered = true;
    e.object = d.object, e.triangle = d.triangle, e.material = d.material_index, e.clipped = d.clipped;
    e.screen = s.screen, e.h = s.h, e.uv_shift = s.uv_shift, e.depth = fb.depth[i], e.color = fb.color[i];
    e.tangents = s.tangents;
    // (the planes a material does not need are not set up: left as they are)
    if constexpr ((N & need_normal) != 0) e.normal = s.normal;
    if constexpr ((N & need_color) != 0) e.vertex_color = s.color;
    if constexpr ((N & need_world_position) != 0) e.world = s.world;
}

template <Needs N>
void walk_triangle(const DrawContext& d, const TriangleSetup& s, const RowSet& rows, Framebuffer& fb, RenderStats& stats) {
    TexturePath path = texture_path<N>(d, fb);
    ShortPathTexture short_path;
    if (path != TexturePath::general) {
        // The mip filters read the decoded copies of every level that has one; bilinear decides
        // span by span (span_reads_closely) and has its copy made by the first span that reads it.
        short_path.decoded = path == TexturePath::bilinear_mip_nearest || path == TexturePath::trilinear;
        short_path.base = d.texture->image->ldr_level(short_path.decoded);
        short_path.mip = d.texture->mipmap.get();
        short_path.last = short_path.mip ? short_path.mip->level_count() - 1 : 0;
        // (A triangle narrower than a batched span has no span that could read the copy.)
        if (path == TexturePath::bilinear && d.texture->image->may_be_decoded() &&
            std::max({s.screen[0].x, s.screen[1].x, s.screen[2].x}) - std::min({s.screen[0].x, s.screen[1].x, s.screen[2].x}) >=
                batched_from - 1)
            path = TexturePath::bilinear_decoded;
    }
    for (int y = rows.first_owned(s.first_row); y <= s.last_row; y = rows.next_owned(y)) {
        const Span span = span_for_row(s.edges, y, fb.width);
        if (span.x0 >= span.x1) continue;
        ++stats.spans;
        // texr explain: did this triangle win the explained pixel?
        const bool explained = d.explain && y == d.explain->y && d.explain->x >= span.x0 && d.explain->x < span.x1;
        const float depth_before = explained ? fb.depth[fb.index(d.explain->x, y)] : 0.0f;
        if (!fb.coverage.empty())  // test instrumentation: every covered pixel, before the depth test
            for (int x = span.x0; x < span.x1; ++x) ++fb.coverage[fb.index(x, y)];
        shade_span<N>(d, s, y, span, fb, stats, path, short_path);
        if (explained && fb.depth[fb.index(d.explain->x, y)] != depth_before) record<N>(d, s, fb);
    }
}

// One compiled walk per Needs set.
using WalkFunction = void (*)(const DrawContext&, const TriangleSetup&, const RowSet&, Framebuffer&, RenderStats&);
template <std::size_t... I>
constexpr std::array<WalkFunction, sizeof...(I)> make_walk_table(std::index_sequence<I...>) {
    return {&walk_triangle<Needs(I)>...};
}
constexpr auto walk_table = make_walk_table(std::make_index_sequence<need_all + 1>());

}  // namespace
}  // namespace texr
