// Coverage: which pixel centres a screen triangle covers (docs/design.md, "Conventions": screen).
// Vertices are snapped to 1/256 pixel and the three edge functions
//   E(P) = (Xb - Xa) (Py - Ya) - (Yb - Ya) (Px - Xa) = A Px + B Py + C
// are evaluated exactly in 64-bit integers. Pixel (x, y) is sampled at its centre,
// P = (256 x + 128, 256 y + 128). Top-left fill rule: a centre exactly on an edge belongs to
// the triangle only if the edge is a top edge (horizontal, interior below it; y grows down)
// or a left edge (interior to its right). So two triangles sharing an edge never both cover
// a centre on it, and never both miss it.
#pragma once
#include <array>
#include <cstdint>

namespace texr {

constexpr int subpixel_bits = 8;
constexpr std::int64_t subpixel_scale = 1 << subpixel_bits;  // 256 steps per pixel

struct SnappedVertex {
    std::int64_t x, y;  // in 1/256 pixel
};

// Rounds a screen coordinate (pixels) to the nearest 1/256 pixel: half away from zero, like
// std::llround, without its library call. |pixels| stays within the guard band (2^15),
// far inside int64.
inline std::int64_t snap(double pixels) {
    const double t = pixels * double(subpixel_scale);
    return static_cast<std::int64_t>(t + (t >= 0.0 ? 0.5 : -0.5));
}

struct EdgeFunction {
    std::int64_t a, b, c;  // E = a X + b Y + c, positive inside
    std::int64_t bias;     // 0 on top-left edges, -1 elsewhere: inside iff E + bias >= 0
};

struct TriangleEdges {
    std::array<EdgeFunction, 3> edges;
    std::int64_t min_x, max_x, min_y, max_y;  // bounding box of the snapped vertices, in 1/256 pixel
};

// Builds the edge functions, oriented so the interior is positive whatever the winding.
// Returns false for a triangle of zero area (nothing to cover).
bool triangle_edges(const std::array<SnappedVertex, 3>& v, TriangleEdges& out);

// Twice the signed area in 1/256-pixel units (positive: counter-clockwise on screen
// with y pointing down, i.e. clockwise as seen).
std::int64_t twice_signed_area(const std::array<SnappedVertex, 3>& v);

struct Span {
    int x0, x1;  // covered pixels x0 <= x < x1 of one row
};

// The pixels of row y whose centres the triangle covers, clipped to [0, width).
Span span_for_row(const TriangleEdges& t, int y, int width);

// First and last row (inclusive) whose centres can be covered, clipped to [0, height):
// the rows whose centres lie within the bounding box. Empty (first > last) if there is none.
void row_range(const TriangleEdges& t, int height, int& first, int& last);
// The same for columns, clipped to [0, width).
void column_range(const TriangleEdges& t, int width, int& first, int& last);

}  // namespace texr
