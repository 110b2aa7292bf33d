// Projective textures (see include/texr/texture/projective.h).
#include "texr/texture/projective.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

namespace texr {

ProjectedUV project(const Projector& p, const glm::dvec3& point, const glm::dvec3& dp_dx, const glm::dvec3& dp_dy) {
    ProjectedUV out;
    const glm::dvec4 c = p.matrix * glm::dvec4(point, 1.0);
    // Ahead of the projector along its view (for a parallel one c.w is always 1: the depth
    // along the view decides for both).
    if (!(glm::dot(point - p.eye, p.forward) > 0.0) || !(c.w > 0.0) || !std::isfinite(c.x) || !std::isfinite(c.y)) return out;
    out.ahead = true;
    out.u = 0.5 * (c.x / c.w + 1.0), out.v = 0.5 * (c.y / c.w + 1.0);
    // d(x/w) = (dx w - x dw) / w^2, and a direction's clip coordinates are M (dP, 0).
    const auto derivative = [&](const glm::dvec3& dp, double& du, double& dv) {
        const glm::dvec4 dc = p.matrix * glm::dvec4(dp, 0.0);
        du = 0.5 * (dc.x * c.w - c.x * dc.w) / (c.w * c.w);
        dv = 0.5 * (dc.y * c.w - c.y * dc.w) / (c.w * c.w);
    };
    derivative(dp_dx, out.d.dudx, out.d.dvdx);
    derivative(dp_dy, out.d.dudy, out.d.dvdy);
    return out;
}

}  // namespace texr
