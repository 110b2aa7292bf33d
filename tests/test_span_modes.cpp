// Span modes: every mode's (u, v) against u'/q evaluated directly, on a strongly
// foreshortened triangle. The adaptive mode must honour its error bound; the subdivided
// modes must err less with shorter sub-spans; plain affine must be visibly wrong.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "texr/raster/span_modes.h"

using namespace texr;

namespace {

// A plane receding to z = -500, tilted so that depth varies along each row (on a level
// floor seen by a level camera every row is at one depth and affine spans would be exact);
// or, `gentle`, a floor from z = -3 to -8 tilted a little; `mirrored` (x -> -x) makes q fall
// along the rows instead of growing, so the adaptive mode walks them backwards. Texture
// coordinates (0, 0), (4, 0), (2, v_far) on a 256 x 256 texture.
struct Floor {
    TextureHomography h;
    Plane u_affine, v_affine;
    explicit Floor(double v_far = 500.0, bool gentle = false, bool mirrored = false) {
        const double f = 1024.0, cx = 1024.0, cy = 300.0;
        const glm::dvec3 steep[3] = {{-2.0, -1.0, -1.0}, {6.0, 2.0, -20.0}, {0.0, -1.0, -500.0}};  // tilted: rows are not iso-depth
        const glm::dvec3 mild[3] = {{-2.0, -1.0, -3.0}, {2.0, -0.9, -3.5}, {0.0, -1.0, -8.0}};  // 3 to 8 units away
        const glm::dvec3* p = gentle ? mild : steep;
        std::array<glm::dvec2, 3> screen;
        std::array<double, 3> inv_w;
        for (int i = 0; i < 3; ++i) {
            screen[i] = {cx + (mirrored ? -f : f) * p[i].x / -p[i].z, cy - f * p[i].y / -p[i].z};
            inv_w[i] = 1.0 / -p[i].z;
        }
        const std::array<glm::dvec2, 3> uv = {glm::dvec2(0, 0), glm::dvec2(4, 0), glm::dvec2(2, v_far)};
        h = texture_homography(screen, inv_w, uv);
        const auto lambda = barycentric_planes(screen);
        u_affine = over_w_plane(lambda, {uv[0].x, uv[1].x, uv[2].x}, {1, 1, 1});
        v_affine = over_w_plane(lambda, {uv[0].y, uv[1].y, uv[2].y}, {1, 1, 1});
    }
};

struct Errors {
    double max = 0.0;
    int divides = 0;
    int spans = 0, stepped_spans = 0;  // adaptive: spans adaptive_steps_whole_span says are all stepped
};

Errors measure(SpanMode mode, double tolerance = 1.0 / 64.0, double v_far = 500.0, bool gentle = false,
               bool mirrored = false) {
    const Floor floor(v_far, gentle, mirrored);
    SpanTexturing t;
    t.h = &floor.h, t.u_affine = floor.u_affine, t.v_affine = floor.v_affine;
    t.width = t.height = 256, t.tolerance = tolerance;
    Errors e;
    std::vector<double> u(2048), v(2048);
    for (int y = 305; y < 1000; y += 7) {  // rows from near the horizon to the near edge
        // The part of the row inside the triangle, conservatively.
        int x0 = 2048, x1 = 0;
        for (int x = 0; x < 2048; ++x) {
            const double q = floor.h.q.at(x + 0.5, y + 0.5);
            const glm::dvec2 uv = floor.h.uv_at(x + 0.5, y + 0.5);
            if (q > 0 && uv.x >= 0 && uv.y >= 0 && uv.x <= 4 && uv.y <= v_far && std::fabs(uv.x - 2.0) <= 2.0 - 2.0 * uv.y / v_far)
                x0 = std::min(x0, x), x1 = std::max(x1, x + 1);
        }
        if (x1 - x0 < 2) continue;
        CoordinateBound bound;
        const int divides = span_texture_coordinates(mode, t, y, x0, x1 - x0, u.data(), v.data(), bound);
        e.divides += divides;
        ++e.spans;
        // The span walk's shortcut: a span it steps itself is one the mode steps throughout.
        if (mode == SpanMode::adaptive && adaptive_steps_whole_span(t, y, x0, x1 - x0)) {
            CHECK(divides == x1 - x0);
            ++e.stepped_spans;
        }
        double u_max = 0.0, v_max = 0.0;
        for (int x = x0; x < x1; ++x) {
            const glm::dvec2 direct = floor.h.uv_at(x + 0.5, y + 0.5);
            e.max = std::max({e.max, std::fabs(u[x - x0] - direct.x) * 256, std::fabs(v[x - x0] - direct.y) * 256});
            u_max = std::max(u_max, std::fabs(u[x - x0])), v_max = std::max(v_max, std::fabs(v[x - x0]));
        }
        // The bound is the largest of the values the mode computed, and every value written,
        // interpolated ones included, is within 2^-48 of it.
        CHECK(bound.u <= u_max);
        CHECK(bound.v <= v_max);
        CHECK(u_max <= bound.u * (1.0 + 0x1p-48));
        CHECK(v_max <= bound.v * (1.0 + 0x1p-48));
    }
    return e;
}

}  // namespace

TEST_CASE("exact and incremental spans agree with direct evaluation") {
    CHECK(measure(SpanMode::exact).max < 1e-9);
    CHECK(measure(SpanMode::incremental).max < 1e-6);
}

TEST_CASE("the adaptive span mode keeps its error bound, for several tolerances") {
    for (double tolerance : {1.0 / 256.0, 1.0 / 64.0, 0.25, 2.0}) {
        CAPTURE(tolerance);
        const Errors adaptive = measure(SpanMode::adaptive, tolerance);
        CHECK(adaptive.max <= tolerance * (1.0 + 1e-9));
        // Never more than a divide per pixel: where the bound allows sub-spans of fewer than
        // 16 pixels (on this steep plane, everywhere up to 0.25 texel), pixels are stepped, a
        // divide each; at 2 texels it interpolates.
        CHECK(adaptive.divides <= measure(SpanMode::exact).divides);
        if (tolerance >= 2.0) CHECK(adaptive.divides < measure(SpanMode::exact).divides);
        MESSAGE("tolerance " << tolerance << ": max error " << adaptive.max << " texel, " << adaptive.divides << " divides");
    }
    // On a floor tilted less across its rows (q varies less along a row), the default
    // tolerance and looser ones interpolate most pixels: fewer than a fifth of a divide per
    // pixel. Mirrored, q falls along every row and the rows are walked backwards.
    for (bool mirrored : {false, true}) {
        CHECK((Floor(4.0, true, mirrored).h.q.dx < 0.0) == mirrored);
        for (double tolerance : {1.0 / 256.0, 1.0 / 64.0, 0.25}) {
            CAPTURE(mirrored);
            CAPTURE(tolerance);
            const Errors mild = measure(SpanMode::adaptive, tolerance, 4.0, true, mirrored);
            const int pixels = measure(SpanMode::exact, tolerance, 4.0, true, mirrored).divides;
            CHECK(mild.max <= tolerance * (1.0 + 1e-9));
            if (tolerance >= 1.0 / 64.0) CHECK(mild.divides * 5 < pixels);
            MESSAGE(std::string(mirrored ? "milder floor, mirrored" : "milder floor") << ", tolerance " << tolerance << ": max error "
                                   << mild.max << " texel, " << mild.divides << " divides for " << pixels << " pixels");
        }
        // The steep floor (stepped at 1/64) backwards too; the span walk steps its spans
        // itself (every span here), and those of the milder floor it leaves to the mode.
        const Errors steep = measure(SpanMode::adaptive, 1.0 / 64.0, 500.0, false, mirrored);
        CHECK(steep.max < 1e-6);
        CHECK(steep.stepped_spans == steep.spans);
        const Errors mild = measure(SpanMode::adaptive, 1.0 / 64.0, 4.0, true, mirrored);
        CHECK(mild.stepped_spans * 4 < mild.spans);
        MESSAGE("spans stepped by the walk: steep " << steep.stepped_spans << " of " << steep.spans << ", milder "
                                                    << mild.stepped_spans << " of " << mild.spans);
    }
    // A looser tolerance never needs more divides.
    CHECK(measure(SpanMode::adaptive, 0.25).divides <= measure(SpanMode::adaptive, 1.0 / 256.0).divides);
}

TEST_CASE("subdivided affine spans err less with shorter sub-spans, and plain affine is wrong") {
    const double e8 = measure(SpanMode::affine8).max, e16 = measure(SpanMode::affine16).max, e32 = measure(SpanMode::affine32).max;
    CHECK(e8 < e16);
    CHECK(e16 < e32);
    // The error of linear interpolation grows with the square of the sub-span length.
    CHECK(e16 / e8 == doctest::Approx(4.0).epsilon(0.5));
    CHECK(measure(SpanMode::affine).max > 10.0);  // tens of texels off: the wrong answer
}

TEST_CASE("an empty span writes nothing in every mode") {
    const Floor floor;
    SpanTexturing t;
    t.h = &floor.h, t.u_affine = floor.u_affine, t.v_affine = floor.v_affine;
    double u[1] = {-7.0}, v[1] = {-7.0};
    for (int m = 0; m < span_mode_count; ++m) {
        CoordinateBound bound;
        CHECK(span_texture_coordinates(SpanMode(m), t, 400, 1000, 0, u, v, bound) == 0);
        CHECK((bound.u == 0.0 && bound.v == 0.0));
        CHECK(u[0] == -7.0);
    }
}

TEST_CASE("the coordinate bound keeps a NaN once it has seen one") {
    CoordinateBound b;
    b.include(-3.0, 2.0);
    CHECK((b.u == 3.0 && b.v == 2.0));
    b.include(std::nan(""), 1.0);
    CHECK(std::isnan(b.u));
    b.include(5.0, -7.0);  // a larger value later does not hide the NaN
    CHECK(std::isnan(b.u));
    CHECK(b.v == 7.0);
    // In every mode: a NaN in u' (or, for affine, in u's screen-space plane) reaches the bound.
    const Floor floor;
    TextureHomography h = floor.h;
    h.u_prime.c = std::nan("");
    SpanTexturing t;
    t.h = &h, t.u_affine = floor.u_affine, t.v_affine = floor.v_affine;
    t.u_affine.c = std::nan("");
    t.width = t.height = 256;
    std::vector<double> u(600), v(600);
    for (int m = 0; m < span_mode_count; ++m) {
        CAPTURE(span_mode_name(SpanMode(m)));
        CoordinateBound bound;
        span_texture_coordinates(SpanMode(m), t, 400, 700, 600, u.data(), v.data(), bound);
        CHECK(std::isnan(bound.u));
        CHECK(!std::isnan(bound.v));
    }
}

TEST_CASE("the adaptive mode steps a span whose error bound overflows, instead of drawing it as one line") {
    // q = 1e118 x + 1e120 and u' = 1e200 (v' = 0): u = 1e80 / (x/100 + 1), halving over the
    // first 100 pixels, a strongly curved row. The bound's K = -u' dq/dx overflows to -inf,
    // so its curvature is inf, and q^3 overflows too: the allowed length inf / inf is NaN.
    // The pixels must then be stepped (as `incremental` does), each within a few roundings
    // of u'/q; a line through the span's ends would be 12% off in its middle.
    TextureHomography h{};
    h.u_prime = {0.0, 0.0, 1e200};
    h.v_prime = {0.0, 0.0, 0.0};
    h.q = {1e118, 0.0, 1e120};
    SpanTexturing t;
    t.h = &h;
    t.width = t.height = 1;
    std::vector<double> u(101), v(101);
    CoordinateBound bound;
    span_texture_coordinates(SpanMode::adaptive, t, 0, 0, 101, u.data(), v.data(), bound);
    double worst = 0.0;
    for (int x = 0; x <= 100; ++x) {
        const double exact = 1e200 / (1e118 * (x + 0.5) + 1e120);
        worst = std::max(worst, std::fabs(u[std::size_t(x)] - exact) / exact);
        CHECK(v[std::size_t(x)] == 0.0);
    }
    CHECK(worst < 1e-12);
}

TEST_CASE("affine8 divides at every 8th pixel and the span's end, where it is exact") {
    // 17 pixels: exact values at pixels 0, 8 and 16 (3 divides), lines between them.
    TextureHomography h;
    h.u_prime = {0.01, 0.0, 0.1}, h.v_prime = {0.0, 0.01, 0.1}, h.q = {0.001, 0.0, 1.0};
    SpanTexturing t;
    t.h = &h;
    double u[17], v[17], eu[17], ev[17];
    CoordinateBound b, eb;
    CHECK(span_texture_coordinates(SpanMode::affine8, t, 0, 0, 17, u, v, b) == 3);
    span_texture_coordinates(SpanMode::exact, t, 0, 0, 17, eu, ev, eb);
    for (const int k : {0, 8, 16}) {
        CAPTURE(k);
        CHECK(u[k] == eu[k]);
        CHECK(v[k] == ev[k]);
    }
    CHECK(u[4] != eu[4]);  // (between them, a line: not the exact curve)
}

TEST_CASE("the adaptive mode keeps its bound where u' and q change in opposite directions along the row") {
    // u = (1.005 - 0.01 x') / (0.995 + 0.01 x'), x' = x + 1/2: u' falls while q grows. The
    // bound's curvature K = du'/dx q - u' dq/dx must take the difference of the two terms;
    // their sum is 0 here at the first pixel's centre, x' = 1/2, and would allow the whole span as one line (43.9 texels
    // off at pixel 41), with v' = 0 (v adds no curvature of its own to hide it). Then every
    // sign of du'/dx, dv'/dx (or v' = 0) and dq/dx, the walk going either way.
    for (const double su : {1.0, -1.0})
        for (const double sv : {1.0, 0.0, -1.0})
            for (const double sq : {1.0, -1.0}) {
                TextureHomography h;
                h.u_prime = {-0.01 * su, 0.0, 1.005}, h.v_prime = {0.003 * sv, 0.0, sv == 0.0 ? 0.0 : 0.4};
                h.q = {0.01 * sq, 0.0, 0.995 + (sq < 0 ? 1.2 : 0.0)};
                SpanTexturing t;
                t.h = &h;
                t.width = t.height = 256;
                std::vector<double> u(101), v(101), eu(101), ev(101);
                CoordinateBound b, eb;
                span_texture_coordinates(SpanMode::adaptive, t, 0, 0, 101, u.data(), v.data(), b);
                span_texture_coordinates(SpanMode::exact, t, 0, 0, 101, eu.data(), ev.data(), eb);
                double worst = 0.0;
                for (int k = 0; k < 101; ++k)
                    worst = std::max({worst, std::fabs(u[std::size_t(k)] - eu[std::size_t(k)]) * 256.0,
                                      std::fabs(v[std::size_t(k)] - ev[std::size_t(k)]) * 256.0});
                CAPTURE(su);
                CAPTURE(sv);
                CAPTURE(sq);
                CHECK(worst <= t.tolerance * (1.0 + 1e-9));
            }
}
