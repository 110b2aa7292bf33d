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
// A level one texel across an axis that wraps by repeat, mirror or clamp (a thin image's
// levels; the coarse levels of a non-square image, such as a 256x64 image's 4x1, 2x1 and 1x1)
// does not change along that axis: every cell of a
// row across it reads one texel, so the sum over the ellipse is taken row by row, each row's
// texel weighted by the Gaussian integrated along the row's chord of the ellipse, in closed
// form (ewa.cpp, row_weights): one read a row, where the ellipse can be thousands of texels
// long across such an axis (it does not shrink with the levels of a thin image). A level one
// texel across both is that texel. Across an axis that wraps to the border, each row has one
// cell on the texel and the rest on the border colour: under an ellipse 32 cells or more
// across that axis, the sum is taken row by row too, the border weighted by the row's
// integral and the texel by its cell's Gaussian weight (within about 5e-4 of the cell sum).
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

}  // namespace texr
