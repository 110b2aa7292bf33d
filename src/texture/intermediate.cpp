// Intermediate (two-stage) mapping (see include/texr/texture/intermediate.h).
#include "texr/texture/intermediate.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

namespace texr {

namespace {
constexpr double pi = 3.14159265358979323846;
}

glm::dvec2 intermediate_uv(const IntermediateMapping& m, const glm::dvec3& p) {
    const glm::dvec3 q = p - m.center;
    const glm::dvec3 y_axis = glm::cross(m.axis, m.reference);
    const double x = glm::dot(q, m.reference), y = glm::dot(q, y_axis), z = glm::dot(q, m.axis);
    switch (m.kind) {
        case Intermediate::planar: return {x / m.size, y / m.size};
        case Intermediate::cylindrical:
        case Intermediate::spherical: {
            double phi = std::atan2(y, x + 0.0);
            if (phi < 0.0) phi += 2.0 * pi;
            const double u = phi / (2.0 * pi);
            if (m.kind == Intermediate::cylindrical) return {u, z / m.size};
            const double r = std::sqrt(x * x + y * y + z * z);
            const double theta = r > 0.0 ? std::acos(std::clamp(z / r, -1.0, 1.0)) : 0.0;
            return {u, 1.0 - theta / pi};  // (the image's top row at +z': see the header)
        }
        case Intermediate::none: break;
    }
    return {0.0, 0.0};
}

UVDerivatives intermediate_derivatives(const IntermediateMapping& m, const glm::dvec3& p, const glm::dvec3& dp_dx,
                                       const glm::dvec3& dp_dy) {
    // Central differences over a small part of each screen step: exact for the planar map,
    // within a relative 1e-6 or so for the others away from the axis.
    const double h = 1e-3;
    const auto along = [&](const glm::dvec3& dp, double& du, double& dv) {
        const glm::dvec2 a = intermediate_uv(m, p + h * dp), b = intermediate_uv(m, p - h * dp);
        double u = a.x - b.x;
        if (m.kind != Intermediate::planar) u -= std::round(u);  // (across the seam: modulo 1)
        du = u / (2.0 * h), dv = (a.y - b.y) / (2.0 * h);
    };
    UVDerivatives d{0.0, 0.0, 0.0, 0.0};
    along(dp_dx, d.dudx, d.dvdx);
    along(dp_dy, d.dudy, d.dvdy);
    return d;
}

}  // namespace texr
