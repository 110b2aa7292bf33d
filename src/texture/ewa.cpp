// EWA filtering (see include/texr/texture/ewa.h).
#include "texr/texture/ewa.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "texr/texture/minify.h"
#include "texr/texture/reconstruct.h"

namespace texr {

namespace {

constexpr float gaussian_alpha = 2.0f;
// The ellipse is the one the derivative vectors span, times this factor. 1 is the classic choice
// (an ellipse one pixel in radius: twice the pixel's own footprint, so the Gaussian blurs
// more than the pixel's box); 0.5 is the pixel's footprint itself, which aliases at the
// horizon. 0.7 scored best against the 16x16 box-filtered ground truth of texr bench
// filters (plane 33.1 dB vs 31.0 dB at 1.0 and 30.3 dB at 0.5, at 512x384) and reads
// about half the texels of 1.0.
constexpr double footprint_scale = 0.7;
constexpr int weight_table_size = 128;

// exp(-alpha r^2) - exp(-alpha) for r^2 in [0, 1), tabulated.
const std::array<float, weight_table_size>& gaussian_weights() {
    static const std::array<float, weight_table_size> table = [] {
        std::array<float, weight_table_size> t{};
        for (int i = 0; i < weight_table_size; ++i) {
            const float r2 = float(i) / float(weight_table_size - 1);
            t[std::size_t(i)] = std::exp(-gaussian_alpha * r2) - std::exp(-gaussian_alpha);
        }
        return t;
    }();
    return table;
}

// The per-thread memory of ewa_over: a list of cells inside the ellipse (each one's Q and
// place, below), summed and emptied whenever it fills, and the places of a box's columns.
// Each holds ewa_list_cells entries, so a thread keeps 96 KiB, whatever the box (the usual box
// is a few dozen cells, and a list of 4096 is emptied once per lookup; an ellipse at max
// anisotropy 64 across the lattice's diagonal has a box of up to about 127 x 127).
constexpr std::size_t ewa_list_cells = std::size_t(1) << 12;
struct EwaScratch {
    std::vector<double> q = std::vector<double>(ewa_list_cells);
    std::vector<std::int64_t> places = std::vector<std::int64_t>(ewa_list_cells);
    std::vector<std::int64_t> column_places = std::vector<std::int64_t>(ewa_list_cells);
};
EwaScratch& ewa_scratch() {
    thread_local EwaScratch scratch;
    return scratch;
}

// The ellipse on one level: Q(s, t) = a s^2 + b s t + c t^2 < 1 about the centre (cs, ct) on
// the level's lattice, and its bounding box of cells [s0, s1] x [t0, t1].
struct EwaEllipse {
    double a, b, c, cs, ct;
    int s0, s1, t0, t1;
};

// The ellipse at one level. (u, v) in [0, 1] texture space; d1, d2 two conjugate
// semi-diameters of the ellipse in the same units (sample_ewa passes its principal axes;
// ewa.h's coefficients give the same ellipse for any conjugate pair). Inline, so that the
// two levels' ellipses, worked out one after the other, overlap their divides and roots.
[[gnu::always_inline]] inline EwaEllipse ellipse_at_level(const Image& image, const Sampler& s, double u, double v, double d1u,
                                                          double d1v, double d2u, double d2v) {
    const int w = image.width(), h = image.height();
    const bool node = s.registration == Registration::node;
    // The diameters on this level's lattice (node registration: its n - 1 spacings).
    const LatticeSize lattice = lattice_size(image, s);
    d1u *= lattice.width, d2u *= lattice.width, d1v *= lattice.height, d2v *= lattice.height;

    // Ellipse coefficients, normalised so the boundary is Q = 1.
    double a = d1v * d1v + d2v * d2v + 1.0;
    double b = -2.0 * (d1u * d1v + d2u * d2v);
    double c = d1u * d1u + d2u * d2u + 1.0;
    // Bounding box of the ellipse: |s| <= sqrt(c / det'), |t| <= sqrt(a / det'), det' = a c - b^2/4,
    // which for the normalised ellipse below (det' = 1 / f) is sqrt(c), sqrt(a) before normalising.
    const double half_s = std::sqrt(c), half_t = std::sqrt(a);
    const double f = a * c - b * b * 0.25;
    a /= f, b /= f, c /= f;

    // The centre on this level's lattice (cell: texel centres at integers), with whole periods
    // removed so it stays small for any u (repeat, mirror); for clamp and border, a centre
    // beyond the box's reach of the image is moved towards it by whole texels, to just
    // outside that reach: every texel the ellipse covers still reads the edge (or the border),
    // with the same weights, as the ellipse keeps its place on the texel lattice.
    const auto centre = [&](double t, int n, double half, Wrap wrap) {
        const double x = node ? t * (n - 1) : t * n - 0.5;
        if (wrap == Wrap::repeat || wrap == Wrap::mirror) {
            const LatticePoint p = split_lattice(wrap, x, n, node);
            return double(p.whole) + p.fraction;
        }
        if (std::isnan(x)) return 0.0;  // (NaN: at the image's first texel, inside)
        const double below = -half - 2.0, above = double(n) + half + 2.0;
        // From 1e15 texels on (and at infinity) no fraction is left to keep the ellipse's place
        // on the lattice by (and x + ceil(below - x) would round away from below).
        if (!(std::fabs(x) < 1e15)) return x < 0.0 ? below : above;
        if (x < below) return x + std::ceil(below - x);
        if (x > above) return x - std::ceil(x - above);
        return x;
    };
    const double cs = centre(u, w, half_s, s.wrap_u), ct = centre(v, h, half_t, s.wrap_v);
    // The box: a few hundred texels a side at most on a level of an image whose sides both
    // shrink with the levels (max_anisotropy <= 64); along the 1-texel side of a thin image
    // (whose levels keep it 1 texel) the ellipse keeps its base length, below 64 times the
    // coarsest level's scale (sample_ewa reads that level alone beyond it): at most about
    // 1.5M texels for 16384-texel images, which ewa_average sums row by row across that
    // side. The floors fit in int either way.
    const int s0 = int(-floor_to_int64(half_s - cs)), s1 = int(floor_to_int64(cs + half_s));
    const int t0 = int(-floor_to_int64(half_t - ct)), t1 = int(floor_to_int64(ct + half_t));
    return {a, b, c, cs, ct, s0, s1, t0, t1};
}

// The Gaussian-weighted average over the ellipse e at one level; `texels` grows by the number
// of texels read. Wide: an HDR image's texels are summed in double (ewa_average sums again so
// where the float sum of texels near the float maximum overflowed).
template <bool Wide>
Color4 ewa_over(const Image& image, const Sampler& s, const EwaEllipse& e, int& texels) {
    const int w = image.width(), h = image.height();
    const bool node = s.registration == Registration::node;
    const double a = e.a, b = e.b, c = e.c, cs = e.cs, ct = e.ct;
    const int s0 = e.s0, s1 = e.s1, t0 = e.t0, t1 = e.t1;
    // The box: the usual one is a few dozen texels wide and about as many high. The ellipse
    // holds the unit disc (the +1 above), so its box is at least 2 texels a side; max() only
    // keeps an ellipse beyond measure from a negative count.
    const int width = std::max(s1 - s0 + 1, 0), height = std::max(t1 - t0 + 1, 0);
    EwaScratch& scratch = ewa_scratch();
    double* const q_list = scratch.q.data();
    std::int64_t* const place_list = scratch.places.data();

    // Each cell's place is row_place(r) + column_place(k): on an 8-bit image with no border
    // the texel's byte offset (its texels are read through row addresses); else its wrapped
    // row and column, each plus 1 (-1 is the border), as ((j + 1) << 32) + i + 1.
    const bool bordered = s.wrap_u == Wrap::border || s.wrap_v == Wrap::border;
    const bool by_offset = !image.is_hdr() && !bordered;
    const LdrLevel level = by_offset ? image.ldr_level(true) : LdrLevel{};
    const std::int64_t row_bytes = std::int64_t(level.row_bytes);
    const auto wrapped_column_place = [&](int k) {
        const int i = wrap_index(s.wrap_u, s0 + k, w, node);
        return by_offset ? std::int64_t(i) * 4 : std::int64_t(i) + 1;
    };
    const auto wrapped_row_place = [&](int r) {
        const int j = wrap_index(s.wrap_v, t0 + r, h, node);
        return by_offset ? std::int64_t(j) * row_bytes : (std::int64_t(j) + 1) << 32;
    };

    // The cells inside the ellipse are summed with Gaussian weights in the order they are
    // listed (below), a list at a time.
    const float* const weight_of = gaussian_weights().data();
    // Q >= 0 (the form is positive definite); stepping may round it below 0.
    const auto weight_at = [&](std::size_t i) { return weight_of[int(std::max(q_list[i], 0.0) * (weight_table_size - 1))]; };
    // An 8-bit image's decoded copy, where it has one (Image::decoded_texels), holds the
    // values decode_ldr_texel reads from the bytes, 4 floats a texel at 4 times the byte
    // offset: one load a texel instead of four byte loads and three table loads.
    const float* const decoded = level.decoded;
    Color4 sum(0.0f);
    // The sum of texels read through Image::texel (HDR images, and 8-bit ones with a border):
    // in double when Wide.
    using TexelSum = std::conditional_t<Wide, glm::dvec4, Color4>;
    using TexelWeight = std::conditional_t<Wide, double, float>;
    TexelSum texel_sum(0.0f);
    float weight_sum = 0.0f;
    // Wide: the weights of texel_sum in double too. (Their float sum, rounded, could leave the
    // average of texels at the float maximum above it, and the average read as inf.)
    double wide_weight_sum = 0.0;
#if defined(__SSE__)
    __m128 sum_lanes = _mm_setzero_ps();  // the sum from the copy (each lane the same product and sum as Color4's)
#endif
    // Sums the list's first `listed` cells. (Inlined where it is called: out of line, the
    // plane's EWA frame took 3% more instructions. The sums in locals: sums kept behind the
    // lambda's references would be stored and loaded again at every cell.)
    const auto sum_listed = [&](std::size_t listed) __attribute__((always_inline)) {
        float listed_weight = weight_sum;
        if (decoded) {
#if defined(__SSE__)
            __m128 lanes = sum_lanes;
            for (std::size_t i = 0; i < listed; ++i) {
                const float weight = weight_at(i);
                lanes = _mm_add_ps(lanes, _mm_mul_ps(_mm_set1_ps(weight), _mm_loadu_ps(decoded + place_list[i])));
                listed_weight += weight;
            }
            sum_lanes = lanes;
#else
            Color4 partial = sum;
            for (std::size_t i = 0; i < listed; ++i) {
                const float weight = weight_at(i);
                const float* t = decoded + place_list[i];
                partial += weight * Color4(t[0], t[1], t[2], t[3]);
                listed_weight += weight;
            }
            sum = partial;
#endif
        } else if (by_offset) {
            Color4 partial = sum;
            for (std::size_t i = 0; i < listed; ++i) {
                const float weight = weight_at(i);
                partial += weight * decode_ldr_texel(level.texels + place_list[i], level.decode);
                listed_weight += weight;
            }
            sum = partial;
        } else {
            TexelSum partial = texel_sum;
            for (std::size_t i = 0; i < listed; ++i) {
                const float weight = weight_at(i);
                const int column = int(place_list[i] & 0xffffffff) - 1, row = int(place_list[i] >> 32) - 1;
                partial += TexelWeight(weight) * TexelSum((column < 0 || row < 0) ? s.border : image.texel(column, row));
                listed_weight += weight;
                if constexpr (Wide) wide_weight_sum += double(weight);
            }
            texel_sum = partial;
        }
        weight_sum = listed_weight;
        texels += int(listed);
    };

    // The cells inside the ellipse (Q < 1) are listed in the box's order, rows from t0, each
    // from s0: every cell is written to the list, and the list grows only by those inside, so
    // there is no branch per cell (a branch whose outcome changes twice in every row of every
    // ellipse is mispredicted often). Q steps along a row in two chains, even and odd cells,
    // each two cells at a time (Q(s + 2) - Q(s) = a (4 s + 4) + 2 b t, which grows by 8 a per
    // step), so that no cell's Q waits for the one before it; the two chains share a pair of
    // SSE2 lanes. A full list is summed and emptied, mid-row if need be.
    const std::size_t room = ewa_list_cells;
    // `chunked`: whether the list may fill before the box is listed (a box of more than
    // ewa_list_cells cells); the usual box is listed without that test.
    std::size_t n = 0;  // the cells listed and not yet summed
    const auto list_cells = [&](auto chunked, auto row_place_of, auto column_place_of) {
        for (int r = 0; r < height; ++r) {
            const double tt = (t0 + r) - ct;
            const std::int64_t row = row_place_of(r);
            const double ss = s0 - cs;
            const double r2_even = a * ss * ss + b * ss * tt + c * tt * tt;
            const double r2_odd = a * (ss + 1.0) * (ss + 1.0) + b * (ss + 1.0) * tt + c * tt * tt;
            const double step_even = a * (4.0 * ss + 4.0) + 2.0 * b * tt, step_odd = step_even + 4.0 * a;
            int k = 0;
            // The pairs of cells from k up to pairs_end() (exclusive): all of the row's, or as
            // many as the list has room for.
            const auto pairs_end = [&] {
                if constexpr (!decltype(chunked)::value) {
                    return width - 1;
                } else {
                    if (room - n < 2) sum_listed(n), n = 0;
                    return k + 2 * int(std::min(std::size_t(width - k) / 2, (room - n) / 2));
                }
            };
#if defined(__SSE2__)
            __m128d r2 = _mm_set_pd(r2_odd, r2_even), step = _mm_set_pd(step_odd, step_even);
            const __m128d step_step = _mm_set1_pd(8.0 * a), one = _mm_set1_pd(1.0);
            do {
                for (const int k_end = pairs_end(); k < k_end; k += 2) {
                    const int inside_mask = _mm_movemask_pd(_mm_cmplt_pd(r2, one));  // (NaN: outside)
                    _mm_storel_pd(q_list + n, r2);
                    place_list[n] = row + column_place_of(k);
                    n += std::size_t(inside_mask & 1);
                    _mm_storeh_pd(q_list + n, r2);
                    place_list[n] = row + column_place_of(k + 1);
                    n += std::size_t(inside_mask >> 1);
                    r2 = _mm_add_pd(r2, step), step = _mm_add_pd(step, step_step);
                }
            } while (decltype(chunked)::value && k + 1 < width);  // (at once: one pass takes the row)
            const double r2_last = _mm_cvtsd_f64(r2);
#else
            double r2_even_k = r2_even, r2_odd_k = r2_odd, step_even_k = step_even, step_odd_k = step_odd;
            const double step_step = 8.0 * a;
            do {
                for (const int k_end = pairs_end(); k < k_end; k += 2) {
                    q_list[n] = r2_even_k, place_list[n] = row + column_place_of(k);
                    n += std::size_t(r2_even_k < 1.0);
                    q_list[n] = r2_odd_k, place_list[n] = row + column_place_of(k + 1);
                    n += std::size_t(r2_odd_k < 1.0);
                    r2_even_k += step_even_k, step_even_k += step_step;
                    r2_odd_k += step_odd_k, step_odd_k += step_step;
                }
            } while (decltype(chunked)::value && k + 1 < width);
            const double r2_last = r2_even_k;
#endif
            if (k < width) {
                if constexpr (decltype(chunked)::value) {
                    if (n == room) sum_listed(n), n = 0;
                }
                q_list[n] = r2_last, place_list[n] = row + column_place_of(k);
                n += std::size_t(r2_last < 1.0);
            }
        }
    };
    const bool chunked = std::size_t(width) * std::size_t(height) > room;
    const std::true_type in_chunks;
    const std::false_type at_once;
    // Columns wrapped once into a table, where the box is not inside the image and the table
    // holds its width.
    const bool inside_image = by_offset && s0 >= 0 && s1 < w && t0 >= 0 && t1 < h;
    const bool column_table = !inside_image && std::size_t(width) <= ewa_list_cells;
    std::int64_t* const column_place = scratch.column_places.data();
    if (column_table)
        for (int k = 0; k < width; ++k) column_place[k] = wrapped_column_place(k);
    if (!chunked && inside_image) {
        // The usual box, inside the image: places without wrapping.
        list_cells(at_once, [&](int r) { return std::int64_t(t0 + r) * row_bytes; }, [&](int k) { return std::int64_t(s0 + k) * 4; });
    } else if (!chunked) {
        list_cells(at_once, wrapped_row_place, [&](int k) { return column_place[k]; });
    } else {
        // (rare: an ellipse at max anisotropy 64 across the lattice's diagonal; a box wider
        // than the column table, wrapped cell by cell, takes a max_anisotropy above the
        // scene format's 64)
        list_cells(in_chunks, wrapped_row_place, [&](int k) { return column_table ? column_place[k] : wrapped_column_place(k); });
    }
    sum_listed(n);
#if defined(__SSE__)
    if (decoded) {
        alignas(16) float out[4];
        _mm_store_ps(out, sum_lanes);
        sum = Color4(out[0], out[1], out[2], out[3]);
    }
#endif
    if (weight_sum <= 0.0f) return fetch(image, s, int(std::lround(cs)), int(std::lround(ct)));
    if (!by_offset) return Color4(texel_sum / (Wide ? TexelWeight(wide_weight_sum) : TexelWeight(weight_sum)));
    return sum / weight_sum;
}

// The weight of one row of the ellipse, for a level that does not change along the rows: what
// the row's cells add up to in ewa_over, each weight read from the table at the entry at or
// below its Q, for a row long enough that its cells stand for its chord. On row t,
// Q = r + a (s - s*)^2, with s* the chord's middle and r = t^2 (a c - b^2/4) / a the least Q
// on the row (a, b, c: EwaEllipse's normalised coefficients; r = t^2 / A with A of ewa.h, the
// ellipse's half-height squared). With y = (s - s*) sqrt(a), the cells whose Q lies in the
// table's step [j - 1, j) / (n - 1) (n entries w_0 .. w_(n-1), w_(n-1) = 0) cover the y
// between sqrt((j - 1) / (n - 1) - r) and sqrt(j / (n - 1) - r) on either side, so the row's
// weight, in cells times sqrt(a) (a factor every row shares), is
//   W(r) = 2 sum over j > (n - 1) r of sqrt(j / (n - 1) - r) (w_(j-1) - w_j).
// The term of the first such j has a square root that falls to 0 at the step's end: it is
// worked out at each lookup; the rest, smooth within a step, is tabulated row_steps + 1 times
// a step and read linearly (within about 1e-6). The shear and the ellipse's width along the
// rows drop out: only its height tells the rows' weights.
constexpr int row_steps = 16;
using RowWeights = std::array<double, (weight_table_size - 1) * (row_steps + 1)>;  // the rest, by step k, then sub-step m
const RowWeights& row_weight_table() {
    static const RowWeights table = [] {
        RowWeights t{};
        const float* const w = gaussian_weights().data();
        const double step = 1.0 / double(weight_table_size - 1);
        for (int k = 0; k < weight_table_size - 1; ++k)
            for (int m = 0; m <= row_steps; ++m) {
                const double r = (double(k) + double(m) / row_steps) * step;
                double rest = 0.0;
                for (int j = k + 2; j < weight_table_size; ++j)
                    rest += 2.0 * std::sqrt(std::max(double(j) * step - r, 0.0)) * (double(w[j - 1]) - double(w[j]));
                t[std::size_t(k * (row_steps + 1) + m)] = rest;
            }
        return t;
    }();
    return table;
}
// W(r) above, for 0 <= r < 1.
inline double row_weight(double r, const RowWeights& table, const float* w) {
    const double x = r * double(weight_table_size - 1);
    const int k = int(x);  // the step r is in: its first term is j = k + 1
    const double at = (x - double(k)) * row_steps;
    const int m = int(at);
    const double* const rest = &table[std::size_t(k * (row_steps + 1) + m)];
    const double first = 2.0 * std::sqrt((double(k + 1) - x) / double(weight_table_size - 1)) * (double(w[k]) - double(w[k + 1]));
    return first + rest[0] + (at - double(m)) * (rest[1] - rest[0]);
}

// Where the ellipse's middle row is ewa_rows_from cells long or more across a level's one
// texel, ewa_average sums the ellipse along the other axis, one read a line (ewa_sum_for):
// there a row's cells, thousands on a thin image's level, add up to nearly W(r). Shorter
// rows: the cell sum, exact and cheap. (The row, not the box: a sheared ellipse's box can be
// wide where its rows are a few cells long.)

// How ewa_average sums the ellipse e on `image` (ewa.h, EwaSum): row by row where the level is
// one texel across s and the ellipse's middle row (Q = a s^2 < 1: 2 / sqrt(a) cells long)
// ewa_rows_from cells or more, column by column likewise across t (2 / sqrt(c)), along whichever
// box side is shorter where both are; else cell by cell.
[[gnu::always_inline]] inline EwaSum ewa_sum_for(const Image& image, const Sampler& s, const EwaEllipse& e) {
    const bool one_s = image.width() == 1, one_t = image.height() == 1;
    if (!one_s && !one_t) return EwaSum::cells;  // (the usual level)
    // 2 / sqrt(a) >= ewa_rows_from, as a <= 4 / ewa_rows_from^2 (false for NaN).
    const double long_row = 4.0 / (double(ewa_rows_from) * double(ewa_rows_from));
    const bool by_rows = one_s && e.a <= long_row, by_columns = one_t && e.c <= long_row;
    if (!by_rows && !by_columns) return EwaSum::cells;
    const int across_s = e.s1 - e.s0 + 1, across_t = e.t1 - e.t0 + 1;
    if (by_rows && (!by_columns || across_t <= across_s)) return s.wrap_u == Wrap::border ? EwaSum::rows_beside_border : EwaSum::rows;
    return s.wrap_v == Wrap::border ? EwaSum::columns_beside_border : EwaSum::columns;
}

// EWA by lines: rows (rows = true) over a level one texel across s whose wrap_u repeats,
// mirrors or clamps, where every cell of a row reads the row's texel in column 0; columns
// (rows = false) over a level one texel across t likewise. The ellipse's sum is each line's texel
// times the line's weight W(r), one read a line. Summed in double (an HDR texel near the
// float maximum cannot overflow it).
// (Out of line: the usual level takes ewa_over, and ewa_average stays inline in sample_ewa.)
[[gnu::noinline]] Color4 ewa_by_lines(const Image& image, const Sampler& s, const EwaEllipse& e, bool rows, int& texels) {
    const bool node = s.registration == Registration::node;
    // r = x^2 (a c - b^2/4) / a along t, / c along s.
    const double centre = rows ? e.ct : e.cs, r_per_x2 = (e.a * e.c - e.b * e.b * 0.25) / (rows ? e.a : e.c);
    const int first = rows ? e.t0 : e.s0, last = rows ? e.t1 : e.s1;
    const RowWeights& table = row_weight_table();
    const float* const weight_of = gaussian_weights().data();
    glm::dvec4 sum(0.0);
    double weight_sum = 0.0;
    for (int k = first; k <= last; ++k) {
        const double x = k - centre, r = x * x * r_per_x2;
        if (!(r < 1.0)) continue;
        const double weight = row_weight(r, table, weight_of);
        const int i = rows ? 0 : wrap_index(s.wrap_u, k, image.width(), node);
        const int j = rows ? wrap_index(s.wrap_v, k, image.height(), node) : 0;
        sum += weight * glm::dvec4(reconstruct_detail::texel_or_border(image, s, i, j));
        weight_sum += weight;
        ++texels;
    }
    // (The row nearest the centre is inside, at r <= 1/4: A >= 1, and the box holds it.)
    return Color4(sum / weight_sum);
}

// EWA over a level one texel across s with border wrap (rows = true; across t: columns): on
// each row, the cell s = 0 reads the row's texel (column 0) and every other cell the border
// colour. The row's weights add up to nearly W(r) / sqrt(a) cells, the cell's weight is the
// Gaussian's at its Q, so the mean is
//   border + sum(cell weight x (texel - border)) / sum(row weights),
// one read a row. In double.
[[gnu::noinline]] Color4 ewa_beside_border(const Image& image, const Sampler& s, const EwaEllipse& e, bool rows, int& texels) {
    const bool node = s.registration == Registration::node;
    const double a = e.a, b = e.b, c = e.c;
    // Along the row, Q = r + a (s - s*)^2 (row_weight): the row's weights add up to W(r) / sqrt(a)
    // (per_cell: W is in cells times sqrt(a)). The cell s = 0 of row t is at (-cs, t - ct) from
    // the centre (columns: t = 0 of column s at (s - cs, -ct)).
    const double r_per_x2 = (a * c - b * b * 0.25) / (rows ? a : c), per_cell = 1.0 / std::sqrt(rows ? a : c);
    const double centre = rows ? e.ct : e.cs, to_cell = rows ? -e.cs : -e.ct;
    const int first = rows ? e.t0 : e.s0, last = rows ? e.t1 : e.s1;
    const RowWeights& table = row_weight_table();
    const float* const weight_of = gaussian_weights().data();
    const glm::dvec4 border(s.border);
    glm::dvec4 sum(0.0);
    double weight_sum = 0.0;
    for (int k = first; k <= last; ++k) {
        const double x = k - centre, r = x * x * r_per_x2;
        if (!(r < 1.0)) continue;
        weight_sum += row_weight(r, table, weight_of) * per_cell;
        const double q = rows ? a * to_cell * to_cell + b * to_cell * x + c * x * x : a * x * x + b * x * to_cell + c * to_cell * to_cell;
        if (!(q < 1.0)) continue;
        const int i = rows ? 0 : wrap_index(s.wrap_u, k, image.width(), node);
        const int j = rows ? wrap_index(s.wrap_v, k, image.height(), node) : 0;
        sum += double(weight_of[int(std::max(q, 0.0) * (weight_table_size - 1))]) *
               (glm::dvec4(reconstruct_detail::texel_or_border(image, s, i, j)) - border);
        ++texels;
    }
    // (The row nearest the centre is inside, at r <= 1/4: weight_sum > 0.)
    return Color4(border + sum / weight_sum);
}

// The Gaussian-weighted mean over the ellipse e on `image`, summed as ewa_sum_for says:
// ewa_over cell by cell (summed again in double where the float sum of an HDR image's texels
// overflowed: 8-bit texels and the border colour cannot overflow it), or along one axis.
[[gnu::always_inline]] inline Color4 ewa_average(const Image& image, const Sampler& s, const EwaEllipse& e, int& texels) {
    switch (ewa_sum_for(image, s, e)) {
        case EwaSum::cells: break;
        case EwaSum::rows: return ewa_by_lines(image, s, e, true, texels);
        case EwaSum::columns: return ewa_by_lines(image, s, e, false, texels);
        case EwaSum::rows_beside_border: return ewa_beside_border(image, s, e, true, texels);
        case EwaSum::columns_beside_border: return ewa_beside_border(image, s, e, false, texels);
    }
    const Color4 average = ewa_over<false>(image, s, e, texels);
    if (all_finite(average) || !image.is_hdr()) return average;
    int again = 0;
    return ewa_over<true>(image, s, e, again);
}

// The ellipse's conjugate semi-diameters d1, d2 (texture units, times footprint_scale) and
// its level of detail, from the footprint (sample_ewa's first steps). `measured` is false for
// a point (major axis 0 or NaN) and for a footprint beyond measure (`beyond`: infinite).
struct EwaFootprint {
    bool measured, beyond;
    double lambda, d1u, d1v, d2u, d2v;
};
[[gnu::always_inline]] inline EwaFootprint ewa_footprint(const MipMap& mip, const Sampler& s, const UVDerivatives& d) {
    // Work in base-level texels (of the registration's lattice) so the axes are comparable
    // when W != H.
    const LatticeSize base = lattice_size(mip.base(), s);
    const double w = base.width, h = base.height;
    // The ellipse's principal axes (footprint_axes: d1 and d2 are its conjugate diameters).
    const FootprintAxes axes = footprint_axes_of(d, w, h);
    const double major = axes.major;
    if (!(major > 0.0) || !std::isfinite(major)) return {false, major > 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    // Clamp the eccentricity: stretch the minor axis (this blurs a little instead of reading an
    // unbounded number of texels). The level: where the minor axis spans about one texel.
    const EwaLevel at_level = ewa_level(major, axes.minor, s.max_anisotropy);
    const double minor = at_level.minor;
    const double a1u = major * axes.major_u, a1v = major * axes.major_v;   // the major axis
    const double a2u = -minor * axes.major_v, a2v = minor * axes.major_u;  // the minor axis
    const double inv_w = footprint_scale / w, inv_h = footprint_scale / h;
    return {true, false, at_level.lambda, a1u * inv_w, a1v * inv_h, a2u * inv_w, a2v * inv_h};
}

}  // namespace

Color4 sample_ewa(const MipMap& mip, const Sampler& s, double u, double v, const UVDerivatives& d, int& texels) {
    texels = 0;
    const EwaFootprint f = ewa_footprint(mip, s, d);
    if (!f.measured) {  // a point (the base level), or a footprint beyond measure (the coarsest)
        texels = 4;
        return sample_bilinear(f.beyond ? mip.level(mip.level_count() - 1) : mip.base(), s, u, v);
    }
    // That level is blended with the next one. A footprint wider than the coarsest level reads
    // that level's average, as the ellipse there would cover the whole image (and cost
    // without bound).
    const int last = mip.level_count() - 1;
    const double lambda = f.lambda;
    if (lambda >= double(last)) {
        texels = 4;
        return sample_bilinear(mip.level(last), s, u, v);
    }
    const int l0 = int(lambda);
    const float t = float(lambda - l0);
    const Image& first = mip.level(l0);
    const EwaEllipse e0 = ellipse_at_level(first, s, u, v, f.d1u, f.d1v, f.d2u, f.d2v);
    if (t == 0.0f || l0 == last) return ewa_average(first, s, e0, texels);
    const Image& second = mip.level(l0 + 1);
    const EwaEllipse e1 = ellipse_at_level(second, s, u, v, f.d1u, f.d1v, f.d2u, f.d2v);
    const Color4 a = ewa_average(first, s, e0, texels);
    const Color4 b = ewa_average(second, s, e1, texels);
    const Color4 blend = a + t * (b - a);
    if (all_finite(blend) || !mip.base().is_hdr()) return blend;
    // HDR levels more than the float maximum apart (-3e38 and 3e38) overflowed b - a: the
    // blend in double.
    return Color4(glm::dvec4(a) + double(t) * (glm::dvec4(b) - glm::dvec4(a)));
}

EwaSum ewa_sum_on_level(const MipMap& mip, const Sampler& s, double u, double v, const UVDerivatives& d, int level) {
    const EwaFootprint f = ewa_footprint(mip, s, d);
    if (!f.measured || level < 0 || level >= mip.level_count()) return EwaSum::cells;
    const Image& image = mip.level(level);
    return ewa_sum_for(image, s, ellipse_at_level(image, s, u, v, f.d1u, f.d1v, f.d2u, f.d2v));
}

}  // namespace texr
