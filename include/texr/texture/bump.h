// Bump mapping, as the lecture's "Bump Mapping" slides derive it. The surface O(u, v) is
// virtually displaced along its unit normal N by the bump map B(u, v):
//   O'(u, v) = O(u, v) + B(u, v) N(u, v),
// and shaded with the normal of the displaced surface, O'_u x O'_v. For small B the terms
// B N_u and B N_v are dropped, and with N x N = 0
//   O'_u x O'_v = O_u x O_v + B_u (N x O_v) - B_v (N x O_u) = O_u x O_v + D.
// The slides write N' = N + D, for a parameterization whose O_u x O_v is the unit normal.
// texr keeps the factor: O_u x O_v = s A N (A its length, s = +1 or -1 as (u, v) turn with
// or against the normal), so N' = N + s D / A, the same direction as O'_u x O'_v, on N's side.
// Only the shading changes: no self-shadowing, and the outline stays (the slide's words).
#pragma once
#include <cstdint>

#include <glm/vec3.hpp>

#include "texr/scene/scene.h"

namespace texr {

// The height B(u, v) = height x the texture's first channel at (u, v) (its reconstruction
// filter at the base level; a procedural texture's value). `texels` grows by those read.
double bump_height_at(const Texture& t, double height, double u, double v, std::uint64_t& texels);

// B_u and B_v by central differences, (B(u + h, v) - B(u - h, v)) / 2h and likewise in v,
// over one texel of the base level (a procedural texture: 1/256 of its pattern's cell) or
// the pixel's footprint in (u, v) (the longer derivative vector), whichever is wider: a
// step-shaped height (bricks) then gives a slope a pixel wide, not a spike a few texels wide
// that pixels far off would step over.
struct BumpSlope {
    double b_u = 0.0, b_v = 0.0;
    double step_u = 0.0, step_v = 0.0;  // h in u and in v
};
BumpSlope bump_slope(const Texture& t, double height, double u, double v, double footprint, std::uint64_t& texels);

// The tangents O_u and O_v of a flat triangle, from its corners' positions p and texture
// coordinates (u, v): the solution of p1 - p0 = O_u du1 + O_v dv1, p2 - p0 = O_u du2 + O_v dv2.
// Zero vectors where the UVs are degenerate (collinear), which leaves the normal as it is.
struct SurfaceTangents {
    glm::dvec3 o_u{0.0}, o_v{0.0};
};
SurfaceTangents surface_tangents(const glm::dvec3 p[3], const double u[3], const double v[3]);

// N' = N + s D / A for the unit normal n (above); n itself where O_u x O_v is 0 or not finite.
glm::dvec3 bumped_normal(const glm::dvec3& n, const SurfaceTangents& t, const BumpSlope& slope);

}  // namespace texr
