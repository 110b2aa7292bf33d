// The lecture's "incremental bilinear update of (u', v', q) in screen space": along a span a
// plane's value changes by the same constant d/dx from one pixel centre to the next.
// A span starts from the plane equation evaluated at its first pixel centre (never from a
// value carried over from the previous row), so the error of the additions is bounded by
// the span length alone: after k steps, at most about k * 2^-53 * (|value| + k |d/dx|).
#pragma once
#include "texr/raster/plane.h"

namespace texr {

struct SteppedPlane {
    double value = 0.0, step = 0.0;

    // Start at the centre of pixel (x0, y): the "prestep" from the plane's origin to
    // (x0 + 1/2, y + 1/2), where the span's first sample lies.
    static SteppedPlane start(const Plane& p, int x0, int y) { return {p.at(x0 + 0.5, y + 0.5), p.dx}; }
    void advance() { value += step; }
};

}  // namespace texr
