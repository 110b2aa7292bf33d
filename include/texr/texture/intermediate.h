// Intermediate (two-stage) mapping, as the lecture's "Intermediate Mapping" slides give it:
// the surface point is expressed in the intermediate surface's frame (a translation to its
// centre and a rotation to its axes: x', y', z' with z' along its axis), one coordinate is
// dropped and (u, v) come from the other two:
//   planar       u = x' / S,            v = y' / S               (drop z')
//   cylindrical  u = phi / 2 pi,        v = z' / H               (drop r; phi = atan2(y', x'))
//   spherical    u = phi / 2 pi,        v = 1 - theta / pi       (drop r; theta from +z')
// with phi in [0, 2 pi). (The slide's v = theta / pi counts from an image's top row; texr's
// v runs up from its bottom row, so the image's top is at the +z' pole, unmirrored.) texr evaluates it at every pixel's world position (the
// O-mapping of the slides is the surface point's own position), so a triangle that spans
// the seam phi = 0 gets no backwards smear across the texture, as interpolating per-vertex
// (u, v) would give it. The screen derivatives come from the world position's by central
// differences of the mapping (u's difference taken modulo 1 across the seam).
#pragma once
#include <glm/vec3.hpp>

#include "texr/raster/homography.h"

namespace texr {

enum class Intermediate { none, planar, cylindrical, spherical };

struct IntermediateMapping {
    Intermediate kind = Intermediate::none;
    glm::dvec3 center{0.0};
    glm::dvec3 axis{0.0, 0.0, 1.0};       // z' (unit)
    glm::dvec3 reference{1.0, 0.0, 0.0};  // x' (unit, square to the axis); y' = z' x x'
    double size = 1.0;                    // planar: S; cylindrical: H
};

// (u, v) of point p; and with d(p)/dx, d(p)/dy, their screen derivatives.
glm::dvec2 intermediate_uv(const IntermediateMapping& m, const glm::dvec3& p);
UVDerivatives intermediate_derivatives(const IntermediateMapping& m, const glm::dvec3& p, const glm::dvec3& dp_dx,
                                       const glm::dvec3& dp_dy);

}  // namespace texr
