// Bump mapping (see include/texr/texture/bump.h).
#include "texr/texture/bump.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "texr/texture/lookup.h"
#include "texr/texture/procedural.h"

namespace texr {

double bump_height_at(const Texture& t, double height, double u, double v, std::uint64_t& texels) {
    if (t.procedural) return height * double(procedural_value(*t.procedural, {u, v, 0.0}, 0.0).x);
    // (no footprint: the filter's reconstruction at the base level)
    return height * double(lookup(t, u, v, UVDerivatives{0.0, 0.0, 0.0, 0.0}, texels).x);
}

BumpSlope bump_slope(const Texture& t, double height, double u, double v, double footprint, std::uint64_t& texels) {
    BumpSlope s;
    if (t.procedural) {
        s.step_u = s.step_v = 1.0 / (256.0 * t.procedural->scale);
    } else {
        s.step_u = 1.0 / double(t.mipmap->base().width());
        s.step_v = 1.0 / double(t.mipmap->base().height());
    }
    if (footprint > 0.0 && std::isfinite(footprint)) s.step_u = std::max(s.step_u, footprint), s.step_v = std::max(s.step_v, footprint);
    s.b_u = (bump_height_at(t, height, u + s.step_u, v, texels) - bump_height_at(t, height, u - s.step_u, v, texels)) / (2.0 * s.step_u);
    s.b_v = (bump_height_at(t, height, u, v + s.step_v, texels) - bump_height_at(t, height, u, v - s.step_v, texels)) / (2.0 * s.step_v);
    return s;
}

SurfaceTangents surface_tangents(const glm::dvec3 p[3], const double u[3], const double v[3]) {
    const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
    const double du1 = u[1] - u[0], dv1 = v[1] - v[0], du2 = u[2] - u[0], dv2 = v[2] - v[0];
    const double det = du1 * dv2 - du2 * dv1;
    SurfaceTangents t;
    if (!(det != 0.0) || !std::isfinite(det)) return t;
    // Cramer's rule on the two edge equations.
    t.o_u = (dv2 * e1 - dv1 * e2) / det;
    t.o_v = (du1 * e2 - du2 * e1) / det;
    return t;
}

glm::dvec3 bumped_normal(const glm::dvec3& n, const SurfaceTangents& t, const BumpSlope& slope) {
    const glm::dvec3 area = glm::cross(t.o_u, t.o_v);
    const double a = glm::length(area);
    if (!(a > 0.0) || !std::isfinite(a)) return n;
    const double s = glm::dot(area, n) >= 0.0 ? 1.0 : -1.0;
    const glm::dvec3 d = slope.b_u * glm::cross(n, t.o_v) - slope.b_v * glm::cross(n, t.o_u);
    const glm::dvec3 bumped = n + (s / a) * d;
    return std::isfinite(bumped.x) && std::isfinite(bumped.y) && std::isfinite(bumped.z) ? bumped : n;
}

}  // namespace texr
