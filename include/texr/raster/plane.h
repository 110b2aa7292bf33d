// A quantity that is linear in screen space: value(x, y) = dx * x + dy * y + c.
// u' = u/w, v' = v/w, q = 1/w and NDC depth are all such planes over a triangle.
#pragma once

namespace texr {

struct Plane {
    double dx = 0.0, dy = 0.0, c = 0.0;
    double at(double x, double y) const { return dx * x + dy * y + c; }
};

}  // namespace texr
