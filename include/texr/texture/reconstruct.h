// Reconstruction filters (lecture, "Nearest Neighbor" and "Bilinear Interpolation"): the
// continuous function an image texture defines between its texel samples.
#pragma once
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

// Dispatches on sampler.filter.
Color4 sample(const Image& image, const Sampler& sampler, double u, double v);

}  // namespace texr
