// Reconstruction filters (lecture, "Nearest Neighbor", "Bilinear Interpolation", "Bicubic
// Interpolation"): the continuous function an image texture defines between its samples.
// Each works on one image (a mip level) and a texture coordinate; wrap and registration come
// from the sampler. `texels` counts the texels read (for --stats).
#pragma once
#include <cstdint>

#include "texr/texture/image.h"
#include "texr/texture/sampler.h"

namespace texr {

// Texel (i, j) after wrapping each index by the sampler's mode; border texels give the
// sampler's border colour.
Color4 fetch(const Image& image, const Sampler& sampler, int i, int j);

// Nearest neighbour. Cell registration: l = min(floor(u * n), n - 1) (the slide);
// node registration: l = floor(u * (n - 1) + 1/2).
Color4 sample_nearest(const Image& image, const Sampler& sampler, double u, double v);

// Bilinear, as the slide's successive linear interpolations: first along v in the two
// columns floor(x) and floor(x) + 1, then along u. Lattice coordinate x = u * n - 1/2
// (cell) or x = u * (n - 1) (node).
Color4 sample_bilinear(const Image& image, const Sampler& sampler, double u, double v);

// The Mitchell-Netravali cubic k(x) with parameters B, C (Mitchell & Netravali 1988):
//   |x| < 1:      ((12 - 9B - 6C)|x|^3 + (-18 + 12B + 6C)|x|^2 + (6 - 2B)) / 6
//   1 <= |x| < 2: ((-B - 6C)|x|^3 + (6B + 30C)|x|^2 + (-12B - 48C)|x| + (8B + 24C)) / 6
// (B, C) = (0, 1/2) is Catmull-Rom (interpolates the samples), (1, 0) the cubic B-spline
// (never overshoots), (1/3, 1/3) Mitchell's recommendation.
float mitchell_netravali(float x, float b, float c);

// Bicubic: 4x4 texels around the lattice coordinate, weighted by k in u and in v.
// With sampler.clamp_overshoot the result is clamped to the range of the 2x2 nearest texels.
Color4 sample_bicubic(const Image& image, const Sampler& sampler, double u, double v);

}  // namespace texr
