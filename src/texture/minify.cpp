// Mipmapped minification filters (see include/texr/texture/minify.h).
#include "texr/texture/minify.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "texr/texture/reconstruct.h"

namespace texr {

namespace {

// 2^k for k in [-1022, 1023], built from its bits.
double power_of_two(int k) {
    const std::uint64_t bits = std::uint64_t(k + 1023) << 52;
    double value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
}

}  // namespace

FootprintAxes footprint_axes(double d1u, double d1v, double d2u, double d2v) {
    FootprintAxes axes{0.0, 0.0, 1.0, 0.0};
    if (std::isnan(d1u) || std::isnan(d1v) || std::isnan(d2u) || std::isnan(d2v)) {
        axes.major = std::numeric_limits<double>::quiet_NaN();
        return axes;
    }
    const double largest = std::max({std::fabs(d1u), std::fabs(d1v), std::fabs(d2u), std::fabs(d2v)});
    if (!(largest > 0.0) || std::isinf(largest)) {  // a point, or a footprint beyond measure
        axes.major = largest;
        return axes;
    }
    // Scale by a power of two (exact) so the largest component is about 1: the squares below
    // neither overflow (from about 1e77 texels on) nor lose precision to underflow. The
    // exponent is read from the bits (std::ilogb and std::ldexp are library calls, 15% of an
    // anisotropic frame); a subnormal reads as 2^-1022, which scales it to at least 2^-52.
    std::uint64_t bits;
    std::memcpy(&bits, &largest, sizeof bits);
    const int exponent = std::clamp(int((bits >> 52) & 0x7ff) - 1023, -1022, 1022);
    const double down = power_of_two(-exponent), up = power_of_two(exponent);
    d1u *= down, d1v *= down, d2u *= down, d2v *= down;
    const double p = d1u * d1u + d2u * d2u, q = d1v * d1v + d2v * d2v, r = d1u * d1v + d2u * d2v;
    const double half_difference = 0.5 * (p - q);
    const double major2 = 0.5 * (p + q) + std::sqrt(half_difference * half_difference + r * r);
    const double major = std::sqrt(major2);
    axes.major = major * up;
    axes.minor = std::min(major, std::fabs(d1u * d2v - d2u * d1v) / major) * up;
    double eu = major2 - q, ev = r;
    if (r * r + (major2 - p) * (major2 - p) > eu * eu + ev * ev) eu = r, ev = major2 - p;
    const double length = std::sqrt(eu * eu + ev * ev);
    if (length > 0.0) axes.major_u = eu / length, axes.major_v = ev / length;  // (a circle: any direction)
    return axes;
}

Color4 sample_anisotropic(const MipMap& mip, const Sampler& s, double u, double v, const UVDerivatives& d, int& probes,
                          std::uint64_t* texels) {
    // (The short path below is cell registration's only, where these are the image's size.)
    const LatticeSize lattice = lattice_size(mip.base(), s);
    const double w = lattice.width, h = lattice.height;
    const FootprintAxes axes = footprint_axes_of(d, w, h);
    const double major = axes.major, minor = axes.minor;
    if (!(major > 0.0) || !std::isfinite(major)) {  // a point, or a footprint beyond measure
        probes = 1;
        if (texels) *texels += 4;
        return sample_bilinear(major > 0.0 ? mip.level(mip.level_count() - 1) : mip.base(), s, u, v);
    }
    const AnisotropicProbes probe = anisotropic_probes(major, minor, s.max_anisotropy);
    const int n = probe.count;
    const double lambda = probe.lambda;
    // The major axis in texture coordinates.
    const double axis_u = major * axes.major_u / w, axis_v = major * axes.major_v / h;
    Color4 sum(0.0f);
    // The probes lie within half the major axis of (u, v): when the default sampler's short
    // path holds for that whole segment, every probe reads the level views directly
    // (the same texels and arithmetic as sample_trilinear, without its per-probe checks).
    // The levels above the base are needed (and built) only for lambda > 0.
    const bool short_path = takes_short_path(mip.base(), s) &&
                            minify_detail::within_short_path_limit(std::fabs(u) + 0.5 * std::fabs(axis_u),
                                                                   std::fabs(v) + 0.5 * std::fabs(axis_v), w, h);
    const LdrLevel base = short_path ? mip.base().ldr_level(true) : LdrLevel{};
    const LdrLevel* levels = short_path ? (lambda > 0.0 ? mip.ldr_levels(true) : &base) : nullptr;
    for (int k = 0; k < n; ++k) {
        const double offset = (k + 0.5) / n - 0.5;  // evenly spaced across the footprint
        const double pu = u + offset * axis_u, pv = v + offset * axis_v;
        sum += levels ? minify_detail::trilinear_over(mip.level_count() - 1, lambda,
                                                      [&](int l) { return bilinear_in(levels[l], pu, pv); })
                      : sample_trilinear(mip, s, pu, pv, lambda);
    }
    probes = n;
    if (texels) *texels += std::uint64_t(n) * std::uint64_t(trilinear_texels(mip, lambda));
    if (!all_finite(sum)) {  // HDR probes near the float maximum overflowed the float sum:
        glm::dvec4 total(0.0);  // the same probes (an HDR image takes no short path), in double
        for (int k = 0; k < n; ++k) {
            const double offset = (k + 0.5) / n - 0.5;
            total += glm::dvec4(sample_trilinear(mip, s, u + offset * axis_u, v + offset * axis_v, lambda));
        }
        return Color4(total / double(n));
    }
    return sum * (1.0f / float(n));
}

}  // namespace texr
