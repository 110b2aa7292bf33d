// The triangle parameterization: M^-1 = U diag(1/w) adj(S), checked against a forward M
// built the other way round, against the vertices' own UVs, and against an exact ray/plane
// intersection in double precision.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <glm/glm.hpp>

#include "texr/raster/homography.h"
#include "texr/raster/span_walk.h"

using namespace texr;

namespace {

// A triangle in camera space (camera at the origin looking down -z), seen by a pinhole
// with focal length f pixels and principal point (cx, cy); screen y grows downwards.
struct CameraTriangle {
    std::array<glm::dvec3, 3> p;
    std::array<glm::dvec2, 3> uv;
    double f = 800.0, cx = 512.0, cy = 384.0;

    glm::dvec2 project(const glm::dvec3& q) const { return {cx + f * q.x / -q.z, cy - f * q.y / -q.z}; }
    std::array<glm::dvec2, 3> screen() const { return {project(p[0]), project(p[1]), project(p[2])}; }
    std::array<double, 3> inv_w() const { return {1.0 / -p[0].z, 1.0 / -p[1].z, 1.0 / -p[2].z}; }

    // Exact (u, v) seen through pixel position (x, y): intersect the viewing ray with the
    // triangle's plane and interpolate the UVs with 3D barycentric coordinates.
    glm::dvec2 ray_cast_uv(double x, double y) const {
        const glm::dvec3 dir((x - cx) / f, -(y - cy) / f, -1.0);
        const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
        const double t = glm::dot(n, p[0]) / glm::dot(n, dir);
        const glm::dvec3 hit = t * dir;
        const double area = glm::dot(n, n);
        const double l0 = glm::dot(glm::cross(p[1] - hit, p[2] - hit), n) / area;
        const double l1 = glm::dot(glm::cross(p[2] - hit, p[0] - hit), n) / area;
        const double l2 = 1.0 - l0 - l1;
        return l0 * uv[0] + l1 * uv[1] + l2 * uv[2];
    }
};

CameraTriangle random_triangle(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> depth(0.5, 50.0), lateral(-0.6, 0.6), tex(-2.0, 3.0);
    CameraTriangle t;
    for (;;) {
        for (int i = 0; i < 3; ++i) {
            const double z = -depth(rng);
            t.p[i] = {lateral(rng) * -z, lateral(rng) * -z, z};
            t.uv[i] = {tex(rng), tex(rng)};
        }
        const auto s = t.screen();
        const double screen_area = std::fabs((s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y));
        const double uv_area = std::fabs((t.uv[1].x - t.uv[0].x) * (t.uv[2].y - t.uv[0].y) -
                                         (t.uv[2].x - t.uv[0].x) * (t.uv[1].y - t.uv[0].y));
        if (screen_area > 100.0 && uv_area > 0.05) return t;
    }
}

glm::dmat3 columns(const std::array<glm::dvec2, 3>& xy) {
    return glm::dmat3(glm::dvec3(xy[0], 1.0), glm::dvec3(xy[1], 1.0), glm::dvec3(xy[2], 1.0));
}

}  // namespace

TEST_CASE("M^-1 times an independently built forward M is a multiple of the identity") {
    std::mt19937_64 rng(1);
    for (int trial = 0; trial < 200; ++trial) {
        const CameraTriangle t = random_triangle(rng);
        const auto screen = t.screen();
        const auto inv_w = t.inv_w();
        // Forward map from its definition: M (u_i, v_i, 1) = w_i (x_i, y_i, 1), so
        // M = S diag(w) U^-1, with S and U holding the vertices as columns.
        const glm::dmat3 w_diag(glm::dvec3(1 / inv_w[0], 0, 0), glm::dvec3(0, 1 / inv_w[1], 0), glm::dvec3(0, 0, 1 / inv_w[2]));
        const glm::dmat3 forward = columns(screen) * w_diag * glm::inverse(columns(t.uv));
        const TextureHomography h = texture_homography(screen, inv_w, t.uv);
        const glm::dmat3 product = h.inverse() * forward;
        const double k = product[0][0];
        REQUIRE(std::fabs(k) > 0.0);
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) CHECK(product[c][r] / k == doctest::Approx(c == r ? 1.0 : 0.0).epsilon(1e-9));
        // And the forward map texr computes agrees with it up to scale.
        const auto texr_forward = h.forward();
        REQUIRE(texr_forward.has_value());
        const double s = (*texr_forward)[2][2] / forward[2][2];
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r)
                CHECK((*texr_forward)[c][r] == doctest::Approx(s * forward[c][r]).epsilon(1e-7).scale(std::fabs(s) * 1e3));
    }
}

TEST_CASE("at each vertex (u, v) equals that vertex's UV") {
    std::mt19937_64 rng(2);
    for (int trial = 0; trial < 200; ++trial) {
        const CameraTriangle t = random_triangle(rng);
        const auto screen = t.screen();
        const TextureHomography h = texture_homography(screen, t.inv_w(), t.uv);
        for (int i = 0; i < 3; ++i) {
            const glm::dvec2 uv = h.uv_at(screen[i].x, screen[i].y);
            CHECK(uv.x == doctest::Approx(t.uv[i].x).epsilon(1e-9));
            CHECK(uv.y == doctest::Approx(t.uv[i].y).epsilon(1e-9));
        }
    }
}

TEST_CASE("interior (u, v) matches a double-precision ray/plane intersection within 1e-3 texel of 1024^2") {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double worst_texels = 0.0;
    for (int trial = 0; trial < 500; ++trial) {
        const CameraTriangle t = random_triangle(rng);
        const auto screen = t.screen();
        const TextureHomography h = texture_homography(screen, t.inv_w(), t.uv);
        for (int k = 0; k < 20; ++k) {
            // A random point inside the screen triangle.
            double a = unit(rng), b = unit(rng);
            if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
            const glm::dvec2 xy = screen[0] + a * (screen[1] - screen[0]) + b * (screen[2] - screen[0]);
            const glm::dvec2 expected = t.ray_cast_uv(xy.x, xy.y);
            const glm::dvec2 got = h.uv_at(xy.x, xy.y);
            worst_texels = std::max({worst_texels, std::fabs(got.x - expected.x) * 1024, std::fabs(got.y - expected.y) * 1024});
        }
    }
    MESSAGE("worst difference: " << worst_texels << " texel");
    CHECK(worst_texels < 1e-3);
}

TEST_CASE("collinear and coincident UVs give finite values, and no forward map") {
    const std::array<glm::dvec2, 3> screen{glm::dvec2(10, 10), glm::dvec2(200, 30), glm::dvec2(60, 180)};
    const std::array<double, 3> inv_w{1.0, 0.25, 0.5};
    SUBCASE("collinear: u = v along a line") {
        const TextureHomography h = texture_homography(screen, inv_w, {glm::dvec2(0, 0), glm::dvec2(1, 1), glm::dvec2(3, 3)});
        for (double y = 20; y < 150; y += 7.3)
            for (double x = 40; x < 120; x += 5.1) {
                const glm::dvec2 uv = h.uv_at(x, y);
                CHECK(std::isfinite(uv.x));
                CHECK(uv.x == doctest::Approx(uv.y));
            }
        CHECK_FALSE(h.forward().has_value());
    }
    SUBCASE("coincident: the same UV everywhere") {
        const glm::dvec2 c(0.25, 0.75);
        const TextureHomography h = texture_homography(screen, inv_w, {c, c, c});
        const glm::dvec2 uv = h.uv_at(77.7, 66.6);
        CHECK(uv.x == doctest::Approx(0.25));
        CHECK(uv.y == doctest::Approx(0.75));
        const auto d = uv_derivatives(h, uv.x, uv.y, h.q.at(77.7, 66.6));
        CHECK(d.dudx == doctest::Approx(0.0).scale(1.0));
        CHECK(d.dvdy == doctest::Approx(0.0).scale(1.0));
        CHECK_FALSE(h.forward().has_value());
    }
}

TEST_CASE("the forward map exists for UVs of any scale that are not collinear, and maps each UV to its vertex") {
    // With UVs near 1e300 the determinant of M^-1 overflowed and the forward map was refused
    // ("the UVs are collinear", found by a review). M (u_i, v_i, 1) must be a multiple of
    // (x_i, y_i, 1) at each vertex, whatever the scale; collinear UVs at that scale still
    // have none.
    using Corners = std::array<glm::dvec2, 3>;
    const auto maps_uvs_to_corners = [](const Corners& screen, const std::array<double, 3>& inv_w, const Corners& uv) {
        const auto forward = texture_homography(screen, inv_w, uv).forward();
        REQUIRE(forward.has_value());
        for (int i = 0; i < 3; ++i) {
            const glm::dvec3 p = *forward * glm::dvec3(uv[std::size_t(i)], 1.0);
            CHECK(p.x / p.z == doctest::Approx(screen[std::size_t(i)].x).epsilon(1e-9));
            CHECK(p.y / p.z == doctest::Approx(screen[std::size_t(i)].y).epsilon(1e-9));
        }
    };
    const Corners screen{glm::dvec2(10, 10), glm::dvec2(200, 30), glm::dvec2(60, 180)};
    const std::array<double, 3> inv_w{1.0, 0.25, 0.5};
    for (double scale : {1e-300, 1e-5, 1.0, 1e7, 1e150, 1e300}) {
        CAPTURE(scale);
        maps_uvs_to_corners(screen, inv_w, {glm::dvec2(-1, 0) * scale, glm::dvec2(1, 0.5) * scale, glm::dvec2(0, 1) * scale});
        const Corners collinear{glm::dvec2(0, 0), glm::dvec2(1, 1) * scale, glm::dvec2(3, 3) * scale};
        CHECK_FALSE(texture_homography(screen, inv_w, collinear).forward().has_value());
        // UVs all below 0: rows of M^-1 whose entries are all negative or 0 (their scale is
        // taken from their magnitudes, not their signed values, which left it 0 and no map);
        // on a right triangle at w = 1, u' = -1 - x / 10 and v' = -1 - y / 10 (at scale 1)
        // have no positive entry at all: rows (-0.1, 0, -1) and (0, -0.1, -1).
        const Corners negative{glm::dvec2(-1, -1) * scale, glm::dvec2(-2, -1) * scale, glm::dvec2(-1, -2) * scale};
        maps_uvs_to_corners(screen, inv_w, negative);
        maps_uvs_to_corners({glm::dvec2(0, 0), glm::dvec2(10, 0), glm::dvec2(0, 10)}, {1.0, 1.0, 1.0}, negative);
    }
}

TEST_CASE("exact derivatives by the quotient rule match central differences of the exact map") {
    std::mt19937_64 rng(4);
    for (int trial = 0; trial < 100; ++trial) {
        const CameraTriangle t = random_triangle(rng);
        const auto screen = t.screen();
        const TextureHomography h = texture_homography(screen, t.inv_w(), t.uv);
        const glm::dvec2 c = (screen[0] + screen[1] + screen[2]) / 3.0;
        const glm::dvec2 uv = h.uv_at(c.x, c.y);
        const auto d = uv_derivatives(h, uv.x, uv.y, h.q.at(c.x, c.y));
        const double e = 1e-3;  // the ray-cast map is smooth; central differences err by O(e^2)
        const glm::dvec2 ddx = (t.ray_cast_uv(c.x + e, c.y) - t.ray_cast_uv(c.x - e, c.y)) / (2 * e);
        const glm::dvec2 ddy = (t.ray_cast_uv(c.x, c.y + e) - t.ray_cast_uv(c.x, c.y - e)) / (2 * e);
        CHECK(d.dudx == doctest::Approx(ddx.x).epsilon(1e-5).scale(1e-3));
        CHECK(d.dvdx == doctest::Approx(ddx.y).epsilon(1e-5).scale(1e-3));
        CHECK(d.dudy == doctest::Approx(ddy.x).epsilon(1e-5).scale(1e-3));
        CHECK(d.dvdy == doctest::Approx(ddy.y).epsilon(1e-5).scale(1e-3));
    }
}

TEST_CASE("stepping (u', v', q) across a 4096-pixel span stays within 1e-3 texel of direct evaluation") {
    // A strongly foreshortened quad-half: the near edge at z = -0.5, the far one at z = -500,
    // spanning 4096 pixels of one row, with UVs repeating 300 times.
    CameraTriangle t;
    t.f = 2048.0, t.cx = 2048.0, t.cy = 100.0;
    t.p = {glm::dvec3(-0.5, -0.05, -0.5), glm::dvec3(500.0, -50.0, -500.0), glm::dvec3(-0.5, 0.3, -0.5)};
    t.uv = {glm::dvec2(0, 0), glm::dvec2(300, 0), glm::dvec2(0, 1)};
    const TextureHomography h = texture_homography(t.screen(), t.inv_w(), t.uv);
    const int y = 110;
    SteppedPlane u = SteppedPlane::start(h.u_prime, 0, y), v = SteppedPlane::start(h.v_prime, 0, y),
                 q = SteppedPlane::start(h.q, 0, y);
    double worst = 0.0;
    for (int x = 0; x < 4096; ++x) {
        const glm::dvec2 direct = h.uv_at(x + 0.5, y + 0.5);
        worst = std::max({worst, std::fabs(u.value / q.value - direct.x) * 1024, std::fabs(v.value / q.value - direct.y) * 1024});
        u.advance(), v.advance(), q.advance();
    }
    MESSAGE("worst stepped-vs-direct difference: " << worst << " texel of a 1024 texture");
    CHECK(worst < 1e-3);
}
