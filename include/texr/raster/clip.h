// Homogeneous clipping, before the perspective divide (so nothing behind the camera can wrap
// around through w < 0). Planes, each "inside" when its distance is >= 0:
//   near  z + w >= 0        far   w - z >= 0
//   guard band  g_x * w -+ x >= 0,  g_y * w -+ y >= 0
// The guard band (g >= 1) is wider than the screen: triangles that only poke out of the
// viewport are not cut (the rasterizer clips those spans for free) but screen coordinates
// stay within +-2^15 pixels, so the 1/256-pixel integer edge functions never overflow.
// A clipped vertex records its weights on the original three vertices: every attribute is
// then interpolated from them, linearly in clip space, which is linear on the surface.
#pragma once
#include <array>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace texr {

struct ClipVertex {
    glm::dvec4 position;  // clip space
    glm::dvec3 weights;   // on the original triangle's vertices 0, 1, 2
};

struct ClipPolygon {
    static constexpr int max_vertices = 9;  // 3 + one per clipping plane
    std::array<ClipVertex, max_vertices> vertices;
    int count = 0;
};

struct GuardBand {
    double x = 1.0, y = 1.0;  // NDC limits; >= 1
};

// A guard band keeping screen coordinates within +-2^15 pixels of any viewport up to 16384.
GuardBand guard_band_for(int width, int height);

enum class ClipResult { inside, clipped, outside };

// Bit k set: p is outside clipping plane k (near, far, left, right, bottom, top), NaN
// included. A triangle is inside when its vertices' codes OR to 0 and outside when they AND
// to non-zero: what clip_triangle decides first, so a mesh can work the codes out once per
// vertex instead of once per triangle corner.
int clip_outcode(const glm::dvec4& p, const GuardBand& band);

// Clips triangle (a, b, c) against the six planes. `inside`: polygon is the triangle itself;
// `clipped`: polygon holds the clipped convex polygon (3..9 vertices); `outside`: nothing left.
ClipResult clip_triangle(const glm::dvec4& a, const glm::dvec4& b, const glm::dvec4& c,
                         const GuardBand& band, ClipPolygon& polygon);

}  // namespace texr
