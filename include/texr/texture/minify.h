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
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "texr/raster/homography.h"
#include "texr/texture/reconstruct.h"
#include "texr/texture/mipmap.h"
#include "texr/texture/sampler.h"

namespace texr {

double level_of_detail(const UVDerivatives& d, int width, int height);  // defined below

// The size of `image` in texels of the sampler's lattice (sampler.h, lattice_texels: n cells,
// or n - 1 node spacings): the units footprints and levels of detail are measured in.
struct LatticeSize {
    int width, height;
};
inline LatticeSize lattice_size(const Image& image, const Sampler& s) {
    return {lattice_texels(s.registration, image.width()), lattice_texels(s.registration, image.height())};
}

// GL_NEAREST_MIPMAP_NEAREST / GL_LINEAR_MIPMAP_NEAREST: the level nearest to lambda, read
// with nearest or bilinear reconstruction. lambda <= 0 is magnification: the base level.
Color4 sample_mip_nearest(const MipMap& mip, const Sampler& s, double u, double v, double lambda, bool bilinear);  // defined below

// GL_LINEAR_MIPMAP_LINEAR: bilinear in levels floor(lambda) and floor(lambda) + 1, blended by
// the fraction of lambda.
Color4 sample_trilinear(const MipMap& mip, const Sampler& s, double u, double v, double lambda);  // defined below

// The pixel's footprint ellipse {d1 cos t + d2 sin t}, d1 = (du/dx, dv/dx) and
// d2 = (du/dy, dv/dy) in texels: its principal semi-axes. d1 and d2 are conjugate diameters
// of the ellipse, its axes only when perpendicular (a footprint seen obliquely and rolled
// has them nearly parallel). The axes are the singular values of J = [d1 d2]: with
// J J^T = [[p, r], [r, q]],
//   major^2 = (p + q) / 2 + sqrt(((p - q) / 2)^2 + r^2),  minor = |det J| / major
// (their product is |det J|, so the minor axis needs no difference of nearly equal
// numbers), the major axis along an eigenvector of J J^T for major^2: (major^2 - q, r) or
// (r, major^2 - p), the longer of the two. (Worked out on the vectors scaled by a power of
// two, so the squares neither overflow nor underflow.)
struct FootprintAxes {
    double major, minor;      // major >= minor >= 0; major is NaN for a NaN input, +inf for an infinite one
    double major_u, major_v;  // unit direction of the major axis (the minor one is perpendicular)
};
FootprintAxes footprint_axes(double d1u, double d1v, double d2u, double d2v);
// The axes of a pixel's footprint in base-level texels of width x height. A derivative
// vector with a NaN counts as degenerate (no extent): the other one is the footprint, as in
// level_of_detail. (sample_anisotropic, sample_ewa and texr explain.)
inline FootprintAxes footprint_axes_of(const UVDerivatives& d, double width, double height) {
    double d1u = d.dudx * width, d1v = d.dvdx * height, d2u = d.dudy * width, d2v = d.dvdy * height;
    if (std::isnan(d1u) || std::isnan(d1v)) d1u = d1v = 0.0;
    if (std::isnan(d2u) || std::isnan(d2v)) d2u = d2v = 0.0;
    return footprint_axes(d1u, d1v, d2u, d2v);
}

// Anisotropic filtering's probes for a footprint of principal axes major >= minor > 0 (in
// base-level texels): N = min(ceil(major / minor), max_anisotropy), each a trilinear lookup
// at lambda = log2(major / N). (sample_anisotropic and texr explain.)
struct AnisotropicProbes {
    int count;
    double lambda;
};
inline AnisotropicProbes anisotropic_probes(double major, double minor, float max_anisotropy) {
    const double ratio = minor > 0.0 ? major / minor : double(max_anisotropy);
    const int n = std::max(1, int(std::ceil(std::min(ratio, double(max_anisotropy)) - 1e-9)));
    return {n, std::log2(major / n)};
}

// Anisotropic: N = min(ceil(major / minor), max_anisotropy) trilinear probes spaced evenly
// along the footprint's major axis (footprint_axes, in base-level texels), at
// lambda = log2(major / N), averaged. Returns the number of probes through `probes`, and
// adds the texels they read to `texels` when given (4 per probe on one level, 8 on two).
Color4 sample_anisotropic(const MipMap& mip, const Sampler& s, double u, double v, const UVDerivatives& d, int& probes,
                          std::uint64_t* texels = nullptr);

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
// log2(r) for r > 0 without a divide, table-driven: with r = m 2^e, m in [1, 2) (e and m read
// from the bits), and c_i = 1 + i/128 for the top 7 bits i of m's fraction,
//   log2 r = e + log2 c_i + ln(1 + x) / ln 2,   x = m / c_i - 1 in [0, 1/128) (less a
//   rounding: about -2^-53 at worst),
//   ln(1 + x) = x - x^2/2 + x^3/3 - x^4/4 + x^5/5 - ...,
// the series cut after x^5 leaves less than x^6 / 6 < 4e-14. The table holds a double near
// 1/c_i and -log2 of that double, so m times it is m / c_i to within a rounding; for i = 0
// it holds 1 and 0 exactly, so the result is exact at powers of two and level boundaries and
// the ties in nearest_level fall where std::log2 puts them. Zero, subnormal, infinite and NaN
// inputs go to std::log2. (The level of detail takes one log per pixel; std::log2 was 14% of
// a trilinear frame, and the previous series' divide, (m - 1)/(m + 1), 12%.)
// The table is computed by the compiler (a constant: no order of initialisation to get
// wrong, and no dependence on the C library's log2): ln y = 2 atanh s, s = (y - 1)/(y + 1),
// summed as 2 (s + s^3/3 + s^5/5 + ...) in long double; s <= 1/3, so 30 terms leave less
// than 1e-29.
struct Log2Table {
    double inverse[128];  // ~ 1 / c_i
    double log2_c[128];   // -log2(inverse[i])
};
constexpr Log2Table make_log2_table() {
    Log2Table t{};
    for (int i = 0; i < 128; ++i) {
        t.inverse[i] = 1.0 / (1.0 + i / 128.0);  // 1 and 0 exactly for i = 0
        const long double y = 1.0L / t.inverse[i], s = (y - 1.0L) / (y + 1.0L);
        long double power = s, sum = 0.0L;
        for (int k = 0; k < 30; ++k, power *= s * s) sum += power / (2 * k + 1);
        t.log2_c[i] = double(2.0L * sum / 0.693147180559945309417232121458176568L);  // / ln 2
    }
    return t;
}
inline constexpr Log2Table log2_table = make_log2_table();

[[gnu::always_inline]] inline double log2_positive(double r) {
    std::uint64_t bits;
    std::memcpy(&bits, &r, sizeof bits);
    const std::uint64_t biased = (bits >> 52) & 0x7ff;
    if (biased == 0 || biased == 0x7ff) return std::log2(r);
    const std::uint64_t fraction = bits & 0x000fffffffffffffULL;
    const std::uint64_t m_bits = fraction | 0x3ff0000000000000ULL;  // m in [1, 2)
    double m;
    std::memcpy(&m, &m_bits, sizeof m);
    const int i = int(fraction >> 45);
    const double x = m * log2_table.inverse[i] - 1.0;
    const double ln = x * (1.0 + x * (-1.0 / 2.0 + x * (1.0 / 3.0 + x * (-1.0 / 4.0 + x * (1.0 / 5.0)))));
    return (double(int(biased) - 1023) + log2_table.log2_c[i]) + ln * 1.4426950408889634;  // 1 / ln 2
}
}  // namespace minify_detail

namespace minify_detail {
// lambda from rho^2 = max(rho_x^2, rho_y^2).
[[gnu::always_inline]] inline double level_of_detail_of_squared(double rho2) {
    return rho2 > 0.0 ? 0.5 * log2_positive(rho2) : -1e9;  // a point footprint: full magnification
}
}  // namespace minify_detail

[[gnu::always_inline]] inline double level_of_detail(const UVDerivatives& d, int width, int height) {
    using minify_detail::squared_texels;
    // lambda = log2(max(rho_x, rho_y)) = log2(max(rho_x^2, rho_y^2)) / 2: one log, no roots.
    // A side with a NaN counts as none (max(0, NaN) is 0; max(r, NaN) is r), so the other
    // side is the footprint, whichever of the two it is.
    const double rho2 = std::max(std::max(0.0, squared_texels(d.dudx, d.dvdx, width, height)),
                                 squared_texels(d.dudy, d.dvdy, width, height));
    return minify_detail::level_of_detail_of_squared(rho2);
}

#if defined(__SSE2__)
// level_of_detail of two footprints at once, one in each lane of SSE2's doubles: the same
// operations on each lane, in the same order, so the same bits (the span walk's batches
// take their pixels two at a time: its dependent chain of roughly 30 operations, half of it
// the series, then overlaps twice as many pixels; products and sums must not be fused,
// -ffp-contract=off in CMakeLists.txt, or the lanes and level_of_detail could differ in
// their last bits). A pair with a lane that log2_positive hands to std::log2 (zero,
// subnormal or infinite rho^2) is done lane by lane, as level_of_detail does it.
[[gnu::always_inline]] inline __m128d level_of_detail_lanes(__m128d dudx, __m128d dvdx, __m128d dudy, __m128d dvdy, int width,
                                                           int height) {
    const __m128d w = _mm_set1_pd(double(width)), h = _mm_set1_pd(double(height));
    const auto squared = [&](__m128d du, __m128d dv) {  // squared_texels
        const __m128d a = _mm_mul_pd(w, du), b = _mm_mul_pd(h, dv);
        return _mm_add_pd(_mm_mul_pd(a, a), _mm_mul_pd(b, b));
    };
    // std::max(0, x) is x only when 0 < x (NaN gives 0), as _mm_max_pd(x, 0); std::max(a, y)
    // is y only when a < y (NaN gives a), as _mm_max_pd(y, a).
    const __m128d rho2 = _mm_max_pd(squared(dudy, dvdy), _mm_max_pd(squared(dudx, dvdx), _mm_setzero_pd()));
    const __m128i bits = _mm_castpd_si128(rho2);
    const __m128i biased = _mm_and_si128(_mm_srli_epi64(bits, 52), _mm_set1_epi64x(0x7ff));
    // Lanes whose exponent field is 0 or 0x7ff (rho2 is never NaN, and never negative).
    const __m128i special = _mm_or_si128(_mm_cmpeq_epi32(biased, _mm_setzero_si128()),
                                         _mm_cmpeq_epi32(biased, _mm_set1_epi64x(0x7ff)));
    if (_mm_movemask_epi8(_mm_shuffle_epi32(special, _MM_SHUFFLE(2, 2, 0, 0))) != 0) {
        alignas(16) double r[2];
        _mm_store_pd(r, rho2);
        return _mm_set_pd(minify_detail::level_of_detail_of_squared(r[1]), minify_detail::level_of_detail_of_squared(r[0]));
    }
    const __m128i fraction = _mm_and_si128(bits, _mm_set1_epi64x(0x000fffffffffffffLL));
    const __m128d m = _mm_castsi128_pd(_mm_or_si128(fraction, _mm_set1_epi64x(0x3ff0000000000000LL)));
    const __m128i index = _mm_srli_epi64(fraction, 45);
    const int i0 = _mm_cvtsi128_si32(index), i1 = _mm_cvtsi128_si32(_mm_unpackhi_epi64(index, index));
    using minify_detail::log2_table;
    const __m128d x =
        _mm_sub_pd(_mm_mul_pd(m, _mm_set_pd(log2_table.inverse[i1], log2_table.inverse[i0])), _mm_set1_pd(1.0));
    __m128d ln = _mm_add_pd(_mm_set1_pd(-1.0 / 4.0), _mm_mul_pd(x, _mm_set1_pd(1.0 / 5.0)));
    ln = _mm_add_pd(_mm_set1_pd(1.0 / 3.0), _mm_mul_pd(x, ln));
    ln = _mm_add_pd(_mm_set1_pd(-1.0 / 2.0), _mm_mul_pd(x, ln));
    ln = _mm_add_pd(_mm_set1_pd(1.0), _mm_mul_pd(x, ln));
    ln = _mm_mul_pd(x, ln);
    // The exponents e = biased - 1023, the low 32 bits of each lane, to doubles.
    const __m128i e = _mm_sub_epi32(_mm_shuffle_epi32(biased, _MM_SHUFFLE(2, 0, 2, 0)), _mm_set1_epi32(1023));
    const __m128d log2 = _mm_add_pd(_mm_add_pd(_mm_cvtepi32_pd(e), _mm_set_pd(log2_table.log2_c[i1], log2_table.log2_c[i0])),
                                    _mm_mul_pd(ln, _mm_set1_pd(1.4426950408889634)));
    return _mm_mul_pd(_mm_set1_pd(0.5), log2);
}

// Trilinear's two levels for n levels of detail, two at a time: for lambda strictly between
// 0 and `last`, l0 = int(lambda) and fraction = float(lambda - l0), as trilinear_over works
// them out; l0 = -1 for every other lambda (either end of the pyramid, NaN), whose fraction
// is unspecified.
inline void trilinear_levels_lanes(const double* lambdas, int n, int last, int* l0s, float* fractions) {
    const __m128d top = _mm_set1_pd(double(last));
    int k = 0;
    for (; k + 1 < n; k += 2) {
        const __m128d lambda = _mm_loadu_pd(lambdas + k);
        const __m128d between = _mm_and_pd(_mm_cmpgt_pd(lambda, _mm_setzero_pd()), _mm_cmplt_pd(lambda, top));
        const __m128i whole = _mm_cvttpd_epi32(_mm_and_pd(lambda, between));  // (0 outside)
        const __m128i inside = _mm_shuffle_epi32(_mm_castpd_si128(between), _MM_SHUFFLE(2, 0, 2, 0));
        const __m128i level = _mm_or_si128(_mm_and_si128(inside, whole), _mm_andnot_si128(inside, _mm_set1_epi32(-1)));
        _mm_storel_epi64(reinterpret_cast<__m128i*>(l0s + k), level);
        _mm_storel_pi(reinterpret_cast<__m64*>(fractions + k), _mm_cvtpd_ps(_mm_sub_pd(lambda, _mm_cvtepi32_pd(whole))));
    }
    if (k < n) {
        const double lambda = lambdas[k];
        l0s[k] = lambda > 0.0 && lambda < double(last) ? int(lambda) : -1;
        if (l0s[k] >= 0) fractions[k] = float(lambda - l0s[k]);
    }
}
#endif

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
    const auto bilinear_at = [&](int l) { return sample_bilinear(mip.level(l), s, u, v); };
    const int last = mip.level_count() - 1;
    const Color4 blend = trilinear_over(last, lambda, bilinear_at);
    if (!mip.base().is_hdr() || all_finite(blend)) [[likely]]
        return blend;
    // HDR levels more than the float maximum apart (-3e38 and 3e38) overflowed b - a: the
    // blend in double. (8-bit levels cannot: the short paths, which read only those, are
    // left without the test, which cost anisotropic filtering 8% of its time.)
    if (!(lambda > 0.0 && lambda < double(last))) return blend;  // one level, read as it is
    const int l0 = int(lambda);
    const glm::dvec4 a(bilinear_at(l0)), b(bilinear_at(l0 + 1));
    return Color4(a + double(float(lambda - l0)) * (b - a));
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
