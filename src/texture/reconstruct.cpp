// Nearest and bilinear reconstruction (see include/texr/texture/reconstruct.h).
#include "texr/texture/reconstruct.h"

#include <cmath>

namespace texr {

Color4 fetch(const Image& image, const Sampler& sampler, int i, int j) {
    const int wi = wrap_index(sampler.wrap_u, i, image.width());
    const int wj = wrap_index(sampler.wrap_v, j, image.height());
    if (wi < 0 || wj < 0) return sampler.border;
    return image.texel(wi, wj);
}

namespace {

// Texture coordinate -> lattice coordinate (in texels), reduced so it fits an int.
double lattice_for_bilinear(Registration registration, Wrap wrap, double t, int n) {
    const double x = registration == Registration::cell ? t * n - 0.5 : t * (n - 1);
    return reduce_lattice(wrap, x, n);
}

int lattice_for_nearest(Registration registration, Wrap wrap, double t, int n) {
    const double x = registration == Registration::cell ? t * n : t * (n - 1) + 0.5;
    const int l = int(std::floor(reduce_lattice(wrap, x, n)));
    // The slide's min(floor(u * n), n - 1): u = 1 exactly still reads the last texel.
    if ((wrap == Wrap::clamp || wrap == Wrap::border) && l == n && t <= 1.0) return n - 1;
    return l;
}

}  // namespace

Color4 sample_nearest(const Image& image, const Sampler& sampler, double u, double v) {
    const int lu = lattice_for_nearest(sampler.registration, sampler.wrap_u, u, image.width());
    const int lv = lattice_for_nearest(sampler.registration, sampler.wrap_v, v, image.height());
    return fetch(image, sampler, lu, lv);
}

Color4 sample_bilinear(const Image& image, const Sampler& sampler, double u, double v) {
    const double x = lattice_for_bilinear(sampler.registration, sampler.wrap_u, u, image.width());
    const double y = lattice_for_bilinear(sampler.registration, sampler.wrap_v, v, image.height());
    const double x0 = std::floor(x), y0 = std::floor(y);
    const float fu = float(x - x0), fv = float(y - y0);
    const int i = int(x0), j = int(y0);
    // Successive linear interpolations: along v in columns i and i + 1, then along u.
    const Color4 column0 = (1.0f - fv) * fetch(image, sampler, i, j) + fv * fetch(image, sampler, i, j + 1);
    const Color4 column1 = (1.0f - fv) * fetch(image, sampler, i + 1, j) + fv * fetch(image, sampler, i + 1, j + 1);
    return (1.0f - fu) * column0 + fu * column1;
}

Color4 sample(const Image& image, const Sampler& sampler, double u, double v) {
    switch (sampler.filter) {
        case Filter::nearest: return sample_nearest(image, sampler, u, v);
        case Filter::bilinear: return sample_bilinear(image, sampler, u, v);
    }
    return {};
}

}  // namespace texr
