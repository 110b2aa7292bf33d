// Mipmapped minification filters (see include/texr/texture/minify.h).
#include "texr/texture/minify.h"

#include <algorithm>
#include <cmath>

#include "texr/texture/reconstruct.h"

namespace texr {

double level_of_detail(const UVDerivatives& d, int width, int height) {
    const double rho_x = std::hypot(width * d.dudx, height * d.dvdx);
    const double rho_y = std::hypot(width * d.dudy, height * d.dvdy);
    const double rho = std::max(rho_x, rho_y);
    return rho > 0.0 ? std::log2(rho) : -1e9;  // a point footprint: full magnification
}

Color4 sample_mip_nearest(const MipMap& mip, const Sampler& s, double u, double v, double lambda, bool bilinear) {
    // OpenGL's nearest level: lambda <= 1/2 -> 0, else ceil(lambda + 1/2) - 1.
    int level = lambda <= 0.5 ? 0 : int(std::ceil(lambda + 0.5)) - 1;
    level = std::min(level, mip.level_count() - 1);
    const Image& image = mip.level(level);
    return bilinear ? sample_bilinear(image, s, u, v) : sample_nearest(image, s, u, v);
}

Color4 sample_trilinear(const MipMap& mip, const Sampler& s, double u, double v, double lambda) {
    const int last = mip.level_count() - 1;
    if (lambda <= 0.0) return sample_bilinear(mip.base(), s, u, v);
    if (lambda >= double(last)) return sample_bilinear(mip.level(last), s, u, v);
    const int l0 = int(lambda);
    const float t = float(lambda - l0);
    const Color4 a = sample_bilinear(mip.level(l0), s, u, v);
    const Color4 b = sample_bilinear(mip.level(l0 + 1), s, u, v);
    return a + t * (b - a);
}

Color4 sample_anisotropic(const MipMap& mip, const Sampler& s, double u, double v, const UVDerivatives& d, int& probes) {
    const double w = mip.base().width(), h = mip.base().height();
    const double rho_x = std::hypot(w * d.dudx, h * d.dvdx), rho_y = std::hypot(w * d.dudy, h * d.dvdy);
    const double major = std::max(rho_x, rho_y), minor = std::min(rho_x, rho_y);
    if (!(major > 0.0)) {
        probes = 1;
        return sample_bilinear(mip.base(), s, u, v);
    }
    const double ratio = minor > 0.0 ? major / minor : double(s.max_anisotropy);
    const int n = std::max(1, int(std::ceil(std::min(ratio, double(s.max_anisotropy)) - 1e-9)));
    const double lambda = std::log2(major / n);
    // The major axis in texture coordinates.
    const double axis_u = rho_x >= rho_y ? d.dudx : d.dudy, axis_v = rho_x >= rho_y ? d.dvdx : d.dvdy;
    Color4 sum(0.0f);
    for (int k = 0; k < n; ++k) {
        const double offset = (k + 0.5) / n - 0.5;  // evenly spaced across the footprint
        sum += sample_trilinear(mip, s, u + offset * axis_u, v + offset * axis_v, lambda);
    }
    probes = n;
    return sum * (1.0f / float(n));
}

}  // namespace texr
