// The texture layer's entry point: one texture lookup with the texture's own filter.
// Only the filters below this call touch texels (DESIGN.md, "Layering").
#pragma once
#include <cstdint>

#include "texr/raster/homography.h"
#include "texr/scene/scene.h"
#include "texr/texture/minify.h"
#include "texr/texture/reconstruct.h"

namespace texr {

// The filters with a footprint (out of line; they read many texels anyway).
Color4 lookup_footprint(const Texture& texture, double u, double v, const UVDerivatives& d, std::uint64_t& texels);

// (u, v) and their exact screen derivatives (ignored by filters without a footprint).
// Adds the number of texels read to `texels`. Nearest, bilinear and trilinear are compiled
// in place.
[[gnu::always_inline]] inline Color4 lookup(const Texture& t, double u, double v, const UVDerivatives& d, std::uint64_t& texels) {
    switch (t.sampler.filter) {
        case Filter::nearest: texels += 1; return sample_nearest(*t.image, t.sampler, u, v);
        case Filter::bilinear: texels += 4; return sample_bilinear(*t.image, t.sampler, u, v);
        case Filter::trilinear: {
            const MipMap& mip = *t.mipmap;
            const double lambda = level_of_detail(d, mip.base().width(), mip.base().height());
            texels += (lambda > 0.0 && lambda < mip.level_count() - 1) ? 8 : 4;  // one level or two
            return sample_trilinear(mip, t.sampler, u, v, lambda);
        }
        default: return lookup_footprint(t, u, v, d, texels);
    }
}

}  // namespace texr
