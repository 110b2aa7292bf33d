// Projective textures (the lecture's "Projective Textures": "project texture onto object
// surfaces, slide projector; parallel or perspective projection"): a surface point P seen by
// a projector has its clip coordinates c = M (P, 1), and the projected image's
//   u = (c.x / c.w + 1) / 2,   v = (c.y / c.w + 1) / 2
// (v up, as texr's texture coordinates). Their screen derivatives follow by the quotient rule
// from P's (dP/dx, dP/dy), so the texture's filters get an exact footprint, as they do from
// a triangle's homography.
#pragma once
#include <glm/vec3.hpp>

#include "texr/raster/homography.h"
#include "texr/scene/scene.h"

namespace texr {

struct ProjectedUV {
    bool ahead = false;  // P is in front of the projector ((P - eye) . forward > 0); behind it, nothing is thrown
    double u = 0.0, v = 0.0;
    UVDerivatives d{0.0, 0.0, 0.0, 0.0};
};

ProjectedUV project(const Projector& p, const glm::dvec3& point, const glm::dvec3& dp_dx, const glm::dvec3& dp_dy);

}  // namespace texr
