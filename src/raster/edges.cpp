// Integer edge functions with the top-left fill rule (see the header).
#include "texr/raster/edges.h"

#include <algorithm>
#include <cmath>

namespace texr {

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
    out.min_x = std::min({v[0].x, v[1].x, v[2].x});
    out.max_x = std::max({v[0].x, v[1].x, v[2].x});
    out.min_y = std::min({v[0].y, v[1].y, v[2].y});
    out.max_y = std::max({v[0].y, v[1].y, v[2].y});
    return true;
}

namespace {

// The pixels k in [0, n) whose centres 256 k + 128 lie in [min, max] (in 1/256 pixel):
// k >= (min - 128) / 256 and k <= (max - 128) / 256. The divisions by 256 are shifts,
// flooring for negative values too (the ceiling as minus the floor of the negation).
void centres_within(std::int64_t min, std::int64_t max, int n, int& first, int& last) {
    const std::int64_t half = subpixel_scale / 2;
    first = int(std::max<std::int64_t>(0, -((half - min) >> subpixel_bits)));
    last = int(std::min<std::int64_t>(n - 1, (max - half) >> subpixel_bits));
}

}  // namespace

void row_range(const TriangleEdges& t, int height, int& first, int& last) { centres_within(t.min_y, t.max_y, height, first, last); }
void column_range(const TriangleEdges& t, int width, int& first, int& last) { centres_within(t.min_x, t.max_x, width, first, last); }

Span span_for_row(const TriangleEdges& t, int y, int width) {
    // Each edge is a linear inequality in the pixel index x along the row:
    //   E(256 x + 128, Py) + bias = (256 a) x + (128 a + b Py + c + bias) >= 0.
    const std::int64_t py = subpixel_scale * y + subpixel_scale / 2;
    std::int64_t slope[3], offset[3];
    for (int k = 0; k < 3; ++k) {
        const EdgeFunction& e = t.edges[std::size_t(k)];
        slope[k] = subpixel_scale * e.a;
        offset[k] = (subpixel_scale / 2) * e.a + e.b * py + e.c + e.bias;
    }
    // The pixels whose centres lie inside the bounding box.
    int first_column, last_column;
    column_range(t, width, first_column, last_column);
    std::int64_t lo = first_column, hi = last_column;
    if (lo > hi) return {0, 0};
    if (hi - lo < 16) {
        // A narrow triangle: test the few candidate centres directly (no divisions), without
        // a branch per centre: the three edge values are stepped along the row, and a centre
        // is inside when none is negative, i.e. when the sign bit of their OR is clear. The
        // covered centres of a row are contiguous, the triangle being convex, so the mask of
        // inside centres is one run of bits: its lowest and highest bits give the span. (Not
        // the run's length by popcount: x86-64's baseline has no such instruction, and the
        // library call it becomes cost more than the bit scan.)
        std::int64_t e0 = slope[0] * lo + offset[0], e1 = slope[1] * lo + offset[1], e2 = slope[2] * lo + offset[2];
        std::uint32_t inside = 0;
        for (int k = 0; k <= int(hi - lo); ++k) {
            inside |= std::uint32_t((e0 | e1 | e2) >= 0) << k;
            e0 += slope[0], e1 += slope[1], e2 += slope[2];
        }
        if (inside == 0) return {0, 0};
        return {int(lo) + __builtin_ctz(inside), int(lo) + 32 - __builtin_clz(inside)};
    }
    for (int k = 0; k < 3; ++k) {
        if (slope[k] > 0) lo = std::max(lo, ceil_div(-offset[k], slope[k]));
        else if (slope[k] < 0) hi = std::min(hi, floor_div(offset[k], -slope[k]));
        else if (offset[k] < 0) return {0, 0};  // parallel to the row and outside it
    }
    if (lo > hi) return {0, 0};
    return {int(lo), int(hi + 1)};
}

}  // namespace texr
