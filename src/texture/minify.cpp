// Mipmapped minification filters (see include/texr/texture/minify.h).
#include "texr/texture/minify.h"

#include <algorithm>
#include <cmath>

#include "texr/texture/reconstruct.h"

namespace texr {

Color4 sample_anisotropic(const MipMap& mip, const Sampler& s, double u, double v, const UVDerivatives& d, int& probes) {
    const double w = mip.base().width(), h = mip.base().height();
    const double rho_x = std::sqrt(minify_detail::squared_texels(d.dudx, d.dvdx, w, h)), rho_y = std::sqrt(minify_detail::squared_texels(d.dudy, d.dvdy, w, h));
    const double major = std::max(rho_x, rho_y), minor = std::min(rho_x, rho_y);
    if (!(major > 0.0) || !std::isfinite(major)) {  // a point, or a footprint beyond measure
        probes = 1;
        return sample_bilinear(major > 0.0 ? mip.level(mip.level_count() - 1) : mip.base(), s, u, v);
    }
    const double ratio = minor > 0.0 ? major / minor : double(s.max_anisotropy);
    const int n = std::max(1, int(std::ceil(std::min(ratio, double(s.max_anisotropy)) - 1e-9)));
    const double lambda = std::log2(major / n);
    // The major axis in texture coordinates.
    const double axis_u = rho_x >= rho_y ? d.dudx : d.dudy, axis_v = rho_x >= rho_y ? d.dvdx : d.dvdy;
    Color4 sum(0.0f);
    // The probes lie within half the major axis of (u, v): when the default sampler's short
    // path holds for that whole segment, every probe reads the level views directly
    // (the same texels and arithmetic as sample_trilinear, without its per-probe checks).
    // The levels above the base are needed (and built) only for lambda > 0.
    const bool short_path = takes_short_path(mip.base(), s) &&
                            minify_detail::within_short_path_limit(std::fabs(u) + 0.5 * std::fabs(axis_u),
                                                                   std::fabs(v) + 0.5 * std::fabs(axis_v), w, h);
    const LdrLevel base = short_path ? mip.base().ldr_level() : LdrLevel{};
    const LdrLevel* levels = short_path ? (lambda > 0.0 ? mip.ldr_levels() : &base) : nullptr;
    for (int k = 0; k < n; ++k) {
        const double offset = (k + 0.5) / n - 0.5;  // evenly spaced across the footprint
        const double pu = u + offset * axis_u, pv = v + offset * axis_v;
        sum += levels ? minify_detail::trilinear_over(mip.level_count() - 1, lambda,
                                                      [&](int l) { return bilinear_in(levels[l], pu, pv); })
                      : sample_trilinear(mip, s, pu, pv, lambda);
    }
    probes = n;
    return sum * (1.0f / float(n));
}

}  // namespace texr
