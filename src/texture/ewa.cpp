// EWA filtering (see include/texr/texture/ewa.h).
#include "texr/texture/ewa.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

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

// The weighted average over the ellipse at one level. (u, v) in [0, 1] texture space;
// d1, d2 two conjugate semi-diameters of the ellipse in the same units (sample_ewa passes its
// principal axes; ewa.h's coefficients give the same ellipse for any conjugate pair).
Color4 ewa_at_level(const Image& image, const Sampler& s, double u, double v, double d1u, double d1v, double d2u,
                    double d2v, int& texels) {
    const int w = image.width(), h = image.height();
    const bool node = s.registration == Registration::node;
    // The diameters on this level's lattice (node registration: its n - 1 spacings).
    const LatticeSize lattice = lattice_size(image, s);
    d1u *= lattice.width, d2u *= lattice.width, d1v *= lattice.height, d2v *= lattice.height;

    // Ellipse coefficients, normalised so the boundary is Q = 1.
    double a = d1v * d1v + d2v * d2v + 1.0;
    double b = -2.0 * (d1u * d1v + d2u * d2v);
    double c = d1u * d1u + d2u * d2u + 1.0;
    const double f = a * c - b * b * 0.25;
    a /= f, b /= f, c /= f;

    // Bounding box of the ellipse: |s| <= sqrt(c / det'), |t| <= sqrt(a / det'), det' = a c - b^2/4.
    const double det = a * c - b * b * 0.25;
    const double half_s = std::sqrt(c / det), half_t = std::sqrt(a / det);

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
        if (std::isnan(x)) return 0.0;  // (as split_lattice reads NaN)
        const double below = -half - 2.0, above = double(n) + half + 2.0;
        // From 1e15 texels on (and at infinity) no fraction is left to keep the ellipse's place
        // on the lattice by (and x + ceil(below - x) would round away from below).
        if (!(std::fabs(x) < 1e15)) return x < 0.0 ? below : above;
        if (x < below) return x + std::ceil(below - x);
        if (x > above) return x - std::ceil(x - above);
        return x;
    };
    const double cs = centre(u, w, half_s, s.wrap_u), ct = centre(v, h, half_t, s.wrap_v);
    // The box is a few hundred texels at most (max_anisotropy <= 64), so the floors fit in int.
    const int s0 = int(-floor_to_int64(half_s - cs)), s1 = int(floor_to_int64(cs + half_s));
    const int t0 = int(-floor_to_int64(half_t - ct)), t1 = int(floor_to_int64(ct + half_t));

    const auto& weights = gaussian_weights();
    Color4 sum(0.0f);
    float weight_sum = 0.0f;
    // Wrap the box's columns once (the usual box is a few dozen texels wide); rows are
    // wrapped once each. Q is stepped along a row (below).
    // `visit` walks the ellipse; row_at(j) and texel_at(row, column) read the texels, so an
    // 8-bit image with no border can be read through row addresses.
    constexpr int stack_columns = 128;
    int stack_column_store[stack_columns];
    std::vector<int> heap_column_store;  // a footprint wider than the stack store (a high max anisotropy)
    const int width = s1 - s0 + 1;
    if (width > stack_columns) heap_column_store.resize(std::size_t(width));
    int* const columns = width > stack_columns ? heap_column_store.data() : stack_column_store;
    for (int k = 0; k < width; ++k) columns[k] = wrap_index(s.wrap_u, s0 + k, w, node);
    const float* const weight_of = weights.data();
    int inside = 0;
    const auto visit = [&](auto row_at, auto texel_at) {
        for (int it = t0; it <= t1; ++it) {
            const double tt = it - ct;
            const auto row = row_at(wrap_index(s.wrap_v, it, h, node));
            const auto cell = [&](double r2, int k) {
                if (!(r2 < 1.0)) return;  // outside the ellipse (or NaN)
                // Q >= 0 (the form is positive definite); stepping may round it below 0.
                const float weight = weight_of[int(std::max(r2, 0.0) * (weight_table_size - 1))];
                sum += weight * texel_at(row, columns[k]);
                weight_sum += weight;
                ++inside;
            };
            // Q steps along the row in two chains, even and odd cells, each two cells at a time
            // (Q(s + 2) - Q(s) = a (4 s + 4) + 2 b t, which grows by 8 a per step), so that no
            // cell's Q waits for the one before it. The cells are still added in order.
            const double ss = s0 - cs;
            double r2_even = a * ss * ss + b * ss * tt + c * tt * tt;
            double r2_odd = a * (ss + 1.0) * (ss + 1.0) + b * (ss + 1.0) * tt + c * tt * tt;
            double step_even = a * (4.0 * ss + 4.0) + 2.0 * b * tt, step_odd = step_even + 4.0 * a;
            const double step_step = 8.0 * a;
            int k = 0;
            for (; k + 1 < width; k += 2) {
                cell(r2_even, k), cell(r2_odd, k + 1);
                r2_even += step_even, step_even += step_step;
                r2_odd += step_odd, step_odd += step_step;
            }
            if (k < width) cell(r2_even, k);
        }
    };
    const bool bordered = s.wrap_u == Wrap::border || s.wrap_v == Wrap::border;
    if (!image.is_hdr() && !bordered) {
        const LdrLevel level = image.ldr_level();
        visit([&](int j) { return level.texels + std::size_t(j) * level.row_bytes; },
              [&](const std::uint8_t* row, int i) { return decode_ldr_texel(row + std::size_t(i) * 4, level.decode); });
    } else {
        visit([](int j) { return j; },
              [&](int j, int i) { return (i < 0 || j < 0) ? s.border : image.texel(i, j); });
    }
    texels += inside;
    if (weight_sum <= 0.0f) return fetch(image, s, int(std::lround(cs)), int(std::lround(ct)));
    return sum / weight_sum;
}

}  // namespace

Color4 sample_ewa(const MipMap& mip, const Sampler& s, double u, double v, const UVDerivatives& d, int& texels) {
    texels = 0;
    // Work in base-level texels (of the registration's lattice) so the axes are comparable
    // when W != H.
    const LatticeSize base = lattice_size(mip.base(), s);
    const double w = base.width, h = base.height;
    // The ellipse's principal axes (footprint_axes: d1 and d2 are its conjugate diameters).
    const FootprintAxes axes = footprint_axes_of(d, w, h);
    const double major = axes.major;
    if (!(major > 0.0) || !std::isfinite(major)) {  // a point, or a footprint beyond measure
        texels = 4;
        return sample_bilinear(major > 0.0 ? mip.level(mip.level_count() - 1) : mip.base(), s, u, v);
    }
    // Clamp the eccentricity: stretch the minor axis (this blurs a little instead of reading an
    // unbounded number of texels). The level: where the minor axis spans about one texel.
    const EwaLevel at_level = ewa_level(major, axes.minor, s.max_anisotropy);
    const double minor = at_level.minor;
    const double a1u = major * axes.major_u, a1v = major * axes.major_v;   // the major axis
    const double a2u = -minor * axes.major_v, a2v = minor * axes.major_u;  // the minor axis
    // That level is blended with the next one. A footprint wider than the coarsest level reads
    // that level's average, as the ellipse there would cover the whole image (and cost
    // without bound).
    const int last = mip.level_count() - 1;
    const double lambda = at_level.lambda;
    if (lambda >= double(last)) {
        texels = 4;
        return sample_bilinear(mip.level(last), s, u, v);
    }
    const int l0 = int(lambda);
    const float t = float(lambda - l0);
    const double inv_w = footprint_scale / w, inv_h = footprint_scale / h;
    const auto at = [&](int level) {
        return ewa_at_level(mip.level(level), s, u, v, a1u * inv_w, a1v * inv_h, a2u * inv_w, a2v * inv_h, texels);
    };
    const Color4 a = at(l0);
    if (t == 0.0f || l0 == last) return a;
    const Color4 b = at(l0 + 1);
    return a + t * (b - a);
}

}  // namespace texr
