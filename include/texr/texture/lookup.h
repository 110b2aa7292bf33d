// The texture layer's entry point: one texture lookup with the texture's own filter.
// Only the filters below this call touch texels (DESIGN.md, "Layering").
#pragma once
#include <cstdint>

#include "texr/raster/homography.h"
#include "texr/scene/scene.h"

namespace texr {

// (u, v) and their exact screen derivatives (ignored by filters without a footprint).
// Adds the number of texels read to `texels`.
Color4 lookup(const Texture& texture, double u, double v, const UVDerivatives& d, std::uint64_t& texels);

}  // namespace texr
