// Environment maps (see include/texr/texture/environment.h).
#include "texr/texture/environment.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "texr/texture/lookup.h"
#include "texr/texture/procedural.h"

namespace texr {

namespace {
constexpr double pi = 3.14159265358979323846;
}

glm::dvec2 latlong_uv(const glm::dvec3& d) {
    const double length = glm::length(d);
    if (!(length > 0.0) || !std::isfinite(length)) return {0.5, 0.5};
    const double longitude = std::atan2(d.x, -d.z + 0.0);  // (+ 0.0: straight up or down, -0 would give u = 1)
    const double latitude = std::asin(std::clamp(d.y / length, -1.0, 1.0));
    return {0.5 + longitude / (2.0 * pi), 0.5 + latitude / pi};
}

glm::dvec3 reflect_direction(const glm::dvec3& v, const glm::dvec3& n) { return v - 2.0 * glm::dot(n, v) * n; }

Color4 environment_value(const Texture& t, const glm::dvec3& d, std::uint64_t& texels) {
    const glm::dvec2 uv = latlong_uv(d);
    if (t.procedural) {
        const double length = glm::length(d);
        const glm::dvec3 unit = length > 0.0 && std::isfinite(length) ? d / length : glm::dvec3(0.0, 0.0, -1.0);
        return procedural_value(*t.procedural, t.procedural->solid ? unit : glm::dvec3(uv, 0.0), 0.0);
    }
    return lookup(t, uv.x, uv.y, UVDerivatives{0.0, 0.0, 0.0, 0.0}, texels);
}

glm::dvec3 pixel_ray(const Camera& camera, int width, int height, int x, int y) {
    // The pixel centre in normalised device coordinates (y up), then through the camera's basis
    // (glm::lookAtRH's: forward f, right r = f x up, up' = r x f) at the vertical field of view.
    const double ndc_x = 2.0 * (x + 0.5) / width - 1.0, ndc_y = 1.0 - 2.0 * (y + 0.5) / height;
    const double t = std::tan(camera.fov_y_degrees * pi / 360.0), aspect = double(width) / double(height);
    const glm::dvec3 f = glm::normalize(camera.target - camera.eye);
    const glm::dvec3 r = glm::normalize(glm::cross(f, camera.up));
    const glm::dvec3 u = glm::cross(r, f);
    return f + (ndc_x * t * aspect) * r + (ndc_y * t) * u;
}

}  // namespace texr
