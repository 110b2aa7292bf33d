// A quantity that is linear in screen space: value(x, y) = dx * x + dy * y + c.
// u' = u/w, v' = v/w, q = 1/w and NDC depth are all such planes over a triangle.
#pragma once

namespace texr {

// No default values on purpose: triangle setup builds hundreds of thousands of planes per
// frame and fills only those a material needs; the others are never read. Write Plane{} for
// a zero plane.
struct Plane {
    double dx, dy, c;
    double at(double x, double y) const { return dx * x + dy * y + c; }
};

}  // namespace texr
