// texr explain: one pixel's story as text (see include/texr/render/explain.h).
#include "texr/render/explain.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "texr/core/error.h"
#include "texr/core/scaling.h"
#include "texr/texture/environment.h"
#include "texr/texture/ewa.h"
#include "texr/texture/projective.h"
#include "texr/texture/lookup.h"
#include "texr/texture/minify.h"
#include "texr/texture/reconstruct.h"
#include "texr/texture/wrap.h"

namespace texr {

namespace {

std::string format(const char* pattern, double a = 0, double b = 0, double c = 0, double d = 0) {
    // As long as it needs to be: %.4f of a coordinate near 1e300 is some 300 characters.
    const int length = std::snprintf(nullptr, 0, pattern, a, b, c, d);
    if (length <= 0) return "";
    std::string out(std::size_t(length) + 1, '\0');
    std::snprintf(out.data(), out.size(), pattern, a, b, c, d);
    out.pop_back();
    return out;
}

// A texture or lattice coordinate: to 4 (or 6) decimals, but in powers of ten from 1e15 on,
// where no fraction is left to show (UVs near 1e308 took 309 digits). No "-0.0000", no "-nan".
std::string coordinate(double x, int decimals = 4) {
    if (std::isnan(x)) return "nan";
    if (!(std::fabs(x) < 1e15)) return format("%.6e", x);
    const std::string shown = format(decimals == 6 ? "%.6f" : "%.4f", x);
    return shown.find_first_not_of("-0.") == std::string::npos && shown[0] == '-' ? shown.substr(1) : shown;
}

// A colour channel: %.5f, or %.6g from 1e6 on (an HDR texel near the float maximum would take
// 39 digits), in parentheses with its neighbours. No "-0.00000" (for -0 or a tiny negative
// value) and no "-nan".
std::string channel(double x) {
    if (std::isnan(x)) return "nan";
    const std::string shown = format(std::fabs(x) < 1e6 || !std::isfinite(x) ? "%.5f" : "%.6g", x);
    return shown == "-0.00000" ? "0.00000" : shown;
}
std::string channels(double x, double y, double z) { return "(" + channel(x) + ", " + channel(y) + ", " + channel(z) + ")"; }
std::string channels(const Color4& c) { return "(" + channel(c.x) + ", " + channel(c.y) + ", " + channel(c.z) + ", " + channel(c.w) + ")"; }

std::string matrix(const glm::dmat3& m, const char* const rows[3]) {
    std::string out;
    for (int r = 0; r < 3; ++r)  // glm is column-major: m[column][row]
        out += "    " + std::string(rows[r]) + format(" [ %14.8g %14.8g %14.8g ]\n", m[0][r], m[1][r], m[2][r]);
    return out;
}

const char* wrap_name(Wrap w) {
    switch (w) {
        case Wrap::repeat: return "repeat";
        case Wrap::mirror: return "mirror";
        case Wrap::clamp: return "clamp";
        case Wrap::border: return "border";
    }
    return "?";
}

// The mip levels the texture's filter reads at this pixel, worked out as the samplers do
// (minify.h, ewa.h), with lambda the level of detail (texr's, as OpenGL's: log2 of the longer
// derivative vector's length in texels; the lecture has no formula for it).
std::string levels_read(const Texture& t, double u, double v, const UVDerivatives& d, double lambda) {
    const MipMap& mip = *t.mipmap;
    const Sampler& s = t.sampler;
    const int last = mip.level_count() - 1;
    const LatticeSize base = lattice_size(mip.base(), s);
    const double w = base.width, h = base.height;
    const auto level = [&](int l) {
        const Image& image = mip.level(l);
        return "level " + std::to_string(l) + " (" + std::to_string(image.width()) + "x" + std::to_string(image.height()) + ")";
    };
    // The levels read at lambda `at` (minify.h trilinear_over; trilinear reads the second level
    // also at a whole lambda, with weight 0, where EWA reads one).
    const auto two_levels = [&](double at, bool whole_reads_one) -> std::string {
        if (!(at > 0.0)) return level(0);
        if (at >= double(last)) return level(last) + ", the coarsest";
        const int l0 = int(at);
        if (whole_reads_one && at == double(l0)) return level(l0);
        return level(l0) + " and " + level(l0 + 1) + format(", blended %.4f of the way to the second", at - l0);
    };
    const auto trilinear_levels = [&](double at) { return two_levels(at, false); };
    switch (s.filter) {
        case Filter::nearest:
        case Filter::bilinear:
        case Filter::bicubic:
            return std::string("    the filter reads the base level only, without mip levels") +
                   (lambda > 0.0 ? ": minified without prefiltering, it can alias\n" : "\n");
        case Filter::nearest_mip_nearest:
        case Filter::bilinear_mip_nearest:
            return "    the level nearest to lambda (0 for lambda <= 1/2, else ceil(lambda + 1/2) - 1, at most the\n"
                   "    coarsest): " +
                   level(minify_detail::nearest_level(last, lambda)) + "\n";
        case Filter::trilinear:
            return "    trilinear: bilinear on " + trilinear_levels(lambda) + "\n";
        case Filter::anisotropic:
        case Filter::ewa:
            break;
    }
    // The footprint ellipse's principal axes, in base-level texels.
    const FootprintAxes axes = footprint_axes_of(d, w, h);
    if (!(axes.major > 0.0) || !std::isfinite(axes.major))
        return "    no footprint to measure (a point, or beyond measure): bilinear on " + level(axes.major > 0.0 ? last : 0) + "\n";
    std::string out = format("    footprint ellipse (the principal axes of the derivative vectors): major %.4g, minor %.4g texels\n",
                             axes.major, axes.minor);
    if (s.filter == Filter::anisotropic) {
        const AnisotropicProbes probes = anisotropic_probes(axes.major, axes.minor, s.max_anisotropy);
        return out + format("    %.0f trilinear probe(s) along the major axis (at most max_anisotropy %g), averaged; each at\n",
                            probes.count, s.max_anisotropy) +
               format("    lambda = log2(major / %.0f) = %.4f: bilinear on ", probes.count, probes.lambda) +
               trilinear_levels(probes.lambda) + "\n";
    }
    const EwaLevel at = ewa_level(axes.major, axes.minor, s.max_anisotropy);
    if (at.stretched) out += format("    the minor axis stretched to major / max_anisotropy = %.4g texels\n", at.minor);
    out += format("    lambda = max(0, log2(minor)) = %.4f: ", at.lambda);
    if (at.lambda >= double(last))
        return out + "at or beyond the coarsest level (the ellipse would cover the image): bilinear on " + level(last) + "\n";
    out += "the Gaussian-weighted mean over the ellipse on " + two_levels(at.lambda, true) + "\n";
    // Levels summed along one axis (ewa.h, EwaSum), as sample_ewa sums them at this lookup.
    const int l0 = int(at.lambda);
    for (int l = l0; l <= std::min(l0 + 1, last); ++l) {
        if (l > l0 && at.lambda == double(l0)) break;
        const EwaSum sum = ewa_sum_on_level(mip, s, u, v, d, l);
        if (sum == EwaSum::cells) continue;
        const bool rows = sum == EwaSum::rows || sum == EwaSum::rows_beside_border;
        const std::string across = rows ? "u" : "v", along = rows ? "v" : "u", line = rows ? "row" : "column";
        out += "    level " + std::to_string(l) + " is one texel across " + across + ", and the ellipse's middle row " +
               std::to_string(ewa_rows_from) + " cells or more: summed\n";
        if (sum == EwaSum::rows || sum == EwaSum::columns)
            out += "    " + line + " by " + line + " along " + along + ", each " + line + "'s texel weighted by its cells' weights together\n";
        else
            out += "    " + line + " by " + line + " along " + along + ", each " + line + "'s one texel beside the border (" + across +
                   " wraps to the border)\n";
    }
    return out;
}

// The texels nearest and bilinear read on the base level, as the slides index them: the
// wrapped column and row of each (row 0 is the image's bottom, v = 0), the fractions
// between them, and their linear values. "" for the other filters.
std::string base_taps(const Texture& t, double u, double v) {
    const Image& image = t.mipmap->base();
    const Sampler& s = t.sampler;
    const int w = image.width(), h = image.height();
    const auto value = [&](int i, int j) {
        const Color4 c = i < 0 || j < 0 ? s.border : image.texel(i, j);
        return channels(c);
    };
    const auto at = [](int i, int j) {
        return i < 0 || j < 0 ? std::string("(the border)") : "(" + std::to_string(i) + ", " + std::to_string(j) + ")";
    };
    if (s.filter == Filter::nearest) {
        const int i = reconstruct_detail::nearest_tap(s.registration, s.wrap_u, u, w, image.inv_width());
        const int j = reconstruct_detail::nearest_tap(s.registration, s.wrap_v, v, h, image.inv_height());
        const std::string which = s.registration == Registration::cell
                                      ? format("    the nearest texel (resU x resV = %.0f x %.0f): ", double(w), double(h)) +
                                            "u resU = " + coordinate(u * w) + ", v resV = " + coordinate(v * h) +
                                            "; column\n"
                                            "    floor(u resU), row floor(v resV), then wrapped (the slide's lu = min(floor(t_u resU),\n"
                                            "    resU - 1) on the wrapped t_u)"
                                      : format("    the nearest node (resU x resV = %.0f x %.0f): ", double(w), double(h)) +
                                            "u (resU - 1) = " + coordinate(u * (w - 1)) + ", v (resV - 1) = " + coordinate(v * (h - 1)) +
                                            ";\n"
                                            "    column round(u (resU - 1)), row round(v (resV - 1)), then wrapped";
        return which + ": texel " + at(i, j) + " (row 0 is the image's bottom),\n    linear RGBA " + value(i, j) + "\n";
    }
    if (s.filter != Filter::bilinear) return "";
    const auto a = reconstruct_detail::bilinear_taps(s.registration, s.wrap_u, u, w, image.inv_width());
    const auto b = reconstruct_detail::bilinear_taps(s.registration, s.wrap_v, v, h, image.inv_height());
    std::string out = "    bilinear reads columns " + std::to_string(a.i0) + " and " + std::to_string(a.i1) + format(" (f_u = %.5f), rows ", a.f) +
                      std::to_string(b.i0) + " and " + std::to_string(b.i1) + format(" (f_v = %.5f), after the wrap\n", b.f) +
                      "    mode (row 0 is the image's bottom; with border wrap, -1 is a texel outside the image, which\n"
                      "    reads the border colour):\n";
    out += "      t00 " + at(a.i0, b.i0) + " " + value(a.i0, b.i0) + "   t10 " + at(a.i1, b.i0) + " " + value(a.i1, b.i0) + "\n";
    out += "      t01 " + at(a.i0, b.i1) + " " + value(a.i0, b.i1) + "   t11 " + at(a.i1, b.i1) + " " + value(a.i1, b.i1) + "\n";
    out += "    along v in each column, then along u: c0 = t00 + f_v (t01 - t00), c1 = t10 + f_v (t11 - t10),\n"
           "    value = c0 + f_u (c1 - c0)\n";
    return out;
}

// Step 6: the material's colour times what it reads, times the light, as the span walk
// shades (scanline.h, shade): each attribute from its plane over w, divided by q.
// (u, v): the coordinates the pixel's lookups read (a bump map's too).
std::string shading(const PixelExplanation& e, const Scene& scene, const Material& m, const Color4& texel, double q, double u,
                    double v) {
    const Needs needs = needs_of(m, scene);
    const double x = e.x + 0.5, y = e.y + 0.5;
    const auto over_q = [&](const std::array<Plane, 3>& p) { return glm::dvec3(p[0].at(x, y), p[1].at(x, y), p[2].at(x, y)) / q; };
    const auto rgb = [](const Color& c) { return channels(c.x, c.y, c.z); };
    const bool lit = m.lighting == Lighting::lambert;
    std::string out = std::string("\n6. Shading (lighting ") + (lit ? "lambert" : "none") + "): linear colour = material colour" +
                      (m.texture >= 0 ? " x texture" : "") + (m.lightmap >= 0 ? " x light map" : "") + (m.slope ? " x slope colour" : "") + (needs & need_color ? " x vertex colour" : "") + (lit ? " x irradiance" : "") + "\n";
    Color c = m.color;
    out += "    material colour " + rgb(m.color) + "\n";
    // A bump map's slopes, read at the scene's (u, v) (the setup's shift added back, as the
    // span walk reads it), with a step of at least the pixel's footprint.
    const auto bump_at = [&](std::uint64_t& texels) {
        const double footprint = footprint_length(uv_derivatives(e.h, u, v, q));
        return bump_slope(scene.textures[std::size_t(m.bump)], m.bump_height, u + e.uv_shift.x, v + e.uv_shift.y, footprint, texels);
    };
    // (the render multiplies the texel by the light map's E before the colour by the texel)
    Color4 lit_texel = texel;
    if (m.texture >= 0) out += "    x texture       " + rgb(Color(texel)) + "\n";
    if (m.lightmap >= 0) {
        const double r = m.lightmap_repeat, lu = (u + e.uv_shift.x) / r, lv = (v + e.uv_shift.y) / r;
        const UVDerivatives d = uv_derivatives(e.h, u, v, q);
        const Texture& map = scene.textures[std::size_t(m.lightmap)];
        std::uint64_t texels = 0;
        const Color irradiance(map.procedural ? procedural_value(*map.procedural, {lu, lv, 0.0}, 0.0)
                                              : lookup(map, lu, lv, {d.dudx / r, d.dvdx / r, d.dudy / r, d.dvdy / r}, texels));
        lit_texel *= Color4(irradiance, 1.0f);
        out += "    x light map     " + rgb(irradiance) + " (" + shown_name(map.name) +
               format(" at (u, v) / %.6g = (%.6g, %.6g): the irradiance E, B = rho E)\n", r, lu, lv);
    }
    if (m.texture >= 0 || m.lightmap >= 0) c *= Color(lit_texel);
    if (m.slope && (needs & need_normal)) {
        // (the shading normal: N' where there is a bump map, as the render's shade() gets it)
        glm::dvec3 n = unit_direction(over_q(e.normal));
        if (m.bump >= 0 && (needs & need_world_position)) {
            std::uint64_t texels = 0;
            n = unit_direction(bumped_normal(n, e.tangents, bump_at(texels)));
        }
        const double alpha = std::clamp(glm::dot(n, m.slope_direction), 0.0, 1.0);
        const Color slope = float(alpha) * m.slope_flat + (1.0f - float(alpha)) * m.slope_steep;
        c *= slope;
        out += "    x slope colour  " + rgb(slope) +
               format(" (alpha = n . w = %.5f", alpha) + (m.bump >= 0 ? ", n the bumped N'" : "") +
               ": alpha flat + (1 - alpha) steep)\n";
    }
    if (needs & need_color) {
        const Color vertex(over_q(e.vertex_color));
        c *= vertex, out += "    x vertex colour " + rgb(vertex) + " (its plane over w, / q)\n";
    }
    if (lit) {
        Color irradiance = scene.ambient;
        out += "    irradiance = ambient " + rgb(scene.ambient);
        if (needs & need_normal) {
            glm::dvec3 n = unit_direction(over_q(e.normal));
            const glm::dvec3 world = over_q(e.world);
            out += format(", N = (%.5f, %.5f, %.5f) (its plane over w, / q, normalised)\n", n.x + 0.0, n.y + 0.0, n.z + 0.0);
            if (m.bump >= 0) {
                const Texture& t = scene.textures[std::size_t(m.bump)];
                std::uint64_t texels = 0;
                const BumpSlope slope = bump_at(texels);
                const SurfaceTangents& o = e.tangents;
                const glm::dvec3 area = glm::cross(o.o_u, o.o_v);
                out += "    bump map " + shown_name(t.name) +
                       format(": B(u, v) = %.6g x the texture's first channel = %.6g\n", m.bump_height,
                              bump_height_at(t, m.bump_height, u + e.uv_shift.x, v + e.uv_shift.y, texels));
                out += format("      B_u = (B(u + h, v) - B(u - h, v)) / 2h = %.6g (h = %.4g), B_v = %.6g (h = %.4g)", slope.b_u,
                              slope.step_u, slope.b_v, slope.step_v) +
                       " (h: a texel, or the pixel's footprint where wider)\n";
                out += format("      the triangle's O_u = (%.5g, %.5g, %.5g), ", o.o_u.x, o.o_u.y, o.o_u.z) +
                       format("O_v = (%.5g, %.5g, %.5g); |O_u x O_v| = %.5g", o.o_v.x, o.o_v.y, o.o_v.z, glm::length(area)) +
                       (glm::dot(area, n) < 0.0 ? " (against N: s = -1)\n" : " (along N: s = 1)\n");
                const glm::dvec3 d = slope.b_u * glm::cross(n, o.o_v) - slope.b_v * glm::cross(n, o.o_u);
                out += format("      D = B_u (N x O_v) - B_v (N x O_u) = (%.5g, %.5g, %.5g); ", d.x + 0.0, d.y + 0.0, d.z + 0.0);
                n = unit_direction(bumped_normal(n, o, slope));
                out += format("N' = N + s D / |O_u x O_v|, normalised: (%.5f, %.5f, %.5f)\n", n.x + 0.0, n.y + 0.0, n.z + 0.0);
                out += "      (N below is N')\n";
            }
            for (std::size_t k = 0; k < scene.lights.size(); ++k) {
                const Light& light = scene.lights[k];
                glm::dvec3 to_light = -light.vector;
                if ((needs & need_world_position) && light.kind == Light::Kind::point) to_light = unit_direction(light.vector - world);
                const double cosine = std::max(0.0, glm::dot(n, to_light));
                irradiance += light.color * float(cosine);
                // (+ 0.0 turns -0 into 0 for printing)
                out += format("      + light %.0f ", double(k)) + (light.kind == Light::Kind::point ? "(point" : "(directional") +
                       format(", L = (%.5f, %.5f, %.5f)) ", to_light.x + 0.0, to_light.y + 0.0, to_light.z + 0.0) + rgb(light.color) +
                       format(" x max(0, N . L) = x %.5f\n", cosine);
            }
        } else {
            out += "\n";
        }
        c *= irradiance;
        out += "    x irradiance    " + rgb(irradiance) + "\n";
    }
    if (m.reflect > 0.0 && scene.environment >= 0 && (needs & need_world_position)) {
        // (the normal as shaded: bumped where the material has a bump map)
        glm::dvec3 n = unit_direction(over_q(e.normal));
        if (m.bump >= 0) {
            std::uint64_t texels = 0;
            n = unit_direction(bumped_normal(n, e.tangents, bump_at(texels)));
        }
        const glm::dvec3 view = unit_direction(over_q(e.world) - scene.camera.eye);
        const glm::dvec3 r = reflect_direction(view, n);
        const glm::dvec2 uv = latlong_uv(r);
        std::uint64_t texels = 0;
        const Color mirrored(environment_value(scene.textures[std::size_t(scene.environment)], r, texels));
        out += "    reflection: " + rgb(c) + format(" x (1 - %.4g) + the environment map along R x %.4g\n", m.reflect, m.reflect) +
               format("      V = (%.5f, %.5f, %.5f) (eye to surface), ", view.x + 0.0, view.y + 0.0, view.z + 0.0) +
               format("R = V - 2 (N . V) N = (%.5f, %.5f, %.5f)\n", r.x + 0.0, r.y + 0.0, r.z + 0.0) +
               format("      map (u, v) = (%.6f, %.6f): ", uv.x, uv.y) + rgb(mirrored) + "\n";
        c = float(1.0 - m.reflect) * c + float(m.reflect) * mirrored;
    }
    return out + "    = " + rgb(c) + "\n";
}

// How the span walk of `mode` gets u and v along a row (explain's step 3), as lines of text.
std::string span_mode_words(SpanMode mode) {
    switch (mode) {
        case SpanMode::exact: return "   The span walk (--span exact) divides u' and v' by q at every pixel.\n";
        case SpanMode::incremental:
            return "   The span walk (--span incremental, the default) steps u', v' and q by their constant\n"
                   "   d/dx along each row, and divides at every pixel.\n";
        case SpanMode::affine8:
        case SpanMode::affine16:
        case SpanMode::affine32:
            return std::string("   The span walk (--span ") + span_mode_name(mode) + ") divides at the ends of sub-spans of " +
                   (mode == SpanMode::affine8 ? "8" : mode == SpanMode::affine16 ? "16" : "32") +
                   " pixels,\n   and interpolates u and v linearly between them.\n";
        case SpanMode::affine:
            return "   The span walk (--span affine) does not divide: it interpolates u and v linearly in screen\n"
                   "   space, without perspective (the wrong answer, for contrast).\n";
        case SpanMode::adaptive:
            return "   The span walk (--span adaptive) divides at the ends of sub-spans as long as the error bound\n"
                   "   allows, and interpolates u and v linearly between them (or steps them as incremental does).\n";
    }
    return "";
}

}  // namespace

std::string describe(const PixelExplanation& e, const Scene& scene) {
    const double x = e.x + 0.5, y = e.y + 0.5;
    std::string out = "pixel (" + std::to_string(e.x) + ", " + std::to_string(e.y) + "), sampled at its centre " +
                      format("(%.1f, %.1f)\n", x, y);
    if (!e.covered && scene.environment >= 0) {
        const Texture& map = scene.textures[std::size_t(scene.environment)];
        const glm::dvec3 ray = pixel_ray(scene.camera, e.width, e.height, e.x, e.y);
        const glm::dvec2 uv = latlong_uv(ray);
        std::uint64_t texels = 0;
        const Color4 value = environment_value(map, ray, texels);
        return out + "no triangle covers it: the environment map " + shown_name(map.name) + " shows, seen along the pixel's ray\n" +
               format("    ray d = (%.6g, %.6g, %.6g) (world space)\n", ray.x + 0.0, ray.y + 0.0, ray.z + 0.0) +
               format("    u = 1/2 + atan2(d.x, -d.z) / 2 pi = %.6f, v = 1/2 + asin(d.y / |d|) / pi = %.6f\n", uv.x, uv.y) +
               "    the map's value there, linear " + channels(value.x, value.y, value.z) +
               format(",\nin the frame file as sRGB bytes (%.0f, %.0f, %.0f)\n", linear_to_srgb8(value.x), linear_to_srgb8(value.y),
                      linear_to_srgb8(value.z));
    }
    if (!e.covered)
        return out + "no triangle covers it: the background colour shows, linear " +
               channels(scene.background.x, scene.background.y, scene.background.z) +
               format(",\nin the frame file as sRGB bytes (%.0f, %.0f, %.0f)\n", linear_to_srgb8(scene.background.x),
                      linear_to_srgb8(scene.background.y), linear_to_srgb8(scene.background.z));

    const Material& m = scene.materials[std::size_t(e.material)];
    const Mesh& mesh = scene.meshes[std::size_t(scene.objects[std::size_t(e.object)].mesh)];
    out += "front-most triangle: object " + std::to_string(e.object) + " (" + mesh.source + "), triangle " +
           std::to_string(e.triangle) + ", material " + shown_name(m.name) + (e.clipped ? "; clipped, this is one piece\n" : "\n");
    out += "  what the material needs per pixel: " + describe(needs_of(m, scene)) + "\n";

    out += "\n1. Screen vertices S (pixels, snapped to 1/256) and q = 1/w at each:\n";
    for (int i = 0; i < 3; ++i) {
        const glm::dvec2& p = e.screen[std::size_t(i)];
        out += format("    v%.0f = (%.15g, %.15g)   1/w = %.8g\n", i, p.x, p.y, e.h.q.at(p.x, p.y));  // (k/256, exactly)
    }

    const char* inverse_rows[3] = {"u'", "v'", "q "};
    out += "\n2. The inverse homography M^-1 = U diag(1/w) adj(S) / det(S): rows u', v', q; columns x, y, 1\n";
    // The UVs the setup moved by whole periods (only the coordinates that moved are named):
    // step 2's U holds them, step 3 says why.
    const std::string moved = e.uv_shift.x != 0.0 && e.uv_shift.y != 0.0 ? format("u by %+.17g and its v by %+.17g", -e.uv_shift.x, -e.uv_shift.y)
                              : e.uv_shift.x != 0.0                   ? format("u by %+.17g", -e.uv_shift.x)
                                                                      : format("v by %+.17g", -e.uv_shift.y);
    if (e.uv_shift != glm::dvec2(0.0))
        out += "   (U holds the corners' UVs after the setup moved the triangle's " + moved + ": step 3 says why)\n";
    out += matrix(e.h.inverse(), inverse_rows);
    if (const auto forward = e.h.forward()) {
        const char* forward_rows[3] = {"x'", "y'", "w "};
        out += "   and the forward homography M = (M^-1)^-1: (u, v, 1) -> (x', y', w)\n" + matrix(*forward, forward_rows);
        out += format("   (The slide's inverse, the adjugate of M (ei - fh, ch - bi, ...), is det(M) = %.8g times M^-1:\n"
                      "   a homography holds up to scale, and u = u'/q, v = v'/q come out the same.)\n",
                      glm::determinant(*forward));
    } else if (const auto zero = [](const Plane& p) { return p.dx == 0.0 && p.dy == 0.0 && p.c == 0.0; };
               !mesh.has_uv && zero(e.h.u_prime) && zero(e.h.v_prime)) {
        out += "   (every corner's u, v is 0, as in a mesh without texture coordinates (this one has faces\n"
               "   without vt): the u' and v' rows are 0 and there is no forward M; the q row still gives 1/w,\n"
               "   for perspective-correct attributes)\n";
    } else {
        out += "   (the UVs are collinear: M^-1 is singular and there is no forward M; u, v are still defined)\n";
    }

    const double u_prime = e.h.u_prime.at(x, y), v_prime = e.h.v_prime.at(x, y), q = e.h.q.at(x, y);
    const double exact_u = u_prime / q, exact_v = v_prime / q;
    out += "\n3. At the pixel centre, from the plane equations:\n";
    out += format("    u' = %.10g   v' = %.10g   q = 1/w = %.10g\n", u_prime, v_prime, q);
    out += format("    u = u'/q = %.10g   v = v'/q = %.10g\n", exact_u, exact_v);
    if (e.uv_shift != glm::dvec2(0.0)) {
        out += "    (the setup moved the triangle's " + moved + ", whole periods of the wrap mode,\n" +
               "    so that the corners' smallest value lies within one period from 0: far from 0 it would\n" +
               "    lose precision; the texture reads the same. In the scene's coordinates" +
               format(" u = %.10g, v = %.10g)\n", exact_u + e.uv_shift.x, exact_v + e.uv_shift.y);
    }
    out += span_mode_words(e.span_mode);
    const UVDerivatives exact_d = uv_derivatives(e.h, exact_u, exact_v, q);
    out += "\n4. Exact derivatives by the quotient rule, du/dx = (du'/dx - u dq/dx) / q:\n";
    out += format("    du/dx = %.6g   dv/dx = %.6g   du/dy = %.6g   dv/dy = %.6g\n", exact_d.dudx, exact_d.dvdx, exact_d.dudy,
                  exact_d.dvdy);

    // The world position the pixel read, and its screen derivatives: the span walk's where it
    // was captured (it steps P' and q along the row: its position may differ from the plane
    // equations' in the last digits, and by a cell boundary in the cell).
    const auto world_read = [&](glm::dvec3& dx, glm::dvec3& dy) {
        glm::dvec3 world;
        for (int i = 0; i < 3; ++i) world[i] = e.world[std::size_t(i)].at(x, y) / q;
        if (e.world_read_known) world = e.world_read;
        attribute_derivatives(e.world, e.h.q, world, 1.0 / q, dx, dy);
        return world;
    };
    Color4 texel(1.0f);
    if (m.texture >= 0 && (m.projector >= 0 || m.mapping.kind != Intermediate::none)) {
        const Texture& t = scene.textures[std::size_t(m.texture)];
        glm::dvec3 dx, dy;
        const glm::dvec3 world = world_read(dx, dy);
        ProjectedUV thrown;
        if (m.projector >= 0) {
            const Projector& p = scene.projectors[std::size_t(m.projector)];
            thrown = project(p, world, dx, dy);
            out += "\n5. Texture " + shown_name(t.name) + ", thrown by projector " + shown_name(p.name) +
                   (p.parallel ? " (parallel)" : " (perspective)") + ":\n";
        } else {
            const glm::dvec2 uv = intermediate_uv(m.mapping, world);
            thrown.ahead = true, thrown.u = uv.x, thrown.v = uv.y, thrown.d = intermediate_derivatives(m.mapping, world, dx, dy);
            const char* kinds[] = {"", "planar", "cylindrical", "spherical"};
            out += "\n5. Texture " + shown_name(t.name) + ", on a " + kinds[int(m.mapping.kind)] + " intermediate surface (two-stage mapping):\n";
        }
        out += format("    the world position P = P'/q: (%.10g, %.10g, %.10g)\n", world.x, world.y, world.z);
        std::uint64_t texels = 0;
        if (!thrown.ahead) {
            texel = t.sampler.border;
            out += "    behind the projector: nothing is thrown here; the texture's border colour\n";
        } else {
            out += (m.projector >= 0
                        ? format("    its clip coordinates c = M (P, 1): u = (c.x / c.w + 1) / 2 = %.10g, v = (c.y / c.w + 1) / 2 = %.10g\n",
                                 thrown.u, thrown.v)
                        : format("    in the surface's frame (x', y', z'), one coordinate dropped: u = %.10g, v = %.10g\n", thrown.u, thrown.v)) +
                   format("    their derivatives: du/dx = %.6g   dv/dx = %.6g   du/dy = %.6g   dv/dy = %.6g\n",
                          thrown.d.dudx, thrown.d.dvdx, thrown.d.dudy, thrown.d.dvdy);
            texel = t.procedural ? procedural_value(*t.procedural, {thrown.u, thrown.v, 0.0}, footprint_length(thrown.d))
                                 : lookup(t, thrown.u, thrown.v, thrown.d, texels);
        }
        out += "    the texture's value, linear RGBA: " + channels(texel) + "\n";
    } else if (m.texture >= 0 && scene.textures[std::size_t(m.texture)].procedural) {
        const Texture& t = scene.textures[std::size_t(m.texture)];
        const Procedural& p = *t.procedural;
        // The (u, v) the span mode gave the pixel, as for an image (below); a solid texture reads
        // the world position instead, which every span mode steps perspective-correctly.
        double u = exact_u, v = exact_v;
        UVDerivatives d = exact_d;
        if (!p.solid && e.uv_read_known && (e.uv_read.x != exact_u || e.uv_read.y != exact_v)) {
            u = e.uv_read.x, v = e.uv_read.y;
            d = uv_derivatives(e.h, u, v, q);
            out += std::string("\n   --span ") + span_mode_name(e.span_mode) +
                   format(" gives this pixel u = %.10g, v = %.10g instead; the pattern below reads them\n", u, v);
        }
        glm::dvec3 world(0.0);
        double footprint = 0.0;
        const bool band_limited = texr::band_limited(p.pattern);
        if (p.solid) {
            glm::dvec3 dx, dy;
            world = world_read(dx, dy);
            out += format("\n   the world position the pixel read, P = P'/q (stepped along the row): (%.10g, %.10g, %.10g)\n",
                          world.x, world.y, world.z);
            if (band_limited) footprint = std::max(glm::length(dx), glm::length(dy));
        } else if (band_limited) {
            footprint = footprint_length(d);
        }
        out += "\n5. Texture " + shown_name(t.name) + " (procedural " + pattern_name(p.pattern) + (p.solid ? ", solid" : "") +
               "; no texels, filter or wrap):\n";
        if (band_limited)
            out += (p.solid ? format("    footprint: the longer of |dP/dx| and |dP/dy| = %.4g world units\n", footprint)
                            : format("    footprint: the longer of |d(u,v)/dx| and |d(u,v)/dy| = %.4g\n", footprint));
        out += procedural_steps(p, p.solid ? world : glm::dvec3(u, v, 0.0), footprint);
        texel = procedural_value(p, p.solid ? world : glm::dvec3(u, v, 0.0), footprint);
    } else if (m.texture >= 0) {
        const Texture& t = scene.textures[std::size_t(m.texture)];
        const int w = t.mipmap->base().width(), h = t.mipmap->base().height();
        // The lookup reads the (u, v) the span mode gave this pixel, with the derivatives taken
        // there (as the span walk does); from exact and incremental they differ from u'/q,
        // v'/q by rounding alone.
        double u = exact_u, v = exact_v;
        UVDerivatives d = exact_d;
        if (e.uv_read_known) {
            u = e.uv_read.x, v = e.uv_read.y;
            d = uv_derivatives(e.h, u, v, q);
            const double off = std::max(std::fabs(u - exact_u) * w, std::fabs(v - exact_v) * h);
            if (off >= 1e-6) {
                out += std::string("\n   --span ") + span_mode_name(e.span_mode) +
                       format(" gives this pixel u = %.10g, v = %.10g instead (%.4g texels off);\n", u, v, off);
                if (e.uv_shift != glm::dvec2(0.0))  // (step 3 gave u'/q, v'/q in both)
                    out += format("   those are moved as in step 3: in the scene's coordinates u = %.10g, v = %.10g;\n", u + e.uv_shift.x,
                                  v + e.uv_shift.y);
                out += format("   the lookup below reads them, with du/dx = %.6g   dv/dx = %.6g   du/dy = %.6g   dv/dy = %.6g\n",
                              d.dudx, d.dvdx, d.dudy, d.dvdy);
            }
        }
        out += "\n5. Texture " + shown_name(t.name) + " (" + std::to_string(w) + "x" + std::to_string(h) + ", filter " +
               filter_name(t.sampler.filter) + ", wrap " + wrap_name(t.sampler.wrap_u) + "/" + wrap_name(t.sampler.wrap_v) +
               ", " + (t.sampler.registration == Registration::cell ? "cell" : "node") + " registration):\n";
        const auto wrapped = [](Wrap mode, double c) {
            switch (mode) {
                case Wrap::repeat: return wrap_repeat(c);
                case Wrap::mirror: return wrap_mirror(c);
                case Wrap::clamp: return wrap_clamp(c);
                case Wrap::border: return c;
            }
            return c;
        };
        // Outside [0, 1] under border wrap: the slide's test returns the border colour, which is
        // what texr does with node registration (but for EWA); with cell registration texels
        // beyond the edge are the border colour, and a filter blends them with those inside.
        const bool outside = (t.sampler.wrap_u == Wrap::border && outside_border(u)) || (t.sampler.wrap_v == Wrap::border && outside_border(v));
        const bool slide_test = t.sampler.registration == Registration::node && t.sampler.filter != Filter::ewa;
        out += "    the wrap mode's coordinate (the slides' form): t_u = " + coordinate(wrapped(t.sampler.wrap_u, u), 6) +
                   ", t_v = " + coordinate(wrapped(t.sampler.wrap_v, v), 6) +
               (!outside                              ? "\n"
                : slide_test                          ? " (outside [0, 1]: the border colour)\n"
                : t.sampler.filter == Filter::nearest ? " (outside [0, 1]: texels beyond the image's edge are the border\n"
                                                        "    colour, as OpenGL has it)\n"
                                                      : " (outside [0, 1]: texels beyond the image's edge are the border colour,\n"
                                                        "    which the filter blends with the texels inside it reaches, as OpenGL does)\n");
        const bool cell = t.sampler.registration == Registration::cell;
        const double lx = cell ? u * w - 0.5 : u * (w - 1);
        const double ly = cell ? v * h - 0.5 : v * (h - 1);
        out += (cell ? "    lattice coordinates (texel centres at whole numbers, before wrapping): x = u resU - 1/2 = " + coordinate(lx) +
                           ",\n    y = v resV - 1/2 = " + coordinate(ly) + "\n"
                     : "    lattice coordinates (nodes at whole numbers, before wrapping): x = u (resU - 1) = " + coordinate(lx) +
                           ",\n    y = v (resV - 1) = " + coordinate(ly) + "\n");
        if (t.sampler.filter == Filter::nearest)  // (it rounds on its own lattice: base_taps, below)
            out += cell ? "    (the lattice that bilinear reads; nearest takes floor(u resU), below)\n"
                        : "    (the lattice that bilinear reads; nearest rounds it, below)\n";
        if (e.uv_shift != glm::dvec2(0.0)) {  // (step 3's re-based u and v: whole periods from the scene's)
            const double su = u + e.uv_shift.x, sv = v + e.uv_shift.y;
            out += "    (of the re-based u and v; of the scene's, x = " + coordinate(cell ? su * w - 0.5 : su * (w - 1)) +
                   " and y = " + coordinate(cell ? sv * h - 0.5 : sv * (h - 1)) + ": whole periods apart, the same\n"
                   "    texels after wrapping)\n";
        }
        out += base_taps(t, u, v);
        // The footprint in texels of the lattice: node registration counts node spacings.
        const LatticeSize lattice = lattice_size(t.mipmap->base(), t.sampler);
        const int lw = lattice.width, lh = lattice.height;
        const double lambda = level_of_detail(d, lw, lh);
        out += format("    footprint: |d(u,v)/dx| = %.4g texels, |d(u,v)/dy| = %.4g texels",
                      std::sqrt(std::pow(lw * d.dudx, 2) + std::pow(lh * d.dvdx, 2)),
                      std::sqrt(std::pow(lw * d.dudy, 2) + std::pow(lh * d.dvdy, 2))) +
               (t.sampler.registration == Registration::node ? " (spacings between nodes)\n" : "\n");
        if (lambda > -1e8)
            out += format("    level of detail lambda = log2(max of the two) = %.4f ", lambda) +
                   (lambda > 0 ? "(minified)\n" : "(magnified or 1:1)\n");
        else  // level_of_detail's answer for a footprint of zero (or NaN) length
            out += "    level of detail: no footprint (u and v do not change here): magnified\n";
        out += levels_read(t, u, v, d, lambda);
        std::uint64_t texels = 0;
        texel = lookup(t, u, v, d, texels);
        out += "    the filter's value, linear RGBA: " + channels(texel) +
               format(" from %.0f texel read", double(texels)) + (texels == 1 ? "\n" : "s\n");
        if (m.cutout > 0.0f)
            out += format("    cutout: alpha %.5f is at least the threshold %.4g: drawn (below it, a hole)\n", texel.w, m.cutout);
    }
    double read_u = exact_u, read_v = exact_v;  // (what the span mode gave the lookups)
    if (e.uv_read_known) read_u = e.uv_read.x, read_v = e.uv_read.y;
    out += shading(e, scene, m, texel, q, read_u, read_v);
    out += format("\n7. Written: depth %.8f, linear colour ", e.depth) + channels(e.color.x, e.color.y, e.color.z) +
           format(",\n   in the frame file as sRGB bytes (%.0f, %.0f, %.0f)\n", linear_to_srgb8(e.color.x), linear_to_srgb8(e.color.y),
                  linear_to_srgb8(e.color.z));
    return out;
}

}  // namespace texr
