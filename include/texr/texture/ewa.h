// Elliptical weighted average (Heckbert 1989, "Fundamentals of Texture Mapping and Image
// Warping", section 3.5.8). The pixel's footprint is the ellipse spanned by the derivative
// vectors d1 = (du/dx, dv/dx) and d2 = (du/dy, dv/dy), scaled by 0.7 (ewa.cpp says why),
// in texels of the level read:
//   Q(s, t) = A s^2 + B s t + C t^2 <= F,   with
//   A = d1v^2 + d2v^2 + 1,  B = -2 (d1u d1v + d2u d2v),  C = d1u^2 + d2u^2 + 1,  F = A C - B^2 / 4
// (the +1 adds a one-texel reconstruction disc, so magnified footprints stay well formed).
// Texels inside the ellipse get Gaussian weights exp(-alpha r^2) - exp(-alpha), r^2 = Q / F,
// alpha = 2. The ellipse's principal axes (d1 and d2 are conjugate diameters, its axes only
// when perpendicular) come from the singular values of [d1 d2]; the minor axis is stretched
// so major/minor <= max_anisotropy (bounding the texels read), the level is chosen so the
// minor axis spans about one texel, and the results of the two nearest levels are blended.
// A thin image's levels keep their 1-texel side, so that the ellipse (its minor axis
// stretched along that side) stays as long across it, in image widths, as on the base level:
// thousands of cells a row. Where a level is one texel across an axis and the ellipse's
// middle row across it is 64 cells or more long (EwaSum: a thin image's levels, and at high
// anisotropy the coarsest levels of others), the sum is taken along the other axis, one read
// a row, from what the row's cells read:
// - repeat, mirror or clamp on that axis: every cell of the row reads the row's texel, which
//   weighs what the row's cells add up to, W(r): the table's weights over the row's chord of
//   the ellipse, worked out in closed form (ewa.cpp, row_weight);
// - border: one cell reads the row's texel, weighted as in the cell sum, and the rest the
//   border colour, weighted by W(r) less that cell's weight.
// W(r) stands for a long row of cells: measured on random ellipses over thin levels, the
// mean is within 1e-3 of the cell sum where rows of texels meet rows of border (contrast 1),
// 5e-4 on random texels, 6e-5 of |texel - border| beside the border, and closer the wider
// the box. Ellipses with shorter rows are summed cell by cell.
#pragma once
#include <algorithm>
#include <cmath>

#include "texr/raster/homography.h"
#include "texr/texture/minify.h"
#include "texr/texture/mipmap.h"
#include "texr/texture/sampler.h"

namespace texr {

// For axes major >= minor (major > 0, finite): the minor axis after the eccentricity clamp
// (stretched to major / max_anisotropy when the ellipse is more eccentric), and the level of
// detail where that minor axis spans about one texel, lambda = max(0, log2(minor)).
struct EwaLevel {
    double minor, lambda;
    bool stretched;
};
inline EwaLevel ewa_level(double major, double minor, float max_anisotropy) {
    const bool stretched = !(minor * max_anisotropy >= major);
    if (stretched) minor = major / max_anisotropy;
    return {minor, std::max(0.0, minify_detail::log2_positive(std::max(minor, 1e-300))), stretched};
}

// `texels` receives the number of texels read.
Color4 sample_ewa(const MipMap& mip, const Sampler& s, double u, double v, const UVDerivatives& d, int& texels);

// How sample_ewa sums the ellipse on one level (above): cell by cell, or along one axis where
// the level is one texel across the other and the ellipse's middle row 64 cells or more long:
// rows (along t: one texel across u) or columns (along u), each reading one texel, or that
// texel beside the border where the 1-texel axis wraps to the border.
enum class EwaSum { cells, rows, columns, rows_beside_border, columns_beside_border };
// The middle row's length, in cells, from which a level one texel across is summed by rows
// (ewa.cpp says why).
constexpr int ewa_rows_from = 64;
// For texr explain: the sum sample_ewa would take on `level` at this lookup (cells for a point
// or a footprint beyond measure); whether it reads that level at all is the caller's to say.
EwaSum ewa_sum_on_level(const MipMap& mip, const Sampler& s, double u, double v, const UVDerivatives& d, int level);

}  // namespace texr
