// Exact rescaling by a power of two, for quantities whose scale does not matter (directions,
// the inverse transpose of a transform): multiplying by 2^k changes no bit of the mantissa,
// so normalising afterwards gives the same bits as before for ordinary values, while squared
// lengths and determinants of values near 1e300 or 1e-300 no longer overflow or underflow.
#pragma once
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace texr {

// The k for which largest * 2^k lies in [1, 2); 0 for a largest of 0, infinity or NaN.
inline int unit_scale_exponent(double largest) {
    if (!(largest > 0.0) || !std::isfinite(largest)) return 0;
    int exponent = 0;
    std::frexp(largest, &exponent);  // largest = m 2^exponent, m in [1/2, 1)
    return 1 - exponent;
}

// d / |d|, as glm::normalize gives it, also where |d|^2 overflows or underflows a double (a
// point light 1e155 away, or 1e-160 from the surface point): such a d is first brought near
// 1 by a power of two. A zero, infinite or NaN d gives NaN, as glm::normalize does.
inline glm::dvec3 unit_direction(const glm::dvec3& d) {
    const double length2 = glm::dot(d, d);
    if (length2 > 0x1p-1000 && length2 < 0x1p1000) return glm::normalize(d);  // (the usual case: one compare more)
    const int k = unit_scale_exponent(std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)}));
    return glm::normalize(glm::dvec3(std::ldexp(d.x, k), std::ldexp(d.y, k), std::ldexp(d.z, k)));
}

}  // namespace texr
