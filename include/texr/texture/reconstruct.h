// Reconstruction filters (lecture, "Nearest Neighbor", "Bilinear Interpolation", "Bicubic
// Interpolation"): the continuous function an image texture defines between its samples.
// Each works on one image (a mip level) and a texture coordinate; wrap and registration come
// from the sampler. `texels` counts the texels read (for --stats).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "texr/texture/image.h"
#include "texr/texture/sampler.h"

namespace texr {

// Texel (i, j) after wrapping each index by the sampler's mode; border texels give the
// sampler's border colour.
Color4 fetch(const Image& image, const Sampler& sampler, int i, int j);  // defined below

// Nearest neighbour. Cell registration: l = min(floor(u * n), n - 1) (the slide);
// node registration: l = floor(u * (n - 1) + 1/2).
Color4 sample_nearest(const Image& image, const Sampler& sampler, double u, double v);  // defined below

// Bilinear, as the slide's successive linear interpolations: first along v in the two
// columns floor(x) and floor(x) + 1, then along u. Lattice coordinate x = u * n - 1/2
// (cell) or x = u * (n - 1) (node).
Color4 sample_bilinear(const Image& image, const Sampler& sampler, double u, double v);  // defined below

// The Mitchell-Netravali cubic k(x) with parameters B, C (Mitchell & Netravali 1988):
//   |x| < 1:      ((12 - 9B - 6C)|x|^3 + (-18 + 12B + 6C)|x|^2 + (6 - 2B)) / 6
//   1 <= |x| < 2: ((-B - 6C)|x|^3 + (6B + 30C)|x|^2 + (-12B - 48C)|x| + (8B + 24C)) / 6
// (B, C) = (0, 1/2) is Catmull-Rom (interpolates the samples), (1, 0) the cubic B-spline
// (never overshoots), (1/3, 1/3) Mitchell's recommendation.
float mitchell_netravali(float x, float b, float c);

// Bicubic: 4x4 texels around the lattice coordinate, weighted by k in u and in v.
// With sampler.clamp_overshoot the result is clamped to the range of the 2x2 nearest texels.
Color4 sample_bicubic(const Image& image, const Sampler& sampler, double u, double v);

// --- Definitions of the filters above that run per pixel: inline, so the span loop
// compiles them in place ------------------------------------------------------------------
namespace reconstruct_detail {

[[gnu::always_inline]] inline Color4 texel_or_border(const Image& image, const Sampler& sampler, int i, int j) {
    return (i < 0 || j < 0) ? sampler.border : image.texel(i, j);
}

}  // namespace reconstruct_detail

inline Color4 fetch(const Image& image, const Sampler& sampler, int i, int j) {
    const bool node = sampler.registration == Registration::node;
    return reconstruct_detail::texel_or_border(image, sampler, wrap_index(sampler.wrap_u, i, image.width(), node),
                                               wrap_index(sampler.wrap_v, j, image.height(), node));
}

namespace reconstruct_detail {

// The texel nearest to t along one axis, wrapped (-1: border).
[[gnu::always_inline]] inline int nearest_tap(Registration registration, Wrap wrap, double t, int n, double inv_n) {
    const bool node = registration == Registration::node;
    // Node registration: reduce the lattice position first, then round to the nearest node,
    // so u and u + 1 read the same texel (see wrap_node_index for the node at u = 1).
    const LatticePoint p = split_lattice(wrap, node ? t * (n - 1) : t * n, n, inv_n, node);
    int l = int(p.whole);
    if (node) {
        if (wrap == Wrap::border && outside_border(t)) return -1;  // the slide's border test
        if (p.fraction >= 0.5) ++l;  // round half up (exactly: x + 1/2 can round up from just below 1/2)
    }
    // The slide's min(floor(u * n), n - 1): u = 1 exactly still reads the last texel.
    if ((wrap == Wrap::clamp || wrap == Wrap::border) && l == n && t <= 1.0) return n - 1;
    if (wrap == Wrap::repeat && !node && l < n) return l;  // reduced into [0, n) already
    return wrap_index(wrap, l, n, node);
}

}  // namespace reconstruct_detail

// The short path of the default sampler (cell registration, repeat on both axes) on an
// 8-bit power-of-two image: floor(x) mod n is the low bits of floor(x) in two's complement,
// so no whole periods need removing. x - floor(x) is the exact fraction for |x| < 2^52;
// the short path stops where the general one stops reading fractions (split_lattice:
// beyond 1e15 texels a coordinate reads as 0), so the two agree everywhere. The caller has
// checked takes_short_path (the span walk does so once per triangle).
constexpr double short_path_limit = 1e15;
inline bool takes_short_path(const Image& image, const Sampler& sampler) {
    return image.is_ldr_pow2() && sampler.repeats_cells();
}

namespace reconstruct_detail {

[[gnu::always_inline]] inline Color4 sample_nearest_general(const Image& image, const Sampler& sampler, double u, double v) {
    const int i = nearest_tap(sampler.registration, sampler.wrap_u, u, image.width(), image.inv_width());
    const int j = nearest_tap(sampler.registration, sampler.wrap_v, v, image.height(), image.inv_height());
    return texel_or_border(image, sampler, i, j);
}

}  // namespace reconstruct_detail

// The short path's nearest texel on level l, for |u * width| and |v * height| below
// short_path_limit (the caller has checked: per lookup in sample_nearest_repeat_pow2, per
// span in the span walk).
[[gnu::always_inline]] inline Color4 nearest_in(const LdrLevel& l, double u, double v) {
    return decode_ldr_texel(l.texels + (std::size_t(floor_to_int64(v * l.height) & l.mask_v) << l.row_shift) +
                                std::size_t(floor_to_int64(u * l.width) & l.mask_u) * 4,
                            l.decode);
}

[[gnu::always_inline]] inline Color4 sample_nearest_repeat_pow2(const Image& image, const Sampler& sampler, double u, double v) {
    const double x = u * image.width(), y = v * image.height();
    if (!(std::fabs(x) < short_path_limit && std::fabs(y) < short_path_limit))
        return reconstruct_detail::sample_nearest_general(image, sampler, u, v);
    return nearest_in(image.ldr_level(), u, v);
}

[[gnu::always_inline]] inline Color4 sample_nearest(const Image& image, const Sampler& sampler, double u, double v) {
    if (takes_short_path(image, sampler)) return sample_nearest_repeat_pow2(image, sampler, u, v);
    return reconstruct_detail::sample_nearest_general(image, sampler, u, v);
}

namespace reconstruct_detail {

// The two lattice neighbours of a coordinate along one axis, wrapped, and the fraction
// between them.
struct AxisTaps {
    int i0, i1;  // -1: border
    float f;
};

[[gnu::always_inline]] inline AxisTaps bilinear_taps(Registration registration, Wrap wrap, double t, int n, double inv_n) {
    const bool node = registration == Registration::node;
    if (node && wrap == Wrap::border && outside_border(t)) return {-1, -1, 0.0f};  // the slide's border test
    const LatticePoint p = split_lattice(wrap, node ? t * (n - 1) : t * n - 0.5, n, inv_n, node);
    const int i = int(p.whole);
    if (wrap == Wrap::repeat && !node) return {i, i + 1 < n ? i + 1 : 0, float(p.fraction)};  // i in [0, n) already
    return {wrap_index(wrap, i, n, node), wrap_index(wrap, i + 1, n, node), float(p.fraction)};
}

}  // namespace reconstruct_detail

namespace reconstruct_detail {

[[gnu::always_inline]] inline Color4 sample_bilinear_general(const Image& image, const Sampler& sampler, double u, double v) {
    const AxisTaps a = bilinear_taps(sampler.registration, sampler.wrap_u, u, image.width(), image.inv_width());
    const AxisTaps b = bilinear_taps(sampler.registration, sampler.wrap_v, v, image.height(), image.inv_height());
    if (!image.is_hdr() && (a.i0 | a.i1 | b.i0 | b.i1) >= 0)  // no border texel: the 8-bit fast path
        return image.blend_ldr(a.i0, a.i1, b.i0, b.i1, a.f, b.f);
    // Successive linear interpolations: along v in columns i0 and i1, then along u.
    const Color4 t00 = texel_or_border(image, sampler, a.i0, b.i0), t01 = texel_or_border(image, sampler, a.i0, b.i1);
    const Color4 t10 = texel_or_border(image, sampler, a.i1, b.i0), t11 = texel_or_border(image, sampler, a.i1, b.i1);
    const Color4 column0 = t00 + b.f * (t01 - t00), column1 = t10 + b.f * (t11 - t10);
    const Color4 blend = column0 + a.f * (column1 - column0);
    if (all_finite(blend)) return blend;
    // HDR texels more than the float maximum apart (-3e38 beside 3e38) overflowed a
    // difference, even where the weight is 0: the same steps in double, whose result lies
    // between the texels (a texel that is itself inf or NaN still gives inf or NaN).
    const auto lerp = [](const glm::dvec4& p, const glm::dvec4& q, double f) { return p + f * (q - p); };
    const glm::dvec4 c0 = lerp(glm::dvec4(t00), glm::dvec4(t01), double(b.f)), c1 = lerp(glm::dvec4(t10), glm::dvec4(t11), double(b.f));
    return Color4(lerp(c0, c1, double(a.f)));
}

}  // namespace reconstruct_detail

// Where a short-path lookup reads its texels: the bytes, the decoded copy (the level has
// one), or the decoded copy if the level has one.
enum class TexelSource { bytes, decoded, either };

namespace reconstruct_detail {

// The short path's bilinear cell on level l: the offsets of its two rows (bytes, or floats
// in the decoded copy) and two columns, and the fractions between them.
struct ShortPathCell {
    std::size_t row0, row1, column0, column1;
    float fx, fy;
};
// The cell from the lattice position (x, y) = (u W - 1/2, v H - 1/2), whose floors are (i, j).
[[gnu::always_inline]] inline ShortPathCell cell_at(const LdrLevel& l, std::int64_t i, std::int64_t j, float fx, float fy) {
    // (the short paths' levels are powers of two: a row is 2^row_shift bytes, or floats in
    // the decoded copy)
    return {std::size_t(j & l.mask_v) << l.row_shift, std::size_t((j + 1) & l.mask_v) << l.row_shift,
            std::size_t(i & l.mask_u) * 4, std::size_t((i + 1) & l.mask_u) * 4, fx, fy};
}

// The cell worked out one coordinate at a time: the definition, and the cell where SSE2 is
// not at hand.
[[gnu::always_inline]] inline ShortPathCell short_path_cell_scalar(const LdrLevel& l, double u, double v) {
    const double x = u * l.width - 0.5, y = v * l.height - 0.5;
    // floor and fraction from one truncation: x - trunc(x) is exact, and adding 1 when x is
    // below its truncation rounds the same real number that x - floor(x) rounds.
    const std::int64_t ti = static_cast<std::int64_t>(x), tj = static_cast<std::int64_t>(y);
    const double di = double(ti), dj = double(tj);
    const bool below_x = di > x, below_y = dj > y;
    const double fx = (x - di) + (below_x ? 1.0 : 0.0), fy = (y - dj) + (below_y ? 1.0 : 0.0);
    return cell_at(l, ti - below_x, tj - below_y, float(fx), float(fy));
}

#if defined(__SSE2__)
// Floors and fractions of two lattice positions, one in each lane: the floor from rounding
// to an integer by adding and subtracting 1.5 2^52 (exact for |x| < 2^51; the short paths'
// coordinates are below short_path_limit = 1e15 < 2^50), less 1 where that rounded up; the
// fraction x - floor(x), one rounding of the same real number as short_path_cell_scalar's,
// so the same float (but for x = -0, whose fraction is -0 here and +0 there: a lattice
// position u W - 1/2 is never -0). The integer is read from the low bits of x + 1.5 2^52.
// Like all of texr's arithmetic, this relies on products and sums not being fused
// (-ffp-contract=off, CMakeLists.txt).
struct FloorLanes {
    std::int64_t whole[2];
    float fraction[2];
};
[[gnu::always_inline]] inline FloorLanes floor_lanes(__m128d x) {
    const __m128d magic = _mm_set1_pd(0x1.8p52);
    const __m128d shifted = _mm_add_pd(x, magic);
    const __m128d rounded = _mm_sub_pd(shifted, magic);
    const __m128d up = _mm_cmplt_pd(x, rounded);  // rounded up: the floor is one less
    const __m128i whole = _mm_add_epi64(_mm_sub_epi64(_mm_castpd_si128(shifted), _mm_castpd_si128(magic)),
                                        _mm_castpd_si128(up));  // (up is -1 as an integer)
    const __m128d floor = _mm_sub_pd(rounded, _mm_and_pd(up, _mm_set1_pd(1.0)));
    alignas(16) float fraction[4];
    _mm_store_ps(fraction, _mm_cvtpd_ps(_mm_sub_pd(x, floor)));
    return {{_mm_cvtsi128_si64(whole), _mm_cvtsi128_si64(_mm_unpackhi_epi64(whole, whole))}, {fraction[0], fraction[1]}};
}
#endif

// The short path's cell: x and y in the two lanes of SSE2's doubles where it is at hand (the
// same cell to the bit; when it came, the plane's bilinear frame 2.98-3.01 -> 2.50-2.58 ms,
// anisotropic 56.6 -> 49.2-50.2 ms, 1 thread, alternated runs).
[[gnu::always_inline]] inline ShortPathCell short_path_cell(const LdrLevel& l, double u, double v) {
#if defined(__SSE2__)
    const FloorLanes f = floor_lanes(_mm_sub_pd(_mm_mul_pd(_mm_set_pd(v, u), _mm_set_pd(l.height, l.width)), _mm_set1_pd(0.5)));
    return cell_at(l, f.whole[0], f.whole[1], f.fraction[0], f.fraction[1]);
#else
    return short_path_cell_scalar(l, u, v);
#endif
}

#if defined(__SSE2__)
// The cells of one (u, v) on two levels (trilinear's), x on both in one pair of lanes and y
// in another: when it came, the plane's trilinear frame 7.15-7.37 -> 6.44-6.69 ms against
// one level at a time in scalar code.
[[gnu::always_inline]] inline void short_path_cells(const LdrLevel& a, const LdrLevel& b, double u, double v, ShortPathCell& ca,
                                                    ShortPathCell& cb) {
    const __m128d half = _mm_set1_pd(0.5);
    const FloorLanes x = floor_lanes(_mm_sub_pd(_mm_mul_pd(_mm_set1_pd(u), _mm_set_pd(b.width, a.width)), half));
    const FloorLanes y = floor_lanes(_mm_sub_pd(_mm_mul_pd(_mm_set1_pd(v), _mm_set_pd(b.height, a.height)), half));
    ca = cell_at(a, x.whole[0], y.whole[0], x.fraction[0], y.fraction[0]);
    cb = cell_at(b, x.whole[1], y.whole[1], x.fraction[1], y.fraction[1]);
}
#endif

}  // namespace reconstruct_detail

// The short path's bilinear lookup on level l, under the same condition as nearest_in, from
// the texels `source` says (the same values from either).
template <TexelSource source = TexelSource::either>
[[gnu::always_inline]] inline Color4 bilinear_in(const LdrLevel& l, double u, double v) {
    const reconstruct_detail::ShortPathCell c = reconstruct_detail::short_path_cell(l, u, v);
    if (source == TexelSource::decoded || (source == TexelSource::either && l.decoded))
        return blend_decoded_texels(l.decoded + c.row0, l.decoded + c.row1, c.column0, c.column1, c.fx, c.fy);
    return blend_ldr_texels(l.texels + c.row0, l.texels + c.row1, c.column0, c.column1, l.decode, c.fx, c.fy);
}

#if defined(__SSE__)
// bilinear_in on a level with a decoded copy, in lanes (image.h, blend_decoded_lanes).
[[gnu::always_inline]] inline __m128 bilinear_decoded_lanes(const LdrLevel& l, double u, double v) {
    const reconstruct_detail::ShortPathCell c = reconstruct_detail::short_path_cell(l, u, v);
    return blend_decoded_lanes(l.decoded + c.row0, l.decoded + c.row1, c.column0, c.column1, c.fx, c.fy);
}
#endif

[[gnu::always_inline]] inline Color4 sample_bilinear_repeat_pow2(const Image& image, const Sampler& sampler, double u, double v) {
    const double x = u * image.width() - 0.5, y = v * image.height() - 0.5;
    if (!(std::fabs(x) < short_path_limit && std::fabs(y) < short_path_limit))
        return reconstruct_detail::sample_bilinear_general(image, sampler, u, v);
    return bilinear_in(image.ldr_level(), u, v);
}

[[gnu::always_inline]] inline Color4 sample_bilinear(const Image& image, const Sampler& sampler, double u, double v) {
    if (takes_short_path(image, sampler)) return sample_bilinear_repeat_pow2(image, sampler, u, v);
    return reconstruct_detail::sample_bilinear_general(image, sampler, u, v);
}

}  // namespace texr
