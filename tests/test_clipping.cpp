// Homogeneous clipping: triangles that cross the camera plane render what a ray caster sees,
// and nothing from behind the camera. Expected coverage and colours come from intersecting
// each pixel's viewing ray with the triangle in double precision.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>
#include <optional>

#include <glm/glm.hpp>

#include "helpers.h"
#include "texr/raster/clip.h"
#include "texr/render/renderer.h"

using namespace texr;

namespace {

constexpr int size = 64;
constexpr double near_distance = 0.1;

struct Hit {
    double depth;      // distance along -z
    glm::dvec3 color;  // barycentric interpolation of the vertex colours
};

// Ray through screen point (x, y) of a 90-degree square camera at the origin looking down -z.
std::optional<Hit> ray_cast(const std::array<Vertex, 3>& v, double x, double y) {
    const glm::dvec3 dir(2.0 * x / size - 1.0, 1.0 - 2.0 * y / size, -1.0);
    const glm::dvec3 p0(v[0].position), p1(v[1].position), p2(v[2].position);
    // Moller-Trumbore.
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, h = glm::cross(dir, e2);
    const double det = glm::dot(e1, h);
    if (std::fabs(det) < 1e-15) return std::nullopt;
    const glm::dvec3 s = -p0;
    const double b1 = glm::dot(s, h) / det;
    const glm::dvec3 qv = glm::cross(s, e1);
    const double b2 = glm::dot(dir, qv) / det;
    const double t = glm::dot(e2, qv) / det;
    if (b1 < 0 || b2 < 0 || b1 + b2 > 1 || t <= 0) return std::nullopt;
    const double depth = t;  // dir.z = -1, so t is the distance along -z
    if (depth < near_distance) return std::nullopt;
    return Hit{depth, (1 - b1 - b2) * glm::dvec3(v[0].color) + b1 * glm::dvec3(v[1].color) + b2 * glm::dvec3(v[2].color)};
}

// True when the ray-cast coverage changes within 0.02 pixel of (x, y): an edge is there.
bool near_an_edge(const std::array<Vertex, 3>& v, double x, double y) {
    const bool centre = ray_cast(v, x, y).has_value();
    for (double dx : {-0.02, 0.0, 0.02})
        for (double dy : {-0.02, 0.0, 0.02})
            if (ray_cast(v, x + dx, y + dy).has_value() != centre) return true;
    return false;
}

struct Comparison {
    int covered = 0, mismatched = 0;
    double worst_color = 0.0;  // worst error / allowed error
    bool all_finite = true;
};

Comparison render_and_compare(const std::array<Vertex, 3>& v) {
    Scene scene = testing::camera_scene(size, size, {0, 0, 0}, {0, 0, -1}, 90.0, near_distance, 100.0);
    Material m;
    m.vertex_colors = true;
    scene.materials.push_back(m);
    scene.background = Color(0.0f);
    testing::add_triangle(scene, v, 0);
    RenderStats stats;
    const Framebuffer fb = render(scene, {}, stats);
    Comparison c;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const Color got = fb.color[fb.index(x, y)];
            c.all_finite = c.all_finite && std::isfinite(got.x) && std::isfinite(got.y) && std::isfinite(got.z) &&
                           (std::isfinite(fb.depth[fb.index(x, y)]) || !fb.drawn(fb.index(x, y)));
            const bool drawn = fb.drawn(fb.index(x, y));
            const auto hit = ray_cast(v, x + 0.5, y + 0.5);
            if (near_an_edge(v, x + 0.5, y + 0.5)) continue;
            if (drawn != hit.has_value()) {
                ++c.mismatched;
                continue;
            }
            if (!drawn) continue;
            ++c.covered;
            // Vertices are snapped to 1/256 pixel, which shifts the image of the surface by
            // at most that much: the colour may differ by its screen gradient times 1/256 px
            // (doubled for slack), plus float rounding. The worst ratio must stay <= 1.
            const auto h1 = ray_cast(v, x + 0.75, y + 0.5), h2 = ray_cast(v, x + 0.25, y + 0.5);
            const auto h3 = ray_cast(v, x + 0.5, y + 0.75), h4 = ray_cast(v, x + 0.5, y + 0.25);
            if (!h1 || !h2 || !h3 || !h4) continue;
            const double gradient = glm::length(h1->color - h2->color) * 2 + glm::length(h3->color - h4->color) * 2;
            const double allowed = gradient * (2.0 / 256.0) + 1e-5;
            c.worst_color = std::max(c.worst_color, double(glm::length(glm::dvec3(got) - hit->color)) / allowed);
        }
    return c;
}

// Renders the triangle and checks it against the ray caster: finite everywhere, the same
// coverage away from edges, colours within the snapping allowance.
void check_matches_ray_caster(const std::array<Vertex, 3>& v, int at_least_covered) {
    const Comparison c = render_and_compare(v);
    CHECK(c.all_finite);
    CHECK(c.covered > at_least_covered);
    CHECK(c.mismatched == 0);
    MESSAGE("colour error / allowed: " << c.worst_color << " over " << c.covered << " pixels");
    CHECK(c.worst_color <= 1.0);
}

Vertex vertex(double x, double y, double z, Color color) {
    Vertex v;
    v.position = glm::vec3(float(x), float(y), float(z));
    v.color = color;
    return v;
}

}  // namespace

TEST_CASE("clipping: a triangle with a vertex behind the camera renders what a ray caster sees") {
    const std::array<Vertex, 3> v = {vertex(0, -1, 2, {1, 0, 0}), vertex(-3, -1, -5, {0, 1, 0}), vertex(3, -1, -5, {0, 0, 1})};
    check_matches_ray_caster(v, 500);
}

TEST_CASE("clipping: a vertex exactly on the camera plane (w = 0)") {
    const std::array<Vertex, 3> v = {vertex(0.5, -0.5, 0, {1, 1, 0}), vertex(-2, -1, -4, {0, 1, 1}), vertex(2, 1, -6, {1, 0, 1})};
    check_matches_ray_caster(v, 200);
}

TEST_CASE("clipping: a vertex at w = 1e-7, just in front of the camera plane") {
    const std::array<Vertex, 3> v = {vertex(0.3, -0.2, -1e-7, {1, 0, 0}), vertex(-2, -1.5, -3, {0, 1, 0}), vertex(2.5, -1, -3, {0, 0, 1})};
    check_matches_ray_caster(v, 200);
}

TEST_CASE("clipping: nothing from behind the camera is drawn") {
    // Entirely behind: it would project (with w < 0) onto the middle of the screen.
    const std::array<Vertex, 3> v = {vertex(-1, -1, 3, {1, 1, 1}), vertex(1, -1, 3, {1, 1, 1}), vertex(0, 1, 3, {1, 1, 1})};
    Scene scene = testing::camera_scene(size, size, {0, 0, 0}, {0, 0, -1}, 90.0, near_distance, 100.0);
    scene.materials.push_back(Material{});
    testing::add_triangle(scene, v, 0);
    RenderStats stats;
    const Framebuffer fb = render(scene, {}, stats);
    for (std::size_t i = 0; i < fb.depth.size(); ++i) REQUIRE_FALSE(fb.drawn(i));
    CHECK(stats.triangles_culled == 1);
    CHECK(stats.pixels_shaded == 0);
}

TEST_CASE("clipping: perspective-correct colours on a plane seen at a grazing angle") {
    const std::array<Vertex, 3> v = {vertex(-50, -0.3, -0.2, {1, 0, 0}), vertex(50, -0.3, -0.2, {0, 1, 0}), vertex(0, -0.3, -80, {0, 0, 1})};
    check_matches_ray_caster(v, 500);
}

TEST_CASE("clipping: a triangle's vertex codes decide inside and outside as clip_triangle does") {
    // clip_outcode bit k: outside plane k. The renderer works the codes out once per vertex and
    // decides a triangle from them: inside when they OR to 0, outside when they AND to non-zero.
    // Checked here against clip_triangle itself, on vertices inside, outside, exactly on a
    // plane (distance 0 is inside), and NaN or infinite.
    const GuardBand band{2.0, 3.0};
    const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<glm::dvec4> points = {
        {0.0, 0.0, 0.0, 1.0},  {1.9, -2.9, 0.5, 1.0}, {2.0, 3.0, 1.0, 1.0},   // inside; on left/top and far planes
        {-2.0, -3.0, -1.0, 1.0},                                                // on right, bottom, near
        {2.5, 0.0, 0.0, 1.0},  {-2.5, 0.0, 0.0, 1.0}, {0.0, 3.5, 0.0, 1.0}, {0.0, -3.5, 0.0, 1.0},
        {0.0, 0.0, 1.5, 1.0},  {0.0, 0.0, -1.5, 1.0}, {0.0, 0.0, 0.0, -1.0},  // beyond one plane; behind the camera
        {nan, 0.0, 0.0, 1.0},  {inf, 0.0, 0.0, 1.0},  {0.0, 0.0, 0.0, inf}};
    // Hand-worked codes (bits: near, far, left, right, bottom, top).
    CHECK(clip_outcode(points[0], band) == 0);
    CHECK(clip_outcode(points[2], band) == 0);  // on the right and top planes: inside
    CHECK(clip_outcode(points[3], band) == 0);  // on the left, bottom and near planes: inside
    CHECK(clip_outcode(points[4], band) == 1 << 3);
    CHECK(clip_outcode(points[5], band) == 1 << 2);
    CHECK(clip_outcode(points[6], band) == 1 << 5);
    CHECK(clip_outcode(points[7], band) == 1 << 4);
    CHECK(clip_outcode(points[8], band) == 1 << 1);
    CHECK(clip_outcode(points[9], band) == 1 << 0);
    CHECK(clip_outcode(points[11], band) == ((1 << 2) | (1 << 3)));  // x NaN: outside the planes that read x
    for (const glm::dvec4& a : points)
        for (const glm::dvec4& b : points)
            for (const glm::dvec4& c : points) {
                const int ca = clip_outcode(a, band), cb = clip_outcode(b, band), cc = clip_outcode(c, band);
                ClipPolygon polygon;
                const ClipResult result = clip_triangle(a, b, c, band, polygon);
                if ((ca | cb | cc) == 0) CHECK(result == ClipResult::inside);
                if ((ca & cb & cc) != 0) CHECK(result == ClipResult::outside);
                if (result == ClipResult::inside) CHECK((ca | cb | cc) == 0);
            }
}

TEST_CASE("clipping: a triangle that all six planes cut keeps all nine corners") {
    // Each plane cuts one corner off: 3 + 6 corners. Checked against a plain Sutherland-Hodgman
    // clipper written here (no cap, a growing list), with the planes in clip.h's order.
    const GuardBand band{2.0, 2.0};
    const glm::dvec4 a(17.897587133449939, -16.474835452139022, -8.9142050675619231, 0.96524198406639528);
    const glm::dvec4 b(-11.646200109650502, 16.330652337685834, 8.432153967676296, 2.551924578401664);
    const glm::dvec4 c(-7.9517706760949345, -18.283209768369343, -6.7733352958032285, 16.593275573596763);
    const auto distance = [&](int plane, const glm::dvec4& p) {
        const double d[6] = {p.z + p.w, p.w - p.z, band.x * p.w + p.x, band.x * p.w - p.x, band.y * p.w + p.y, band.y * p.w - p.y};
        return d[plane];
    };
    std::vector<glm::dvec4> reference = {a, b, c};
    for (int plane = 0; plane < 6; ++plane) {
        std::vector<glm::dvec4> kept;
        for (std::size_t i = 0; i < reference.size(); ++i) {
            const glm::dvec4 &p = reference[i], &q = reference[(i + 1) % reference.size()];
            const double dp = distance(plane, p), dq = distance(plane, q);
            if (dp >= 0.0) kept.push_back(p);
            if ((dp >= 0.0) != (dq >= 0.0)) kept.push_back(p + (dp / (dp - dq)) * (q - p));
        }
        reference = kept;
    }
    REQUIRE(reference.size() == 9);
    ClipPolygon polygon;
    REQUIRE(clip_triangle(a, b, c, band, polygon) == ClipResult::clipped);
    REQUIRE(polygon.count == 9);
    // The same corners in the same order (clip_triangle takes each crossing from the inside
    // end: the same point to rounding), and each corner's weights give its position back.
    for (int i = 0; i < 9; ++i) {
        const ClipVertex& v = polygon.vertices[std::size_t(i)];
        CAPTURE(i);
        for (int k = 0; k < 4; ++k) CHECK(v.position[k] == doctest::Approx(reference[std::size_t(i)][k]).epsilon(1e-9));
        const glm::dvec4 from_weights = v.weights.x * a + v.weights.y * b + v.weights.z * c;
        for (int k = 0; k < 4; ++k) CHECK(from_weights[k] == doctest::Approx(v.position[k]).epsilon(1e-9));
    }
}

TEST_CASE("clipping: one vertex beyond the near plane gives the quadrilateral worked out by hand, with its weights") {
    // a = (0, 0, 0, 1), b = (0.5, 0, 0, 1) inside; c = (0, 0.5, -3, 1) beyond the near plane
    // z + w >= 0. Edge b -> c meets z = -w at t = 1/3: (1/3, 1/6, -1, 1), weights (0, 2/3, 1/3);
    // edge c -> a at t = 2/3 from c: (0, 1/6, -1, 1), weights (2/3, 0, 1/3). (A single plane
    // cuts it: an odd number of passes, whose result must still reach the caller's polygon.)
    ClipPolygon polygon;
    const ClipResult r = clip_triangle(glm::dvec4(0, 0, 0, 1), glm::dvec4(0.5, 0, 0, 1), glm::dvec4(0, 0.5, -3, 1), guard_band_for(100, 100), polygon);
    REQUIRE(r == ClipResult::clipped);
    REQUIRE(polygon.count == 4);
    const std::pair<glm::dvec4, glm::dvec3> expected[4] = {{{0, 0, 0, 1}, {1, 0, 0}},
                                                           {{0.5, 0, 0, 1}, {0, 1, 0}},
                                                           {{1.0 / 3, 1.0 / 6, -1, 1}, {0, 2.0 / 3, 1.0 / 3}},
                                                           {{0, 1.0 / 6, -1, 1}, {2.0 / 3, 0, 1.0 / 3}}};
    for (const auto& e : expected) {
        int found = 0;
        for (int i = 0; i < polygon.count; ++i)
            found += glm::all(glm::lessThan(glm::abs(polygon.vertices[std::size_t(i)].position - e.first), glm::dvec4(1e-12))) &&
                     glm::all(glm::lessThan(glm::abs(polygon.vertices[std::size_t(i)].weights - e.second), glm::dvec3(1e-12)));
        CAPTURE(e.first.x);
        CAPTURE(e.first.y);
        CHECK(found == 1);
    }
}
