// Nearest, bilinear and bicubic reconstruction (see include/texr/texture/reconstruct.h).
#include "texr/texture/reconstruct.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

namespace texr {

namespace {

// Texture coordinate -> lattice coordinate (texels), split into whole texels (reduced by
// whole periods, so it fits an int) and the fraction.
inline LatticePoint lattice(Registration registration, Wrap wrap, double t, int n, double inv_n) {
    const bool node = registration == Registration::node;
    return split_lattice(wrap, node ? t * (n - 1) : t * n - 0.5, n, inv_n, node);
}

}  // namespace

float mitchell_netravali(float x, float b, float c) {
    x = std::fabs(x);
    if (x < 1.0f)
        return ((12.0f - 9.0f * b - 6.0f * c) * x * x * x + (-18.0f + 12.0f * b + 6.0f * c) * x * x + (6.0f - 2.0f * b)) / 6.0f;
    if (x < 2.0f)
        return ((-b - 6.0f * c) * x * x * x + (6.0f * b + 30.0f * c) * x * x + (-12.0f * b - 48.0f * c) * x +
                (8.0f * b + 24.0f * c)) / 6.0f;
    return 0.0f;
}

Color4 sample_bicubic(const Image& image, const Sampler& sampler, double u, double v) {
    const int w = image.width(), h = image.height();
    if (sampler.registration == Registration::node &&  // the slide's border test, as nearest and bilinear
        ((sampler.wrap_u == Wrap::border && outside_border(u)) || (sampler.wrap_v == Wrap::border && outside_border(v))))
        return sampler.border;
    const LatticePoint x = lattice(sampler.registration, sampler.wrap_u, u, w, image.inv_width());
    const LatticePoint y = lattice(sampler.registration, sampler.wrap_v, v, h, image.inv_height());
    const int x0 = int(x.whole), y0 = int(y.whole);
    const float fu = float(x.fraction), fv = float(y.fraction);
    // Taps at offsets -1, 0, 1, 2 from floor(x): distances 1 + f, f, 1 - f, 2 - f.
    // With node registration a border axis has been tested above: the lookup lies inside
    // [0, 1], where the slide returns the texture, so taps beyond its edge nodes read the edge
    // (as clamp), not the border colour.
    const bool node = sampler.registration == Registration::node;
    const Wrap tap_wrap_u = node && sampler.wrap_u == Wrap::border ? Wrap::clamp : sampler.wrap_u;
    const Wrap tap_wrap_v = node && sampler.wrap_v == Wrap::border ? Wrap::clamp : sampler.wrap_v;
    float wu[4], wv[4];
    int iu[4], iv[4];
    for (int k = 0; k < 4; ++k) {
        wu[k] = mitchell_netravali(float(k - 1) - fu, sampler.cubic_b, sampler.cubic_c);
        wv[k] = mitchell_netravali(float(k - 1) - fv, sampler.cubic_b, sampler.cubic_c);
        iu[k] = wrap_index(tap_wrap_u, x0 + k - 1, w, node);
        iv[k] = wrap_index(tap_wrap_v, y0 + k - 1, h, node);
    }
    Color4 sum(0.0f);
    for (int b = 0; b < 4; ++b) {
        Color4 row(0.0f);
        for (int a = 0; a < 4; ++a) row += wu[a] * reconstruct_detail::texel_or_border(image, sampler, iu[a], iv[b]);
        sum += wv[b] * row;
    }
    if (!all_finite(sum)) {
        // Overflowed in float: HDR texels near 3.4e38 times weights above 1 (B and C far from
        // [0, 1]) made inf - inf. The same sum in double; a true value beyond float stays inf.
        // Each axis's weights sum to 1, but not quite in floats: the sum is divided by theirs,
        // or texels at the float maximum itself came out above it (inf).
        glm::dvec4 total(0.0);
        for (int b = 0; b < 4; ++b) {
            glm::dvec4 row(0.0);
            for (int a = 0; a < 4; ++a) row += double(wu[a]) * glm::dvec4(reconstruct_detail::texel_or_border(image, sampler, iu[a], iv[b]));
            total += double(wv[b]) * row;
        }
        double weight_u = 0.0, weight_v = 0.0;
        for (int k = 0; k < 4; ++k) weight_u += double(wu[k]), weight_v += double(wv[k]);
        sum = Color4(total / (weight_u * weight_v));
    }
    if (sampler.clamp_overshoot) {
        const Color4 t00 = reconstruct_detail::texel_or_border(image, sampler, iu[1], iv[1]), t10 = reconstruct_detail::texel_or_border(image, sampler, iu[2], iv[1]);
        const Color4 t01 = reconstruct_detail::texel_or_border(image, sampler, iu[1], iv[2]), t11 = reconstruct_detail::texel_or_border(image, sampler, iu[2], iv[2]);
        sum = glm::clamp(sum, glm::min(glm::min(t00, t10), glm::min(t01, t11)), glm::max(glm::max(t00, t10), glm::max(t01, t11)));
    }
    return sum;
}

}  // namespace texr
