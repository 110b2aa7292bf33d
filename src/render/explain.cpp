// texr explain: one pixel's story as text (see include/texr/render/explain.h).
#include "texr/render/explain.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "texr/texture/minify.h"
#include "texr/texture/wrap.h"

namespace texr {

namespace {

std::string format(const char* pattern, double a = 0, double b = 0, double c = 0, double d = 0) {
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, pattern, a, b, c, d);
    return buffer;
}

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
// (minify.h, ewa.h), with lambda the level of detail of the lecture's formula.
std::string levels_read(const Texture& t, const UVDerivatives& d, double lambda) {
    const MipMap& mip = *t.mipmap;
    const Sampler& s = t.sampler;
    const int last = mip.level_count() - 1;
    const double w = mip.base().width(), h = mip.base().height();
    const auto level = [&](int l) {
        const Image& image = mip.level(l);
        return "level " + std::to_string(l) + " (" + std::to_string(image.width()) + "x" + std::to_string(image.height()) + ")";
    };
    const auto trilinear_levels = [&](double at) -> std::string {  // minify.h trilinear_over
        if (!(at > 0.0)) return level(0);
        if (at >= double(last)) return level(last) + ", the coarsest";
        const int l0 = int(at);
        if (at == double(l0)) return level(l0);
        return level(l0) + " and " + level(l0 + 1) + format(", blended %.4f of the way to the second", at - l0);
    };
    switch (s.filter) {
        case Filter::nearest:
        case Filter::bilinear:
        case Filter::bicubic:
            return std::string("    the filter reads the base level only, without mip levels") +
                   (lambda > 0.0 ? ": minified without prefiltering, it can alias\n" : "\n");
        case Filter::nearest_mip_nearest:
        case Filter::bilinear_mip_nearest:
            return "    the level nearest to lambda (0 for lambda <= 1/2, else ceil(lambda + 1/2) - 1): " +
                   level(minify_detail::nearest_level(last, lambda)) + "\n";
        case Filter::trilinear:
            return "    trilinear: bilinear on " + trilinear_levels(lambda) + "\n";
        case Filter::anisotropic:
        case Filter::ewa:
            break;
    }
    // The footprint ellipse's principal axes, in base-level texels (footprint_axes); EWA
    // counts a derivative vector with a NaN as no extent.
    double d1u = d.dudx * w, d1v = d.dvdx * h, d2u = d.dudy * w, d2v = d.dvdy * h;
    if (s.filter == Filter::ewa) {
        if (std::isnan(d1u) || std::isnan(d1v)) d1u = d1v = 0.0;
        if (std::isnan(d2u) || std::isnan(d2v)) d2u = d2v = 0.0;
    }
    const FootprintAxes axes = footprint_axes(d1u, d1v, d2u, d2v);
    if (!(axes.major > 0.0) || !std::isfinite(axes.major))
        return "    no footprint to measure (a point, or beyond measure): bilinear on " + level(axes.major > 0.0 ? last : 0) + "\n";
    std::string out = format("    footprint ellipse (the principal axes of the derivative vectors): major %.4g, minor %.4g texels\n",
                             axes.major, axes.minor);
    if (s.filter == Filter::anisotropic) {  // minify.cpp sample_anisotropic
        const double ratio = axes.minor > 0.0 ? axes.major / axes.minor : double(s.max_anisotropy);
        const int n = std::max(1, int(std::ceil(std::min(ratio, double(s.max_anisotropy)) - 1e-9)));
        const double at = std::log2(axes.major / n);
        return out + format("    %.0f trilinear probe(s) along the major axis (at most max_anisotropy %g), averaged; each at\n", n,
                            s.max_anisotropy) +
               format("    lambda = log2(major / %.0f) = %.4f: bilinear on ", n, at) + trilinear_levels(at) + "\n";
    }
    // ewa.cpp sample_ewa: the minor axis is stretched to major / max_anisotropy at most that
    // eccentricity; the level is where the minor axis spans about one texel.
    double minor = axes.minor;
    if (!(minor * s.max_anisotropy >= axes.major)) {
        minor = axes.major / s.max_anisotropy;
        out += format("    the minor axis stretched to major / max_anisotropy = %.4g texels\n", minor);
    }
    const double at = std::max(0.0, std::log2(std::max(minor, 1e-300)));
    out += format("    lambda = log2(minor) = %.4f: ", at);
    if (at >= double(last)) return out + "wider than the image, bilinear on " + level(last) + ", the coarsest\n";
    return out + "the Gaussian-weighted mean over the ellipse on " + trilinear_levels(at) + "\n";
    return out;
}

}  // namespace

std::string describe(const PixelExplanation& e, const Scene& scene) {
    const double x = e.x + 0.5, y = e.y + 0.5;
    std::string out = "pixel (" + std::to_string(e.x) + ", " + std::to_string(e.y) + "), sampled at its centre " +
                      format("(%.1f, %.1f)\n", x, y);
    if (!e.covered) return out + "no triangle covers it: the background colour shows\n";

    const Material& m = scene.materials[std::size_t(e.material)];
    const Mesh& mesh = scene.meshes[std::size_t(scene.objects[std::size_t(e.object)].mesh)];
    out += "front-most triangle: object " + std::to_string(e.object) + " (" + mesh.source + "), triangle " +
           std::to_string(e.triangle) + ", material '" + m.name + "'" + (e.clipped ? "; clipped, this is one piece\n" : "\n");
    out += "  what the material needs per pixel: " + describe(needs_of(m, scene)) + "\n";

    out += "\n1. Screen vertices S (pixels, snapped to 1/256) and q = 1/w at each:\n";
    for (int i = 0; i < 3; ++i) {
        const glm::dvec2& p = e.screen[std::size_t(i)];
        out += format("    v%.0f = (%.4f, %.4f)   1/w = %.8g\n", i, p.x, p.y, e.h.q.at(p.x, p.y));
    }

    const char* inverse_rows[3] = {"u'", "v'", "q "};
    out += "\n2. The inverse homography M^-1 = U diag(1/w) adj(S) / det(S): rows u', v', q; columns x, y, 1\n";
    out += matrix(e.h.inverse(), inverse_rows);
    if (const auto forward = e.h.forward()) {
        const char* forward_rows[3] = {"x'", "y'", "w "};
        out += "   and the forward homography M = (M^-1)^-1: (u, v, 1) -> (x', y', w)\n" + matrix(*forward, forward_rows);
    } else {
        out += "   (the UVs are collinear: M^-1 is singular and there is no forward M; u, v are still defined)\n";
    }

    const double u_prime = e.h.u_prime.at(x, y), v_prime = e.h.v_prime.at(x, y), q = e.h.q.at(x, y);
    const double u = u_prime / q, v = v_prime / q;
    out += "\n3. At the pixel centre (the span walk steps these by the constant d/dx of each row):\n";
    out += format("    u' = %.10g   v' = %.10g   q = 1/w = %.10g\n", u_prime, v_prime, q);
    out += format("    u = u'/q = %.10g   v = v'/q = %.10g\n", u, v);
    const UVDerivatives d = uv_derivatives(e.h, u, v, q);
    out += "\n4. Exact derivatives by the quotient rule, du/dx = (du'/dx - u dq/dx) / q:\n";
    out += format("    du/dx = %.6g   dv/dx = %.6g   du/dy = %.6g   dv/dy = %.6g\n", d.dudx, d.dvdx, d.dudy, d.dvdy);

    if (m.texture >= 0) {
        const Texture& t = scene.textures[std::size_t(m.texture)];
        const int w = t.mipmap->base().width(), h = t.mipmap->base().height();
        out += "\n5. Texture '" + t.name + "' (" + std::to_string(w) + "x" + std::to_string(h) + ", filter " +
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
        out += format("    the wrap mode's coordinate (the slides' form): t_u = %.6f, t_v = %.6f", wrapped(t.sampler.wrap_u, u),
                      wrapped(t.sampler.wrap_v, v)) +
               ((t.sampler.wrap_u == Wrap::border && outside_border(u)) || (t.sampler.wrap_v == Wrap::border && outside_border(v))
                    ? " (outside [0, 1]: the border colour)\n"
                    : "\n");
        const double lx = t.sampler.registration == Registration::cell ? u * w - 0.5 : u * (w - 1);
        const double ly = t.sampler.registration == Registration::cell ? v * h - 0.5 : v * (h - 1);
        out += format("    lattice coordinates (texels, before wrapping): x = %.4f, y = %.4f\n", lx, ly);
        const double lambda = level_of_detail(d, w, h);
        out += format("    footprint: |d(u,v)/dx| = %.4g texels, |d(u,v)/dy| = %.4g texels\n",
                      std::sqrt(std::pow(w * d.dudx, 2) + std::pow(h * d.dvdx, 2)),
                      std::sqrt(std::pow(w * d.dudy, 2) + std::pow(h * d.dvdy, 2)));
        out += format("    level of detail lambda = log2(max of the two) = %.4f ", lambda) +
               (lambda > 0 ? "(minified)\n" : "(magnified or 1:1)\n");
        out += levels_read(t, d, lambda);
    }
    out += format("\n6. Written: depth %.8f, linear colour (%.5f, %.5f, %.5f)\n", e.depth, e.color.x, e.color.y, e.color.z);
    return out;
}

}  // namespace texr
