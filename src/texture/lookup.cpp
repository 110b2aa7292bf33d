// Dispatch on the texture's filter (see include/texr/texture/lookup.h).
#include "texr/texture/lookup.h"

#include "texr/texture/ewa.h"
#include "texr/texture/minify.h"
#include "texr/texture/reconstruct.h"

namespace texr {

Color4 lookup_footprint(const Texture& t, double u, double v, const UVDerivatives& d, std::uint64_t& texels) {
    const Sampler& s = t.sampler;
    const MipMap& mip = *t.mipmap;
    // The level of detail, for the mip filters only.
    const auto lod = [&] {
        const LatticeSize base = lattice_size(mip.base(), s);
        return level_of_detail(d, base.width, base.height);
    };
    switch (s.filter) {
        case Filter::nearest: texels += 1; return sample_nearest(mip.base(), s, u, v);
        case Filter::bilinear: texels += 4; return sample_bilinear(mip.base(), s, u, v);
        case Filter::bicubic: texels += 16; return sample_bicubic(mip.base(), s, u, v);
        case Filter::nearest_mip_nearest:
            texels += 1;
            return sample_mip_nearest(mip, s, u, v, lod(), false);
        case Filter::bilinear_mip_nearest:
            texels += 4;
            return sample_mip_nearest(mip, s, u, v, lod(), true);
        case Filter::trilinear: {
            const double lambda = lod();
            texels += std::uint64_t(trilinear_texels(mip, lambda));
            return sample_trilinear(mip, s, u, v, lambda);
        }
        case Filter::anisotropic: {
            int probes = 0;
            return sample_anisotropic(mip, s, u, v, d, probes, &texels);
        }
        case Filter::ewa: {
            int read = 0;
            const Color4 c = sample_ewa(mip, s, u, v, d, read);
            texels += std::uint64_t(read);
            return c;
        }
    }
    return {};
}

}  // namespace texr
