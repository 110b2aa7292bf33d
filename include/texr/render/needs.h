// "Skip what a scene doesn't need" (docs/design.md): the set of per-pixel quantities a draw's
// material really uses. The span loop is compiled once per set (a template parameter), so
// a flat-coloured material interpolates nothing but depth, and a nearest-sampled texture
// pays for no derivatives, normals or world positions.
#pragma once
#include <string>

#include "texr/scene/scene.h"

namespace texr {

enum Need : unsigned {
    need_uv = 1u << 0,              // u = u'/q, v = v'/q
    need_uv_derivatives = 1u << 1,  // exact du/dx ... for filters with a footprint
    need_normal = 1u << 2,          // interpolated normal (lighting)
    need_color = 1u << 3,           // interpolated vertex colour
    need_world_position = 1u << 4,  // interpolated world position (point lights)
};
constexpr unsigned need_all = (1u << 5) - 1;
using Needs = unsigned;

Needs needs_of(const Material& material, const Scene& scene);

// "uv, normal; skips uv derivatives, vertex colour, world position", for --stats.
std::string describe(Needs needs);

}  // namespace texr
