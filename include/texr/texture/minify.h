// Minification (lecture, "Texture Mapping": find the pixel's pre-image in the texture and
// integrate over it). The pre-image of a pixel is approximated by the parallelogram spanned
// by the exact screen derivatives (du/dx, dv/dx) and (du/dy, dv/dy) from the homography.
// Level of detail, with lengths measured in texels of the base level (W x H):
//   rho_x = sqrt((W du/dx)^2 + (H dv/dx)^2),  rho_y = sqrt((W du/dy)^2 + (H dv/dy)^2)
//   lambda = log2(max(rho_x, rho_y))
// the true lengths of the two derivative vectors, not a max of absolute components, so the
// level does not change when the footprint rotates.
#pragma once
#include "texr/raster/homography.h"
#include "texr/texture/mipmap.h"
#include "texr/texture/sampler.h"

namespace texr {

double level_of_detail(const UVDerivatives& d, int width, int height);

// GL_NEAREST_MIPMAP_NEAREST / GL_LINEAR_MIPMAP_NEAREST: the level nearest to lambda, read
// with nearest or bilinear reconstruction. lambda <= 0 is magnification: the base level.
Color4 sample_mip_nearest(const MipMap& mip, const Sampler& s, double u, double v, double lambda, bool bilinear);

// GL_LINEAR_MIPMAP_LINEAR: bilinear in levels floor(lambda) and floor(lambda) + 1, blended by
// the fraction of lambda.
Color4 sample_trilinear(const MipMap& mip, const Sampler& s, double u, double v, double lambda);

// Anisotropic: N = min(ceil(major / minor), max_anisotropy) trilinear probes spaced evenly
// along the footprint's major axis, at lambda = log2(major / N), averaged. Returns the
// number of probes through `probes`.
Color4 sample_anisotropic(const MipMap& mip, const Sampler& s, double u, double v, const UVDerivatives& d, int& probes);

}  // namespace texr
