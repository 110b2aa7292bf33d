// Integer edge functions with the top-left fill rule (see the header).
#include "texr/raster/edges.h"

#include <algorithm>
#include <cmath>

namespace texr {

std::int64_t snap(double pixels) {
    // Round half away from zero, like std::llround, without its library call. |pixels| stays
    // within the guard band (2^15), far inside int64.
    const double t = pixels * double(subpixel_scale);
    return static_cast<std::int64_t>(t + (t >= 0.0 ? 0.5 : -0.5));
}

std::int64_t twice_signed_area(const std::array<SnappedVertex, 3>& v) {
    return (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
}

namespace {

// Floor and ceiling of n / d for d > 0, exact for negative n.
std::int64_t floor_div(std::int64_t n, std::int64_t d) {
    std::int64_t q = n / d;
    if ((n % d != 0) && (n < 0)) --q;
    return q;
}
std::int64_t ceil_div(std::int64_t n, std::int64_t d) { return -floor_div(-n, d); }

}  // namespace

bool triangle_edges(const std::array<SnappedVertex, 3>& v, TriangleEdges& out) {
    const std::int64_t area = twice_signed_area(v);
    if (area == 0) return false;
    const std::int64_t sign = area > 0 ? 1 : -1;
    for (int i = 0; i < 3; ++i) {
        const SnappedVertex& p = v[i];
        const SnappedVertex& q = v[(i + 1) % 3];
        EdgeFunction e;
        e.a = sign * (p.y - q.y);
        e.b = sign * (q.x - p.x);
        e.c = -(e.a * p.x + e.b * p.y);
        // Left edge: interior at larger x (a > 0). Top edge: horizontal, interior below (b > 0).
        const bool top_left = e.a > 0 || (e.a == 0 && e.b > 0);
        e.bias = top_left ? 0 : -1;
        out.edges[i] = e;
    }
    out.min_y = std::min({v[0].y, v[1].y, v[2].y});
    out.max_y = std::max({v[0].y, v[1].y, v[2].y});
    return true;
}

void row_range(const TriangleEdges& t, int height, int& first, int& last) {
    // Row y's centre is 256 y + 128; it can be covered only within [min_y, max_y].
    const std::int64_t half = subpixel_scale / 2;
    first = int(std::max<std::int64_t>(0, ceil_div(t.min_y - half, subpixel_scale)));
    last = int(std::min<std::int64_t>(height - 1, floor_div(t.max_y - half, subpixel_scale)));
}

Span span_for_row(const TriangleEdges& t, int y, int width) {
    // Each edge is a linear inequality in the pixel index x along the row:
    //   E(256 x + 128, Py) + bias = (256 a) x + (128 a + b Py + c + bias) >= 0.
    const std::int64_t py = subpixel_scale * y + subpixel_scale / 2;
    std::int64_t lo = 0, hi = std::int64_t(width) - 1;
    for (const EdgeFunction& e : t.edges) {
        const std::int64_t slope = subpixel_scale * e.a;
        const std::int64_t offset = (subpixel_scale / 2) * e.a + e.b * py + e.c + e.bias;
        if (slope > 0) lo = std::max(lo, ceil_div(-offset, slope));
        else if (slope < 0) hi = std::min(hi, floor_div(offset, -slope));
        else if (offset < 0) return {0, 0};  // parallel to the row and outside it
    }
    if (lo > hi) return {0, 0};
    return {int(lo), int(hi + 1)};
}

}  // namespace texr
