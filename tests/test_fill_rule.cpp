// Coverage with the top-left rule: shared edges are covered exactly once. Coverage is
// counted per pixel (not read back from colours), and the expected inside/outside of each
// pixel centre is decided by exact integer cross products against the outline.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include <glm/vec2.hpp>

#include "texr/raster/edges.h"

using namespace texr;

namespace {

struct Coverage {
    int width, height;
    std::vector<int> count;
    Coverage(int w, int h) : width(w), height(h), count(std::size_t(w) * std::size_t(h), 0) {}

    void add(const std::array<SnappedVertex, 3>& v) {
        TriangleEdges edges;
        if (!triangle_edges(v, edges)) return;
        int first = 0, last = -1;
        row_range(edges, height, first, last);
        for (int y = first; y <= last; ++y) {
            const Span s = span_for_row(edges, y, width);
            for (int x = s.x0; x < s.x1; ++x) ++count[std::size_t(y) * std::size_t(width) + std::size_t(x)];
        }
    }
    int at(int x, int y) const { return count[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
};

SnappedVertex at_pixels(double x, double y) { return {snap(x), snap(y)}; }

// Sign of the cross product (b - a) x (p - a), exact in 64-bit integers.
std::int64_t side(const SnappedVertex& a, const SnappedVertex& b, std::int64_t px, std::int64_t py) {
    return (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
}

// For a convex outline (any winding): +1 strictly inside, 0 on the boundary, -1 outside.
int classify(const std::vector<SnappedVertex>& outline, int x, int y) {
    const std::int64_t px = 256 * std::int64_t(x) + 128, py = 256 * std::int64_t(y) + 128;
    bool any_positive = false, any_negative = false, any_zero = false;
    for (std::size_t i = 0; i < outline.size(); ++i) {
        const std::int64_t s = side(outline[i], outline[(i + 1) % outline.size()], px, py);
        any_positive |= s > 0;
        any_negative |= s < 0;
        any_zero |= s == 0;
    }
    if (any_positive && any_negative) return -1;
    return any_zero ? 0 : 1;
}

void check_fan(const glm::dvec2& centre, double radius, int triangles, int width, int height) {
    std::vector<SnappedVertex> rim;
    for (int i = 0; i < triangles; ++i) {
        const double a = 2.0 * M_PI * i / triangles;
        rim.push_back(at_pixels(centre.x + radius * std::cos(a), centre.y + radius * std::sin(a)));
    }
    Coverage cover(width, height);
    const SnappedVertex c = at_pixels(centre.x, centre.y);
    for (int i = 0; i < triangles; ++i) cover.add({c, rim[std::size_t(i)], rim[std::size_t((i + 1) % triangles)]});
    int inside = 0, boundary_covered = 0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const int where = classify(rim, x, y);
            const int n = cover.at(x, y);
            REQUIRE(n <= 1);  // never twice, anywhere
            if (where > 0) {
                REQUIRE(n == 1);
                ++inside;
            } else if (where < 0) {
                REQUIRE(n == 0);
            } else {
                boundary_covered += n;
            }
        }
    CHECK(inside > 3000);
    (void)boundary_covered;
}

}  // namespace

TEST_CASE("a fan of 1000 triangles around one point covers every inside pixel exactly once") {
    SUBCASE("centre between pixel centres") { check_fan({50.3, 47.7}, 40.0, 1000, 100, 100); }
    SUBCASE("centre exactly on a pixel centre: the shared vertex is covered once") {
        check_fan({50.5, 50.5}, 40.0, 1000, 100, 100);
        Coverage cover(100, 100);
        const SnappedVertex c = at_pixels(50.5, 50.5);
        for (int i = 0; i < 1000; ++i) {
            const double a0 = 2.0 * M_PI * i / 1000, a1 = 2.0 * M_PI * (i + 1) / 1000;
            cover.add({c, at_pixels(50.5 + 40 * std::cos(a0), 50.5 + 40 * std::sin(a0)),
                       at_pixels(50.5 + 40 * std::cos(a1), 50.5 + 40 * std::sin(a1))});
        }
        CHECK(cover.at(50, 50) == 1);
    }
    SUBCASE("opposite winding") {
        // The same fan built clockwise: coverage must not depend on winding.
        std::vector<SnappedVertex> rim;
        for (int i = 0; i < 1000; ++i) {
            const double a = -2.0 * M_PI * i / 1000;
            rim.push_back(at_pixels(60.5 + 35 * std::cos(a), 40.5 + 35 * std::sin(a)));
        }
        Coverage cover(120, 90);
        for (int i = 0; i < 1000; ++i) cover.add({at_pixels(60.5, 40.5), rim[std::size_t(i)], rim[std::size_t((i + 1) % 1000)]});
        for (int y = 0; y < 90; ++y)
            for (int x = 0; x < 120; ++x) {
                REQUIRE(cover.at(x, y) <= 1);
                if (classify(rim, x, y) > 0) REQUIRE(cover.at(x, y) == 1);
            }
        CHECK(cover.at(60, 40) == 1);
    }
}

TEST_CASE("a grid of quads split into triangles covers every inside pixel exactly once") {
    const int cells = 12, width = 110, height = 100;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> jitter(-2.0, 2.0);
    for (int variant = 0; variant < 3; ++variant) {
        // variant 0: grid lines exactly through pixel centres; 1: jittered interior vertices;
        // 2: vertices on pixel centres and on 1/256 sub-pixel positions near them.
        std::vector<std::vector<SnappedVertex>> grid(cells + 1, std::vector<SnappedVertex>(cells + 1));
        for (int j = 0; j <= cells; ++j)
            for (int i = 0; i <= cells; ++i) {
                double x = 5.5 + 8.0 * i, y = 3.5 + 7.0 * j;
                const bool interior = i > 0 && j > 0 && i < cells && j < cells;
                if (variant == 1 && interior) x += jitter(rng), y += jitter(rng);
                if (variant == 2 && interior) x += ((i + j) % 3 - 1) / 256.0, y += ((i * j) % 3 - 1) / 256.0;
                grid[std::size_t(j)][std::size_t(i)] = at_pixels(x, y);
            }
        Coverage cover(width, height);
        for (int j = 0; j < cells; ++j)
            for (int i = 0; i < cells; ++i) {
                const auto a = grid[std::size_t(j)][std::size_t(i)], b = grid[std::size_t(j)][std::size_t(i + 1)];
                const auto c = grid[std::size_t(j + 1)][std::size_t(i + 1)], d = grid[std::size_t(j + 1)][std::size_t(i)];
                if ((i + j) % 2) cover.add({a, b, c}), cover.add({a, c, d});  // both diagonals
                else cover.add({a, b, d}), cover.add({b, c, d});
            }
        const std::vector<SnappedVertex> outline = {grid[0][0], grid[0][cells], grid[cells][cells], grid[cells][0]};
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const int where = classify(outline, x, y);
                REQUIRE(cover.at(x, y) <= 1);
                if (where > 0) REQUIRE(cover.at(x, y) == 1);
                if (where < 0) REQUIRE(cover.at(x, y) == 0);
            }
    }
}

TEST_CASE("top-left rule: a centre on a top or left edge is covered, on a bottom or right edge is not") {
    // Axis-aligned square from (2.5, 2.5) to (5.5, 5.5) as two triangles: its top and left
    // edges pass through the centres of row 2 and column 2, its right and bottom edges
    // through those of column 5 and row 5. Covered: columns 2..4, rows 2..4.
    Coverage cover(8, 8);
    const auto a = at_pixels(2.5, 2.5), b = at_pixels(5.5, 2.5), c = at_pixels(5.5, 5.5), d = at_pixels(2.5, 5.5);
    cover.add({a, b, c});
    cover.add({a, c, d});
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) CHECK(cover.at(x, y) == ((x >= 2 && x <= 4 && y >= 2 && y <= 4) ? 1 : 0));
}

TEST_CASE("zero-area triangles cover nothing") {
    TriangleEdges edges;
    CHECK_FALSE(triangle_edges({at_pixels(1, 1), at_pixels(5, 5), at_pixels(9, 9)}, edges));
    CHECK_FALSE(triangle_edges({at_pixels(3, 3), at_pixels(3, 3), at_pixels(3, 3)}, edges));
}

TEST_CASE("row_range and column_range hold exactly the pixel centres inside the bounding box") {
    // Brute force: centre k (at 256 k + 128) is in the range iff min <= 256 k + 128 <= max,
    // for boxes with corners anywhere from well off screen to past the far edge, on and off
    // the centres.
    std::mt19937 rng(11);
    std::uniform_int_distribution<std::int64_t> coordinate(-4 * 256, 24 * 256);
    const int width = 16, height = 12;
    for (int trial = 0; trial < 20000; ++trial) {
        TriangleEdges t{};
        t.min_x = coordinate(rng), t.min_y = coordinate(rng);
        t.max_x = t.min_x + coordinate(rng) % 700 + 700, t.max_y = t.min_y + coordinate(rng) % 700 + 700;
        if (trial % 3 == 0) t.max_x = t.min_x + trial % 300, t.max_y = t.min_y + trial % 257;  // boxes under a pixel
        int rows[2], columns[2];
        row_range(t, height, rows[0], rows[1]);
        column_range(t, width, columns[0], columns[1]);
        for (int y = 0; y < height; ++y) {
            const bool inside = t.min_y <= 256 * y + 128 && 256 * y + 128 <= t.max_y;
            REQUIRE((y >= rows[0] && y <= rows[1]) == inside);
        }
        for (int x = 0; x < width; ++x) {
            const bool inside = t.min_x <= 256 * x + 128 && 256 * x + 128 <= t.max_x;
            REQUIRE((x >= columns[0] && x <= columns[1]) == inside);
        }
    }
}

TEST_CASE("tiny triangles around a pixel centre cover it exactly as the top-left rule says") {
    // Every triangle whose corners lie on the 7 x 7 subpixel grid around the centre of pixel
    // (0, 0) (128, 128 in 1/256 pixel): the centre is covered when it is strictly inside,
    // or on an edge that is a top edge (horizontal, the rest of the triangle below it) or a
    // left edge (the triangle to its right), and only by those edges where it lies on several
    // (a corner). Worked out here on the triangle turned clockwise on screen (y down), where
    // inside is (b - a) x (p - a) > 0 for every edge a -> b, a top edge runs along +x and a
    // left edge runs up (-y). Triangles of area 1/2 or 1 subpixel^2 are among them, where the
    // edge functions' top-left biases decide alone.
    int covered = 0, checked = 0, wrong = 0;
    for (int a = 0; a < 49; ++a)
        for (int b = 0; b < 49; ++b)
            for (int c = 0; c < 49; ++c) {
                std::array<SnappedVertex, 3> v = {SnappedVertex{125 + a % 7, 125 + a / 7}, SnappedVertex{125 + b % 7, 125 + b / 7},
                                                  SnappedVertex{125 + c % 7, 125 + c / 7}};
                std::array<SnappedVertex, 3> cw = v;
                const std::int64_t area = side(v[0], v[1], v[2].x, v[2].y);
                if (area == 0) continue;
                if (area < 0) std::swap(cw[1], cw[2]);
                bool inside = true;
                for (int e = 0; e < 3; ++e) {
                    const SnappedVertex& p = cw[std::size_t(e)];
                    const SnappedVertex& q = cw[std::size_t((e + 1) % 3)];
                    const std::int64_t s = side(p, q, 128, 128);
                    const bool top = p.y == q.y && q.x > p.x, left = q.y < p.y;
                    inside = inside && (s > 0 || (s == 0 && (top || left)));
                }
                TriangleEdges edges;
                REQUIRE(triangle_edges(v, edges));
                int first = 0, last = -1;
                row_range(edges, 4, first, last);
                bool drawn = false;
                if (first <= 0 && last >= 0) {
                    const Span s = span_for_row(edges, 0, 4);
                    drawn = s.x0 <= 0 && 0 < s.x1;
                }
                wrong += drawn != inside;
                covered += inside;
                ++checked;
            }
    CHECK(wrong == 0);
    CHECK(covered > checked / 20);
    MESSAGE(checked << " triangles, " << covered << " cover the centre");
}
