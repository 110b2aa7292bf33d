// Environment maps, as the lecture's "Environment Map" slides give the latitude-longitude
// map: "Cartesian coords of ray dir. -> spherical coords -> uv tex coords". A direction d
// (world space, y up) has longitude atan2(d.x, -d.z) and latitude asin(d.y / |d|), and
//   u = 1/2 + longitude / 2 pi,   v = 1/2 + latitude / pi,
// so the image's middle column looks along -z (texr's default view), u grows towards +x, its
// top row (v = 1) is straight up and its bottom row (v = 0) straight down. The background
// of a frame is the map seen along each pixel's ray; a material that reflects it reads the
// map along the reflected view ray, R = V - 2 (N . V) N ("Reflection Map Rendering").
#pragma once
#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "texr/scene/scene.h"

namespace texr {

// (u, v) of direction d on the latitude-longitude map; (0.5, 0.5) for a zero or non-finite d.
glm::dvec2 latlong_uv(const glm::dvec3& d);

// V reflected about the unit normal n: V - 2 (n . V) n.
glm::dvec3 reflect_direction(const glm::dvec3& v, const glm::dvec3& n);

// The map's value along direction d: the texture's filter at (u, v) with no footprint (its
// base level), or a procedural texture at (u, v, 0), or, if it is solid, at d / |d| itself.
// `texels` grows by those read.
Color4 environment_value(const Texture& t, const glm::dvec3& d, std::uint64_t& texels);

// The direction of the ray through the centre of pixel (x, y) (row 0 at the top) of a
// width x height frame seen by `camera` (the renderer's perspective; not normalised).
glm::dvec3 pixel_ray(const Camera& camera, int width, int height, int x, int y);

}  // namespace texr
