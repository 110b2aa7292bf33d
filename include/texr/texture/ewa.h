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
// thousands of cells a row. Where a level is one texel across an axis and the ellipse's box
// is 64 cells or more across it (EwaSum), the sum is taken along the other axis, one read a
// row, from what the row's cells read:
// - repeat, mirror or clamp on that axis: every cell of the row reads the row's texel, weighted
//   by the Gaussian integrated along the row's chord of the ellipse, in closed form (ewa.cpp,
//   row_weights);
// - border: one cell reads the row's texel, weighted as in the cell sum, and the rest the
//   border colour, weighted by the row's integral less that cell's.
// The rows' integrals stand for the sums of their cells, whose weights the table rounds (in
// the tests: within 1.4e-3 of the cell sum where rows of texels meet rows of border of contrast
// 0.9, under half an 8-bit step; beside the border, within 4e-4 of |texel - border|). Boxes
// narrower than 64 cells, and every level of an image whose sides both shrink, are summed
// cell by cell.
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
// the level is one texel across the other and the ellipse's box 64 cells or more across it:
// rows (along t: one texel across u) or columns (along u), each reading one texel, or that
// texel beside the border where the 1-texel axis wraps to the border.
enum class EwaSum { cells, rows, columns, rows_beside_border, columns_beside_border };
// For texr explain: the sum sample_ewa takes on `level` at this lookup (cells where it reads
// no ellipse: a point or a footprint beyond measure).
EwaSum ewa_sum_on_level(const MipMap& mip, const Sampler& s, double u, double v, const UVDerivatives& d, int level);

}  // namespace texr
