// The texture layer's entry point: one texture lookup with the texture's own filter.
// Only the filters below this call touch texels (docs/design.md, "Layering").
#pragma once
#include <cstdint>

#include "texr/raster/homography.h"
#include "texr/scene/scene.h"
#include "texr/texture/reconstruct.h"

namespace texr {

// The filters with a footprint (out of line; they read many texels anyway).
Color4 lookup_footprint(const Texture& texture, double u, double v, const UVDerivatives& d, std::uint64_t& texels);

// (u, v) and their exact screen derivatives (ignored by filters without a footprint).
// Adds the number of texels read to `texels`. Nearest and bilinear are compiled in place,
// in their general form: the span loop takes the short paths of power-of-two textures
// itself (scanline.h), and this keeps the many span loops it compiles small.
[[gnu::always_inline]] inline Color4 lookup(const Texture& t, double u, double v, const UVDerivatives& d, std::uint64_t& texels) {
    switch (t.sampler.filter) {
        case Filter::nearest: texels += 1; return reconstruct_detail::sample_nearest_general(*t.image, t.sampler, u, v);
        case Filter::bilinear: texels += 4; return reconstruct_detail::sample_bilinear_general(*t.image, t.sampler, u, v);
        default: return lookup_footprint(t, u, v, d, texels);
    }
}

}  // namespace texr
