// Minification (lecture, "Texture Mapping": find the pixel's pre-image in the texture and
// integrate over it). The pre-image of a pixel is approximated by the parallelogram spanned
// by the exact screen derivatives (du/dx, dv/dx) and (du/dy, dv/dy) from the homography.
// Level of detail, with lengths measured in texels of the base level (W x H):
//   rho_x = sqrt((W du/dx)^2 + (H dv/dx)^2),  rho_y = sqrt((W du/dy)^2 + (H dv/dy)^2)
//   lambda = log2(max(rho_x, rho_y))
// the true lengths of the two derivative vectors, not a max of absolute components, so the
// level does not change when the footprint rotates.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "texr/raster/homography.h"
#include "texr/texture/reconstruct.h"
#include "texr/texture/mipmap.h"
#include "texr/texture/sampler.h"

namespace texr {

double level_of_detail(const UVDerivatives& d, int width, int height);  // defined below

// GL_NEAREST_MIPMAP_NEAREST / GL_LINEAR_MIPMAP_NEAREST: the level nearest to lambda, read
// with nearest or bilinear reconstruction. lambda <= 0 is magnification: the base level.
Color4 sample_mip_nearest(const MipMap& mip, const Sampler& s, double u, double v, double lambda, bool bilinear);  // defined below

// GL_LINEAR_MIPMAP_LINEAR: bilinear in levels floor(lambda) and floor(lambda) + 1, blended by
// the fraction of lambda.
Color4 sample_trilinear(const MipMap& mip, const Sampler& s, double u, double v, double lambda);  // defined below

// Anisotropic: N = min(ceil(major / minor), max_anisotropy) trilinear probes spaced evenly
// along the footprint's major axis, at lambda = log2(major / N), averaged. Returns the
// number of probes through `probes`.
Color4 sample_anisotropic(const MipMap& mip, const Sampler& s, double u, double v, const UVDerivatives& d, int& probes);

// --- Definitions of the per-pixel parts: inline, so the span loop compiles them in place ---
namespace minify_detail {
// Squared length of a derivative vector in texels. (Not std::hypot: that guards against
// overflow at a cost of tens of nanoseconds per pixel; an overflow to +inf here only
// selects the coarsest level, which is right for such a footprint.)
[[gnu::always_inline]] inline double squared_texels(double du, double dv, double width, double height) {
    return (width * du) * (width * du) + (height * dv) * (height * dv);
}
}  // namespace minify_detail

namespace minify_detail {
// log2(r) for r > 0, within 2e-9 of the exact value and exact for powers of two; about a
// third of the time of std::log2, which the span loop would call once per pixel. With
// r = m 2^e, m in [sqrt(1/2), sqrt(2)) (e and m read from the bits),
//   log2 r = e + ln(m) / ln 2,   ln m = 2 (s + s^3/3 + s^5/5 + s^7/7 + s^9/9 + ...),
//   s = (m - 1) / (m + 1),  |s| <= 0.1716,
// and the series cut after s^9 leaves less than 2 s^11 / 11 / (1 - s^2) < 8e-10 in ln m.
// Zero, subnormal, infinite and NaN inputs go to std::log2.
[[gnu::always_inline]] inline double log2_positive(double r) {
    std::uint64_t bits;
    std::memcpy(&bits, &r, sizeof bits);
    const std::uint64_t biased = (bits >> 52) & 0x7ff;
    if (biased == 0 || biased == 0x7ff) return std::log2(r);
    // Mantissa bits as a number in [1, 2); above sqrt(2), halve it into [sqrt(1/2), 1).
    std::uint64_t m_bits = (bits & 0x000fffffffffffffULL) | 0x3ff0000000000000ULL;
    int e = int(biased) - 1023;
    if (m_bits > 0x3ff6a09e667f3bccULL) m_bits -= 0x0010000000000000ULL, ++e;  // sqrt(2) = 0x3ff6a09e667f3bcd
    double m;
    std::memcpy(&m, &m_bits, sizeof m);
    const double s = (m - 1.0) / (m + 1.0), s2 = s * s;
    const double series = s * (2.0 + s2 * (2.0 / 3.0 + s2 * (2.0 / 5.0 + s2 * (2.0 / 7.0 + s2 * (2.0 / 9.0)))));
    return double(e) + series * 1.4426950408889634;  // 1 / ln 2
}
}  // namespace minify_detail

[[gnu::always_inline]] inline double level_of_detail(const UVDerivatives& d, int width, int height) {
    using minify_detail::squared_texels;
    // lambda = log2(max(rho_x, rho_y)) = log2(max(rho_x^2, rho_y^2)) / 2: one log, no roots.
    const double rho2 = std::max(squared_texels(d.dudx, d.dvdx, width, height), squared_texels(d.dudy, d.dvdy, width, height));
    return rho2 > 0.0 ? 0.5 * minify_detail::log2_positive(rho2) : -1e9;  // a point footprint: full magnification
}

namespace minify_detail {

// OpenGL's nearest level: lambda <= 1/2 -> 0, else ceil(lambda + 1/2) - 1. An infinite
// footprint reads the coarsest level (`last`); NaN reads the base.
[[gnu::always_inline]] inline int nearest_level(int last, double lambda) {
    int level = 0;
    if (lambda >= double(last)) level = last;
    else if (lambda > 0.5) {
        level = int(lambda + 0.5);                     // = ceil(lambda + 1/2) - 1 ...
        if (double(level) == lambda + 0.5) --level;  // ... also when lambda + 1/2 is whole
        level = std::min(last, level);
    }
    return level;
}

// Trilinear blending (`last` the index of the 1x1 level), with bilinear_at(l) the bilinear
// lookup on level l: the general path reads the levels through MipMap, the short paths
// through their LdrLevel views (reconstruct.h bilinear_in), with the same arithmetic.
template <typename BilinearAt>
[[gnu::always_inline]] inline Color4 trilinear_over(int last, double lambda, const BilinearAt& bilinear_at) {
    if (!(lambda > 0.0)) return bilinear_at(0);  // also NaN
    if (lambda >= double(last)) return bilinear_at(last);
    const int l0 = int(lambda);
    const float t = float(lambda - l0);
    const Color4 a = bilinear_at(l0);
    const Color4 b = bilinear_at(l0 + 1);
    return a + t * (b - a);
}

[[gnu::always_inline]] inline Color4 mip_nearest(const MipMap& mip, const Sampler& s, double u, double v, double lambda, bool bilinear) {
    const Image& image = mip.level(nearest_level(mip.level_count() - 1, lambda));
    return bilinear ? sample_bilinear(image, s, u, v) : sample_nearest(image, s, u, v);
}

// Whether the short paths may read (u, v) on any level of a base level of W x H texels
// without a per-lookup check (reconstruct.h, short_path_limit): |u W| + 1 and |v H| + 1 are
// below the limit (also false for NaN). Coarser levels have smaller coordinates.
[[gnu::always_inline]] inline bool within_short_path_limit(double u, double v, double width, double height) {
    return std::fabs(u * width) + 1.0 < short_path_limit && std::fabs(v * height) + 1.0 < short_path_limit;
}

[[gnu::always_inline]] inline Color4 trilinear(const MipMap& mip, const Sampler& s, double u, double v, double lambda) {
    return trilinear_over(mip.level_count() - 1, lambda, [&](int l) { return sample_bilinear(mip.level(l), s, u, v); });
}
}  // namespace minify_detail

[[gnu::always_inline]] inline Color4 sample_mip_nearest(const MipMap& mip, const Sampler& s, double u, double v, double lambda, bool bilinear) {
    return minify_detail::mip_nearest(mip, s, u, v, lambda, bilinear);
}

// The texels trilinear reads at lambda when the coarsest level is `last`: one level's four
// at either end of the pyramid, two levels' eight between.
inline int trilinear_texels(int last, double lambda) { return (lambda > 0.0 && lambda < last) ? 8 : 4; }
inline int trilinear_texels(const MipMap& mip, double lambda) { return trilinear_texels(mip.level_count() - 1, lambda); }

[[gnu::always_inline]] inline Color4 sample_trilinear(const MipMap& mip, const Sampler& s, double u, double v, double lambda) {
    return minify_detail::trilinear(mip, s, u, v, lambda);
}

}  // namespace texr
