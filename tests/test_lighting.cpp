// Lambert lighting against values worked out independently of the renderer: each covered
// pixel's linear colour is ambient + sum over lights of colour * max(0, N . L), with N and L
// found here from the geometry (a ray through the pixel centre onto the surface, the normal
// of the transformed surface from its edges), not from the renderer's plane equations.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <stb_image_write.h>

#include "helpers.h"
#include "texr/core/color.h"
#include "texr/core/scaling.h"
#include "texr/render/explain.h"
#include "texr/render/renderer.h"
#include "texr/scene/obj_mesh.h"
#include "texr/scene/parser.h"

using namespace texr;

namespace {

Framebuffer render_text(const std::string& text) { return testing::render_scene_text(text, "lighting.scene"); }

// The camera of these scenes: at (0, 3, 0) looking straight down (-y), up is -z, 90 degrees,
// 32x32 pixels. The world point on the plane y = h seen at the centre of pixel (x, y).
constexpr int size = 32;
const std::string camera = "size 32 32\ncamera eye 0 3 0 target 0 0 0 up 0 0 -1 fov 90\n";
glm::dvec3 point_seen(int x, int y, double h) {
    const double ndc_x = (x + 0.5) / size * 2.0 - 1.0, ndc_y = 1.0 - (y + 0.5) / size * 2.0;
    // right = forward x up = (0, -1, 0) x (0, 0, -1) = (1, 0, 0); tan(45 degrees) = 1
    const glm::dvec3 direction(ndc_x, -1.0, -ndc_y);
    return glm::dvec3(0.0, 3.0, 0.0) + (3.0 - h) * direction;
}

// The sRGB curve (IEC 61966-2-1), as scene colours are decoded.
double linear_of(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
const double ambient = linear_of(0.5);  // "ambient 0.5 0.5 0.5": 0.21404

}  // namespace

TEST_CASE("Lambert, directional light: ambient + cos of the angle, with normals given at any length") {
    // A floor at y = 0, its normals given as (0, 2, 0): N . L uses the unit normal. The light
    // travels along (0, -1, -1): L = (0, 1, 1) / sqrt 2, N . L = 1 / sqrt 2. A light from
    // below adds nothing (the cosine is clamped at 0, not taken as its absolute value).
    const std::string floor = "quad material white v -4 0 4 0 0 n 0 2 0 v 4 0 4 1 0 n 0 2 0 v 4 0 -4 1 1 n 0 2 0 "
                              "v -4 0 -4 0 1 n 0 2 0\n";
    const std::string scene = camera + "ambient 0.5 0.5 0.5\nmaterial white color 1 1 1 lighting lambert\n" + floor;
    Framebuffer fb = render_text(scene + "light directional 0 -1 -1 color 1 1 1\n");
    const double expected = ambient + 1.0 / std::sqrt(2.0);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const Color c = fb.color[fb.index(x, y)];
            REQUIRE(c.x == doctest::Approx(expected).epsilon(1e-5));
            REQUIRE(c.y == c.x);
        }
    fb = render_text(scene + "light directional 0 1 0 color 1 1 1\n");
    CHECK(fb.color[fb.index(16, 16)].x == doctest::Approx(ambient).epsilon(1e-6));
    // Two lights, each clamped on its own: a coloured one at 45 degrees and a white one from
    // below (which adds nothing, and takes nothing away). Each channel: ambient +
    // linear(colour) / sqrt 2.
    fb = render_text(scene + "light directional 0 -1 -1 color 1 0.5 0.25\nlight directional 0 1 0 color 1 1 1\n");
    const Color c = fb.color[fb.index(16, 16)];
    CHECK(c.x == doctest::Approx(ambient + linear_of(1.0) / std::sqrt(2.0)).epsilon(1e-5));
    CHECK(c.y == doctest::Approx(ambient + linear_of(0.5) / std::sqrt(2.0)).epsilon(1e-5));
    CHECK(c.z == doctest::Approx(ambient + linear_of(0.25) / std::sqrt(2.0)).epsilon(1e-5));
}

TEST_CASE("Lambert, point light: L from each pixel's own world position, normals computed from the winding") {
    // A floor at y = 0 without normals: texr computes them from the right-handed winding,
    // (b - a) x (c - a) = (8, 0, 0) x (8, 0, -8) = (0, 64, 0): up. A point light at
    // (1, 1, -0.5): at the world point P seen through each pixel, N . L = normalize(light - P).y.
    const std::string scene = camera +
                              "ambient 0.5 0.5 0.5\nmaterial white color 1 1 1 lighting lambert\n"
                              "light point 1 1 -0.5 color 1 1 1\n"
                              "quad material white v -4 0 4 0 0 v 4 0 4 1 0 v 4 0 -4 1 1 v -4 0 -4 0 1\n";
    const Framebuffer fb = render_text(scene);
    double brightest = 0.0;
    int brightest_x = -1, brightest_y = -1;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const glm::dvec3 p = point_seen(x, y, 0.0);
            const double cosine = glm::normalize(glm::dvec3(1.0, 1.0, -0.5) - p).y;
            const double expected = ambient + std::max(0.0, cosine);
            CAPTURE(x);
            CAPTURE(y);
            // Within 5e-4: the vertices are snapped to 1/256 pixel, which moves the surface
            // seen through a pixel by up to about 4e-4 world units (a pixel is 0.1875), and the
            // cosine changes by at most about 1 per unit here.
            REQUIRE(std::fabs(fb.color[fb.index(x, y)].x - expected) < 5e-4);
            if (fb.color[fb.index(x, y)].x > brightest) brightest = fb.color[fb.index(x, y)].x, brightest_x = x, brightest_y = y;
        }
    // The brightest pixel is the one under the light: x = 1 is pixel 16 + 16/3 = 21.3 -> 21,
    // z = -0.5 is pixel 16 - 8/3 = 13.3 -> 13.
    CHECK(brightest_x == 21);
    CHECK(brightest_y == 13);
}

TEST_CASE("Lambert under a non-uniform scale and a rotation: normals follow the surface (inverse transpose)") {
    // The quad lies in the plane x + y = 0 with normals (1, 1, 0). Scaled by (1, 0.25, 1) and
    // then turned 30 degrees about z, its edges (4, -4, 0) and (0, 0, 4) become
    // R (4, -1, 0) = (4 cos 30 + sin 30, 4 sin 30 - cos 30, 0) and (0, 0, 4); their cross
    // product, turned to face up, is the surface's normal. Lit straight from above, N . L is
    // its y: 0.9615. Transforming the normal like a position gives 0.695, and the inverse
    // without the transpose 0.731.
    const std::string scene = camera +
                              "ambient 0.5 0.5 0.5\nmaterial white color 1 1 1 lighting lambert\n"
                              "light directional 0 -1 0 color 1 1 1\n"
                              "quad material white scale 1 0.25 1 rotate 30 0 0 1 v -2 2 -2 0 0 n 1 1 0 v 2 -2 -2 1 0 n 1 1 0 "
                              "v 2 -2 2 1 1 n 1 1 0 v -2 2 2 0 1 n 1 1 0\n";
    const Framebuffer fb = render_text(scene);
    const double cos30 = std::sqrt(3.0) / 2.0, sin30 = 0.5;
    const glm::dvec3 edge1(4.0 * cos30 + sin30, 4.0 * sin30 - cos30, 0.0), edge2(0.0, 0.0, 4.0);
    glm::dvec3 n = glm::normalize(glm::cross(edge1, edge2));
    if (n.y < 0.0) n = -n;
    const double expected = ambient + n.y;
    CHECK(n.y == doctest::Approx(0.9615).epsilon(1e-4));
    int covered = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            if (fb.drawn(fb.index(x, y))) {
                ++covered;
                REQUIRE(fb.color[fb.index(x, y)].x == doctest::Approx(expected).epsilon(1e-5));
            }
    CHECK(covered > 100);
}

TEST_CASE("Lambert with normals that vary over a triangle seen at an angle: perspective-correct, on every texture path") {
    // A floor triangle whose three normals differ, seen obliquely, lit from straight above:
    // each pixel's N . L is the y of the normalised normal at the world point P it sees,
    // where the normal is the vertices' unit normals weighted by P's barycentric coordinates
    // in the world triangle (perspective-correct interpolation is linear on the surface). An
    // affine interpolation in screen space would differ by up to tens of percent here. The
    // normals are given at lengths 1, sqrt 5 and sqrt 10: weighing the given vectors instead
    // of their directions would differ by up to 0.21 here. Then the same triangle scaled by
    // (1.5, 1, 0.5): its corners move, and its normals turn by the inverse transpose,
    // diag(1/1.5, 1, 2), which also leaves them at new, unequal lengths.
    // The same with a white texture: a bilinear 2x2 image takes the span walk's short,
    // batched path, which steps the normals its own way.
    const std::string dir = testing::scratch_folder("lighting");
    testing::write_text(dir + "/white.ppm", std::string("P6\n2 2\n255\n") + std::string(12, char(255)));
    const std::string triangle = " v -6 0 3 0 0 n 0 1 0 v 6 0 3 1 0 n 2 1 0 v 0 0 -30 0.5 1 n 0 1 -3\n";
    const std::string common = "size 48 32\ncamera eye 0 1 2 target 0 0 -3 fov 90\nambient 0.5 0.5 0.5\n"
                               "light directional 0 -1 0 color 1 1 1\ntexture white file " + dir + "/white.ppm\n";
    // The camera's basis, for the ray through a pixel centre.
    const glm::dvec3 eye(0.0, 1.0, 2.0), forward = glm::normalize(glm::dvec3(0.0, 0.0, -3.0) - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0.0, 1.0, 0.0))), up = glm::cross(right, forward);
    for (int variant = 0; variant < 4; ++variant) {
        const std::string material = variant % 2 == 0 ? "material m color 1 1 1 lighting lambert\n"
                                                       : "material m texture white lighting lambert\n";
        const bool scaled = variant >= 2;
        CAPTURE(material);
        CAPTURE(scaled);
        const std::string transform = scaled ? " scale 1.5 1 0.5" : "";
        const glm::dvec3 scale = scaled ? glm::dvec3(1.5, 1.0, 0.5) : glm::dvec3(1.0);
        const glm::dvec3 a = scale * glm::dvec3(-6.0, 0.0, 3.0), b = scale * glm::dvec3(6.0, 0.0, 3.0),
                         c = scale * glm::dvec3(0.0, 0.0, -30.0);
        const glm::dvec3 na = glm::dvec3(0.0, 1.0, 0.0) / scale, nb = glm::dvec3(2.0, 1.0, 0.0) / scale,
                         nc = glm::dvec3(0.0, 1.0, -3.0) / scale;
        const Framebuffer fb = render_text(common + material + "triangle material m" + transform + triangle);
        int checked = 0;
        double worst = 0.0;
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 48; ++x) {
                if (!fb.drawn(fb.index(x, y))) continue;
                const double ndc_x = (x + 0.5) / 48.0 * 2.0 - 1.0, ndc_y = 1.0 - (y + 0.5) / 32.0 * 2.0;
                const glm::dvec3 ray = forward + ndc_x * 1.5 * right + ndc_y * up;  // tan(45 degrees) = 1, aspect 1.5
                const glm::dvec3 p = eye + (-eye.y / ray.y) * ray;
                // Barycentric coordinates of p in the triangle, in the xz plane.
                const auto area = [](glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2) {
                    return (p1.x - p0.x) * (p2.z - p0.z) - (p2.x - p0.x) * (p1.z - p0.z);
                };
                const double whole = area(a, b, c);
                const double wa = area(p, b, c) / whole, wb = area(a, p, c) / whole, wc = area(a, b, p) / whole;
                if (std::min({wa, wb, wc}) < 0.02) continue;  // pixels at the edges may be the neighbour's
                const double expected = ambient + glm::normalize(wa * glm::normalize(na) + wb * glm::normalize(nb) + wc * glm::normalize(nc)).y;
                worst = std::max(worst, std::fabs(fb.color[fb.index(x, y)].x - expected));
                ++checked;
            }
        CHECK(checked > 300);
        // Vertex snapping (1/256 pixel) moves P by a little; the normal changes slowly.
        CHECK(worst < 1e-3);
        MESSAGE("largest difference from the surface's own normal: ", worst, " over ", checked, " pixels");
    }
}

TEST_CASE("Lambert at extreme scales: directions of 1e300 and 1e-300, objects scaled by 1e-110 and 1e150") {
    // A floor of unit normals lit along (0, -1, -1) at any length: ambient + 1 / sqrt 2
    // (squared lengths of 1e600 and 1e-600 overflowed and underflowed: no light, or NaN).
    const double expected = ambient + 1.0 / std::sqrt(2.0);
    const std::string floor = "quad material white v -4 0 4 0 0 v 4 0 4 1 0 v 4 0 -4 1 1 v -4 0 -4 0 1";
    const std::string materials = "ambient 0.5 0.5 0.5\nmaterial white color 1 1 1 lighting lambert\n";
    for (const char* light : {"0 -1e300 -1e300", "0 -1e-300 -1e-300"}) {
        CAPTURE(light);
        const Framebuffer fb = render_text(camera + materials + floor + "\nlight directional " + light + " color 1 1 1\n");
        CHECK(fb.color[fb.index(16, 16)].x == doctest::Approx(expected).epsilon(1e-5));
    }
    // The floor scaled by s (and rotated about an axis of length 1e300: a quarter turn about
    // y changes nothing of a square floor), seen from s times as far: the same picture. Its
    // normals come from the inverse transpose of a matrix whose entries are s, which overflowed
    // or underflowed before.
    for (const double s : {1e-110, 1e150}) {
        CAPTURE(s);
        char text[512];
        std::snprintf(text, sizeof text,
                      "size 32 32\ncamera eye 0 %.17g 0 target 0 0 0 up 0 0 -1e-300 fov 90 near %.17g far %.17g\n%s%s scale %.17g "
                      "rotate 90 0 1e300 0\nlight directional 0 -1 -1 color 1 1 1\n",
                      3.0 * s, 0.1 * s, 100.0 * s, materials.c_str(), floor.c_str(), s);
        const Framebuffer fb = render_text(text);
        for (const int at : {0, 16, 31}) CHECK(fb.color[fb.index(at, at)].x == doctest::Approx(expected).epsilon(1e-5));
    }
}

TEST_CASE("a point light 1e155 away lights as a directional light from its direction") {
    // |light - P|^2 is about 2e310, beyond a double: normalising it gave (0, 0, 0), no light.
    // From 1e155 units the directions to the floor's points differ by less than 1e-154, so
    // each pixel is ambient + 1/sqrt 2, as under "light directional 0 -1 -1" (the first test).
    const std::string scene = camera +
                              "ambient 0.5 0.5 0.5\nmaterial white color 1 1 1 lighting lambert\n"
                              "quad material white v -4 0 4 0 0 v 4 0 4 1 0 v 4 0 -4 1 1 v -4 0 -4 0 1\n";
    const double expected = ambient + 1.0 / std::sqrt(2.0);
    for (const char* position : {"0 1e155 1e155", "0 1e300 1e300"}) {
        CAPTURE(position);
        const Framebuffer fb = render_text(scene + "light point " + position + " color 1 1 1\n");
        for (const int at : {0, 16, 31}) CHECK(fb.color[fb.index(at, at)].x == doctest::Approx(expected).epsilon(1e-5));
    }
    // unit_direction itself, at lengths whose squares are out of range, and a usual one.
    for (const double s : {1e-200, 1e-160, 0.5, 1e160, 1e300}) {
        CAPTURE(s);
        const glm::dvec3 d = unit_direction(glm::dvec3(3.0 * s, 0.0, -4.0 * s));
        CHECK(d.x == doctest::Approx(0.6).epsilon(1e-15));
        CHECK(d.y == 0.0);
        CHECK(d.z == doctest::Approx(-0.8).epsilon(1e-15));
    }
    CHECK(std::isnan(unit_direction(glm::dvec3(0.0)).x));
}

TEST_CASE("a surface scaled unevenly by 1e-200 or 1e160 is lit as one scaled by 1") {
    // The floor y = 0 scaled along y by 1e-200 (or along x and z by 1e160, seen from 1e150 times as
    // far) is the same floor; its normals (inverse transpose) are (0, 1e200, 0) before the
    // power-of-two rescale of the largest entry, which leaves them far beyond 1: squared,
    // they overflowed, normalised to 0, and the floor was unlit. Lit along (0, -1, -1):
    // ambient + 1 / sqrt 2 everywhere.
    const double expected = ambient + 1.0 / std::sqrt(2.0);
    const std::string materials = "ambient 0.5 0.5 0.5\nmaterial white color 1 1 1 lighting lambert\n"
                                  "light directional 0 -1 -1 color 1 1 1\n";
    const std::string floor = "quad material white v -4 0 4 0 0 v 4 0 4 1 0 v 4 0 -4 1 1 v -4 0 -4 0 1";
    const Framebuffer thin = render_text(camera + materials + floor + " scale 1 1e-200 1\n");
    const Framebuffer wide = render_text(
        "size 32 32\ncamera eye 0 3e150 0 target 0 0 0 up 0 0 -1 fov 90 near 1e149 far 1e152\n" + materials + floor +
        " scale 1e160 1 1e160\n");
    for (const Framebuffer* fb : {&thin, &wide})
        for (const int at : {0, 16, 31}) CHECK(fb->color[fb->index(at, at)].x == doctest::Approx(expected).epsilon(1e-5));
}

TEST_CASE("an infinite lit colour times no light is written as 0, not NaN") {
    // A float texel of 1e38 times a material colour of 10000 is infinite; lambert with no
    // light and no ambient multiplies it by 0 (NaN in IEEE arithmetic).
    const std::string dir = testing::scratch_folder("inf-times-zero");
    const float texel[3] = {1e38f, 1e38f, 1e38f};
    REQUIRE(stbi_write_hdr((dir + "/bright.hdr").c_str(), 1, 1, 3, texel));
    const std::string text = camera + "texture t file " + dir + "/bright.hdr filter nearest\n"
                             "material m texture t color 10000 10000 10000 lighting lambert\n"
                             "quad material m v -4 0 4 0 0 v 4 0 4 1 0 v 4 0 -4 1 1 v -4 0 -4 0 1\n";
    const Framebuffer fb = render_text(text);
    for (const int at : {0, 16, 31}) {
        const Color c = fb.color[fb.index(at, at)];
        CHECK(c.x == 0.0f);
        CHECK(c.y == 0.0f);
        CHECK(c.z == 0.0f);
    }
}

TEST_CASE("unit_scale_exponent brings the largest value to 1 or more and below 2 by a power of two") {
    CHECK(unit_scale_exponent(1.0) == 0);
    CHECK(unit_scale_exponent(1.999) == 0);
    CHECK(unit_scale_exponent(2.0) == -1);
    CHECK(unit_scale_exponent(0.75) == 1);
    CHECK(unit_scale_exponent(0x1p-1074) == 1074);  // the smallest subnormal
    CHECK(unit_scale_exponent(0x1.fffffffffffffp1023) == -1023);  // the largest double
    for (const double x : {3e-300, 7e-20, 0.3, 12345.0, 1e150, 1e300}) {
        const double scaled = std::ldexp(x, unit_scale_exponent(x));
        CHECK(scaled >= 1.0);
        CHECK(scaled < 2.0);
    }
    CHECK(unit_scale_exponent(0.0) == 0);
    CHECK(unit_scale_exponent(std::numeric_limits<double>::infinity()) == 0);
    CHECK(unit_scale_exponent(std::nan("")) == 0);
}

TEST_CASE("texr explain finds the same light for a point light 1e155 away and for normals of 1e200") {
    // The explained pixel's story recomputes N and L: the floor's N = (0, 1, 0) and, from a
    // light 1e155 along (0, 1, 1) or a directional light along (0, -1, -1), N . L = 1 / sqrt 2.
    const std::string materials = "ambient 0.5 0.5 0.5\nmaterial white color 1 1 1 lighting lambert\n";
    const std::string floor = "quad material white v -4 0 4 0 0 v 4 0 4 1 0 v 4 0 -4 1 1 v -4 0 -4 0 1";
    for (const std::string& text : {camera + materials + floor + "\nlight point 0 1e155 1e155 color 1 1 1\n",
                                    camera + materials + floor + " scale 1 1e-200 1\nlight directional 0 -1 -1 color 1 1 1\n"}) {
        CAPTURE(text);
        std::istringstream in(text);
        const Scene scene = parse_scene(in, "lighting.scene");
        RenderOptions options;
        options.explain_x = 16, options.explain_y = 16;
        RenderStats stats;
        const Framebuffer fb = render(scene, options, stats);
        REQUIRE(fb.explanation);
        const std::string story = describe(*fb.explanation, scene);
        CAPTURE(story);
        CHECK(story.find("N = (0.00000, 1.00000, 0.00000)") != std::string::npos);
        CHECK(story.find("x max(0, N . L) = x 0.70711") != std::string::npos);
    }
}

TEST_CASE("a scene built in code with colours or light vectors beyond a parsed scene's still shades no NaN on the short paths") {
    // A black 8-bit texture (the short path: nearest, repeat, power of two) under lambert: the
    // material colour, a light's colour or a directional light's vector made huge or infinite
    // (the parser refuses these; render() takes any Scene) gives inf times 0 = NaN, which
    // is written as 0. The short path gives the general path's frame (capture_uv sends every
    // span to the general path, which always tests for NaN).
    const std::string dir = testing::scratch_folder("short-path-nan");
    const unsigned char black[4 * 4] = {};
    REQUIRE(stbi_write_png((dir + "/black.png").c_str(), 2, 2, 4, black, 8));
    const std::string text = camera + "ambient 0.5 0.5 0.5\ntexture t file " + dir + "/black.png filter nearest\n"
                             "material m texture t lighting lambert\nlight directional 0 -1 -1 color 1 1 1\n"
                             "quad material m v -4 0 4 0 0 v 4 0 4 1 0 v 4 0 -4 1 1 v -4 0 -4 0 1\n";
    const float inf = std::numeric_limits<float>::infinity();
    for (int variant = 0; variant < 3; ++variant) {
        CAPTURE(variant);
        std::istringstream in(text);
        Scene scene = parse_scene(in, "lighting.scene");
        if (variant == 0) scene.materials[0].color = Color(inf);
        if (variant == 1) scene.lights[0].color = Color(3e38f), scene.lights.push_back(scene.lights[0]);
        if (variant == 2) scene.lights[0].vector = glm::dvec3(0.0, -1e300, -1e300);
        RenderOptions short_path, general;
        general.capture_uv = true;
        RenderStats stats;
        const Framebuffer a = render(scene, short_path, stats), b = render(scene, general, stats);
        std::size_t nan = 0, differ = 0;
        for (std::size_t i = 0; i < a.color.size(); ++i) {
            nan += std::isnan(a.color[i].x) || std::isnan(a.color[i].y) || std::isnan(a.color[i].z);
            differ += !(a.color[i] == b.color[i]);
        }
        CHECK(nan == 0);
        CHECK(differ == 0);
    }
}

TEST_CASE("OBJ vertex colours (v x y z r g b) are sRGB, interpolated across the face like a scene triangle's c") {
    // A floor triangle seen from straight above, its corners coloured in the OBJ file; each
    // pixel's linear colour is the corners' decoded colours weighted by the barycentric
    // coordinates of the world point it sees (found here from the camera, not the renderer).
    // The same triangle written inline with `c` gives the same frame.
    const std::string dir = testing::scratch_folder("obj-colours");
    const glm::dvec3 a(-2.5, 0.0, 2.0), b(2.5, 0.0, 2.0), c(0.0, 0.0, -2.5);
    const glm::dvec3 ca(1.0, 0.5, 0.0), cb(0.0, 1.0, 0.25), cc(0.2, 0.4, 1.0);
    testing::write_text(dir + "/tri.obj", "v -2.5 0 2 1 0.5 0\nv 2.5 0 2 0 1 0.25\nv 0 0 -2.5 0.2 0.4 1\nf 1 2 3\n");
    const std::string common = camera + "material paint vertex_colors on\n";
    const Framebuffer fb = render_text(common + "mesh " + dir + "/tri.obj material paint\n");
    const Framebuffer inline_fb =
        render_text(common + "triangle material paint v -2.5 0 2 0 0 c 1 0.5 0 v 2.5 0 2 1 0 c 0 1 0.25 v 0 0 -2.5 0 1 c 0.2 0.4 1\n");
    const auto decoded = [](glm::dvec3 srgb) { return glm::dvec3(linear_of(srgb.x), linear_of(srgb.y), linear_of(srgb.z)); };
    int checked = 0, covered = 0, differ = 0;
    double worst = 0.0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const std::size_t i = fb.index(x, y);
            differ += fb.drawn(i) != inline_fb.drawn(i) || !(fb.color[i] == inline_fb.color[i]);
            if (!fb.drawn(i)) continue;
            ++covered;
            const glm::dvec3 p = point_seen(x, y, 0.0);
            const auto area = [](glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2) {
                return (p1.x - p0.x) * (p2.z - p0.z) - (p2.x - p0.x) * (p1.z - p0.z);
            };
            const double whole = area(a, b, c);
            const double wa = area(p, b, c) / whole, wb = area(a, p, c) / whole, wc = area(a, b, p) / whole;
            if (std::min({wa, wb, wc}) < 0.02) continue;  // pixels at the edges
            const glm::dvec3 expected = wa * decoded(ca) + wb * decoded(cb) + wc * decoded(cc);
            const Color got = fb.color[i];
            worst = std::max({worst, std::fabs(got.x - expected.x), std::fabs(got.y - expected.y), std::fabs(got.z - expected.z)});
            ++checked;
        }
    CHECK(covered > 200);
    CHECK(checked > 150);
    CHECK(worst < 1e-3);  // (vertices snapped to 1/256 pixel; colours kept as floats)
    CHECK(differ == 0);
    MESSAGE("largest difference from the decoded colours' blend: ", worst, " over ", checked, " pixels");
}

TEST_CASE("OBJ normals: the file's are kept where other faces have none, and computed ones are shared by a position's corners") {
    // Worked out by hand: each computed normal is the sum of cross(b - a, c - a) over the
    // faces around the corner's position (v index), normalised.
    const std::string dir = testing::scratch_folder("obj-normals");
    // Two faces with vn (1, 0, 1), which is kept as written, and two without on the plane z = 0.
    // Positions 2 and 3 are on both kinds: their corners without vn take the sum of the four
    // faces' normals, (0, 0, 2) + (0, 0, 2) + (0, 0, 2) + (0, 0, 2) (each face's cross product
    // is (0, 0, 2): twice its area, 1), so (0, 0, 1).
    testing::write_text(dir + "/mix.obj",
                        "v -1 -1 0\nv 0 -1 0\nv 0 1 0\nv -1 1 0\nv 1 -1 0\nv 1 1 0\nvn 1 0 1\n"
                        "f 1//1 2//1 3//1\nf 1//1 3//1 4//1\nf 2 5 6\nf 2 6 3\n");
    Mesh mesh = load_obj(dir + "/mix.obj", [](const ObjMaterialInfo&) { return 0; });
    REQUIRE(mesh.has_normals);
    REQUIRE(mesh.triangles.size() == 4);
    for (int t = 0; t < 4; ++t)
        for (const std::uint32_t i : mesh.triangles[std::size_t(t)]) {
            const glm::vec3 n = mesh.vertices[i].normal;
            CAPTURE(t);
            if (t < 2) {
                CHECK(n == glm::vec3(1.0f, 0.0f, 1.0f));  // as the file gives it
            } else {
                CHECK(n == glm::vec3(0.0f, 0.0f, 1.0f));
            }
        }
    // Faces of different areas, and a quad (split in two, but one face): a quad of area 4
    // facing +z and a triangle of area 2 facing +x share the positions (2, 0, 0) and (2, 2, 0).
    // Their vector areas (twice the area along the normal) are (0, 0, 8) and (4, 0, 0): both
    // shared corners take (4, 0, 8) normalised, (1, 0, 2) / sqrt(5), whichever diagonal splits
    // the quad; the quad's other corners its own (0, 0, 1), the triangle's its own (1, 0, 0).
    testing::write_text(dir + "/areas.obj", "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nv 2 0 -2\nf 1 2 3 4\nf 2 5 3\n");
    mesh = load_obj(dir + "/areas.obj", [](const ObjMaterialInfo&) { return 0; });
    REQUIRE(mesh.vertices.size() == 5);
    for (const Vertex& v : mesh.vertices) {
        CAPTURE(v.position.x);
        CAPTURE(v.position.y);
        CAPTURE(v.position.z);
        const glm::dvec3 expected = v.position.x == 2.0f && v.position.z == 0.0f ? glm::dvec3(1, 0, 2) / std::sqrt(5.0)
                                    : v.position.z == 0.0f                       ? glm::dvec3(0, 0, 1)
                                                                                 : glm::dvec3(1, 0, 0);
        for (int k = 0; k < 3; ++k) CHECK(v.normal[k] == doctest::Approx(expected[k]).epsilon(1e-6));
    }
    // Rendered, lit from the front (L = (0, 0, 1) towards the light): N . L = 1/sqrt(2) on the
    // left faces (the file's normal, normalised when shading), 1 on the right.
    const Framebuffer fb = render_text("size 100 60\ncamera eye 0 0 3 target 0 0 0 fov 60\nlight directional 0 0 -1\n"
                                       "material m color 1 1 1 lighting lambert\nmesh " + dir + "/mix.obj material m\n");
    CHECK(fb.color[fb.index(35, 30)].x == doctest::Approx(std::sqrt(0.5)).epsilon(1e-5));
    CHECK(fb.color[fb.index(65, 30)].x == doctest::Approx(1.0).epsilon(1e-5));
    // A roof of two faces on positions 1-4 (ridge 2-3 at z = 0.6), written twice: with the
    // ridge's corners on the same vt indices, and on other vt indices of the same values. The
    // faces' cross products: (b - a) x (c - a) for (1, 2, 3) = (1, 0, 0.6) x (1, 2, 0.6) =
    // (-1.2, 0, 2); for (3, 2, 4) = (0, -2, 0) x (1, 0, -0.6) = (1.2, 0, 2). The ridge's
    // normal is their sum (0, 0, 4), normalised (0, 0, 1), in both files; the eaves keep
    // their face's own.
    const std::string head = "v -1 -1 0\nv 0 -1 0.6\nv 0 1 0.6\nv 1 1 0\nvt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 1 1\nvt 0.5 0\nvt 0.5 1\n"
                             "f 1/1 2/2 3/3\n";
    for (const char* second : {"f 3/3 2/2 4/4\n", "f 3/6 2/5 4/4\n"}) {
        CAPTURE(second);
        testing::write_text(dir + "/roof.obj", head + second);
        mesh = load_obj(dir + "/roof.obj", [](const ObjMaterialInfo&) { return 0; });
        const double left = 1.0 / std::sqrt(1.2 * 1.2 + 4.0);
        for (const Vertex& v : mesh.vertices) {
            CAPTURE(v.position.x);
            if (v.position.x == 0.0f) {
                CHECK(v.normal.x == doctest::Approx(0.0).epsilon(1e-6));
                CHECK(v.normal.z == doctest::Approx(1.0).epsilon(1e-6));
            } else {
                CHECK(v.normal.x == doctest::Approx(v.position.x < 0.0f ? -1.2 * left : 1.2 * left).epsilon(1e-6));
                CHECK(v.normal.y == doctest::Approx(0.0).epsilon(1e-6));
                CHECK(v.normal.z == doctest::Approx(2.0 * left).epsilon(1e-6));
            }
        }
    }
}

TEST_CASE("OBJ smoothing groups: s off makes faces flat, s N (or on) smooths a group's faces only, a file without s lines smooths all") {
    // Two unit quads meeting at the edge x = 1, z = 0 (positions 2 and 3): A in the plane z = 0
    // facing +z, B in the plane x = 1 facing +x. Their vector areas (Newell: twice the area
    // along the normal) are (0, 0, 2) and (2, 0, 0). Smoothed together, the shared corners
    // take (1, 0, 1) / sqrt(2); apart, each face's corners take its own normal.
    const std::string dir = testing::scratch_folder("obj-smoothing");
    const std::string positions = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 0 -1\nv 1 1 -1\n";
    const std::string a = "f 1 2 3 4\n", b = "f 2 5 6 3\n";
    const glm::vec3 up(0.0f, 0.0f, 1.0f), side(1.0f, 0.0f, 0.0f);
    const glm::vec3 shared = glm::vec3(1.0f, 0.0f, 1.0f) / std::sqrt(2.0f);
    struct Case {
        std::string faces;
        bool together;  // A and B smoothed together
        std::size_t vertices;
        std::size_t flat_triangle = 99;  // a third face, flat, between them (its corners take +z)
    };
    const Case cases[] = {
        {a + b, true, 6},                                         // no s line: one group
        {"s 1\n" + a + b, true, 6},                               // one s group
        {"s 7\n" + a + "s 007\n" + b, true, 6},                  // the same number, written otherwise
        {"s on\n" + a + "s 1\n" + b, true, 6},                    // on is group 1
        {"s 123456789012345678901234567890\n" + a + "s 0123456789012345678901234567890\n" + b, true, 6},
        {"s 3\n" + a + "s off\nf 4 1 2\ns 3\n" + b, true, 9, 2},  // group 3 again, after a flat face
        {"s off\n" + a + b, false, 8},
        {"s 0\n" + a + "s 00\n" + b, false, 8},
        {"s 1\n" + a + "s 2\n" + b, false, 8},
        {a + "s 1\n" + b, false, 8},                               // before any s line, and group 1
        {"s 1\n" + a + "s off\n" + b, false, 8},
        {"s on\n" + a + "s 2\n" + b, false, 8},
    };
    for (const Case& c : cases) {
        CAPTURE(c.faces);
        testing::write_text(dir + "/two.obj", positions + c.faces);
        const Mesh mesh = load_obj(dir + "/two.obj", [](const ObjMaterialInfo&) { return 0; });
        CHECK(mesh.vertices.size() == c.vertices);
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            bool in_b = false;  // B's triangles have a corner at z = -1
            for (const std::uint32_t k : mesh.triangles[t]) in_b = in_b || mesh.vertices[k].position.z == -1.0f;
            for (const std::uint32_t i : mesh.triangles[t]) {
                const Vertex& v = mesh.vertices[i];
                CAPTURE(t);
                CAPTURE(v.position.x);
                CAPTURE(v.position.y);
                CAPTURE(v.position.z);
                const bool on_edge = v.position.x == 1.0f && v.position.z == 0.0f;
                const glm::vec3 expected = t == c.flat_triangle       ? up
                                           : on_edge && c.together ? shared
                                           : in_b                  ? side
                                                                   : up;
                for (int k = 0; k < 3; ++k) CHECK(v.normal[k] == doctest::Approx(expected[k]).epsilon(1e-6));
            }
        }
    }
    // Corners with a normal of their own keep it under s off, and are one vertex whatever their
    // groups (4 vertices here, not 6); a flat face's normal is its whole outline's (Newell's),
    // which for a concave quad whose second corner is reflex, (0, 2), (0.5, 1), (0, 0), (2, 1)
    // (shoelace: twice the area is +3, counter-clockwise), and a concave pentagon is +z,
    // where its first three corners alone would turn the other way.
    const auto normals_of = [&](const std::string& obj) {
        testing::write_text(dir + "/more.obj", obj);
        return load_obj(dir + "/more.obj", [](const ObjMaterialInfo&) { return 0; });
    };
    Mesh mesh = normals_of(positions + "vn 0 3 0\ns off\nf 1//1 2 3 4\n");
    REQUIRE(mesh.vertices.size() == 4);
    for (const Vertex& v : mesh.vertices) CHECK(v.normal == (v.position == glm::vec3(0.0f) ? glm::vec3(0.0f, 3.0f, 0.0f) : up));
    mesh = normals_of(positions + "vn 0 3 0\ns 1\nf 1//1 2//1 3//1\ns 2\nf 1//1 3//1 4//1\n");
    CHECK(mesh.vertices.size() == 4);
    mesh = normals_of("v 0 2 0\nv 0.5 1 0\nv 0 0 0\nv 2 1 0\nv 0 0 1\nv 2 0 1\nv 2 2 1\nv 1 0.5 1\nv 0 2 1\n"
                      "s off\nf 1 2 3 4\nf 5 6 7 8 9\n");
    REQUIRE(mesh.vertices.size() == 9);
    for (const Vertex& v : mesh.vertices) CHECK(v.normal == up);
    // A position a face passes twice (a spike of no width, 3 -> 7 -> 3, on B) counts that face
    // once in its group's sum: the shared corners stay (1, 0, 1) / sqrt(2), in the first group
    // a face is in and in a later one (after a face C of group 1 elsewhere).
    for (const std::string& first : {std::string(), std::string("v 5 5 5\nv 6 5 5\nv 5 6 5\ns 1\nf 8 9 10\n")}) {
        CAPTURE(first);
        mesh = normals_of(positions + "v 1 2 0\n" + first + "s 5\n" + a + "f 2 5 6 3 7 3\n");
        for (const Vertex& v : mesh.vertices) {
            CAPTURE(v.position.x);
            CAPTURE(v.position.y);
            CAPTURE(v.position.z);
            if (v.position.z == 5.0f) continue;  // C
            const glm::vec3 expected = v.position.x == 1.0f && v.position.z == 0.0f && v.position.y < 1.5f ? shared
                                       : v.position.x == 1.0f && v.position.z != 0.0f                  ? side
                                       : v.position.y == 2.0f                                           ? side
                                                                                                        : up;
            for (int k = 0; k < 3; ++k) CHECK(v.normal[k] == doctest::Approx(expected[k]).epsilon(1e-6));
        }
    }

    // Rendered, lit along -z (N . L is N's z), from where both faces show: flat, every covered
    // pixel is 1 (on A) or 0 (on B); smoothed, A darkens towards the shared edge.
    const auto shades = [&](const std::string& faces) {
        testing::write_text(dir + "/lit.obj", positions + faces);
        const Framebuffer fb = render_text("size 120 90\ncamera eye 2.2 0.5 2.2 target 0.5 0.5 -0.3 fov 50\nbackground 0 0 1\n"
                                           "light directional 0 0 -1\nmaterial m color 1 1 1 lighting lambert\nmesh " + dir + "/lit.obj material m\n");
        int lit = 0, dark = 0, between = 0;
        for (int y = 0; y < fb.height; ++y)
            for (int x = 0; x < fb.width; ++x) {
                const Color c = fb.color[fb.index(x, y)];
                if (c.z == 1.0f && c.x == 0.0f) continue;  // background
                const float r = c.x;
                (r > 1.0f - 1e-5f ? lit : r < 1e-5f ? dark : between) += 1;
            }
        return std::array<int, 3>{lit, dark, between};
    };
    const std::array<int, 3> flat = shades("s off\n" + a + b), smooth = shades(a + b);
    CHECK(flat[0] > 800);
    CHECK(flat[1] > 400);
    CHECK(flat[2] == 0);
    CHECK(smooth[2] > 800);
}

TEST_CASE("OBJ flat faces whose parts' windings cancel (a bow-tie) take the normal of their plane, not +z") {
    // The bow-tie (0,0,0) (1,0,1) (1,0,0) (0,0,1) in the plane y = 0: its outline crosses
    // itself at (0.5, 0, 0.5), and its two triangles turn opposite ways with equal areas, so its
    // vector area is 0. Its fan triangles from the first corner: (1,0,1) x (1,0,0) = (0, 1, 0)
    // and (1,0,0) x (0,0,1) = (0, -1, 0), equally long; the first is taken. A face of no area
    // at all (its corners on a line) still takes +z.
    const std::string dir = testing::scratch_folder("obj-bow-tie");
    const auto normals = [&](const std::string& text) {
        testing::write_text(dir + "/f.obj", text);
        std::vector<glm::vec3> out;
        for (const Vertex& v : load_obj(dir + "/f.obj", [](const ObjMaterialInfo&) { return 0; }).vertices) out.push_back(v.normal);
        return out;
    };
    const std::string bow_tie = "v 0 0 0\nv 1 0 1\nv 1 0 0\nv 0 0 1\n";
    for (const std::string flat : {"s off\n", "s 0\n"}) {
        const std::vector<glm::vec3> n = normals(bow_tie + flat + "f 1 2 3 4\n");
        REQUIRE(n.size() == 4);
        for (const glm::vec3& v : n) CHECK(v == glm::vec3(0.0f, 1.0f, 0.0f));
    }
    // Scaled and turned: the bow-tie in the plane x = 2, corners (2, 0, 0) (2, 3, 3) (2, 0, 3)
    // (2, 3, 0), whose vector area is 0 as well: (0, 3, 3) x (0, 0, 3) = (9, 0, 0), so +x.
    for (const glm::vec3& v : normals("v 2 0 0\nv 2 3 3\nv 2 0 3\nv 2 3 0\ns off\nf 1 2 3 4\n")) CHECK(v == glm::vec3(1.0f, 0.0f, 0.0f));
    // A bow-tie across a tilted plane, with corners A, A + u + v, A + u, A + v that floats do
    // not hold exactly: its vector area is not quite 0 (rounding), but far below its fan's
    // area. Its plane's normal is u x v = (0.1, 0.2, 0.3) x (0.3, -0.1, 0.2) = (0.07, 0.07,
    // -0.07); its two fan triangles face either way, as long as each other but for rounding.
    for (const glm::dvec3 a : {glm::dvec3(0.0), glm::dvec3(10.1, 3.3, -7.7)}) {
        const auto corner = [&](double x, double y, double z) {
            return "v " + std::to_string(a.x + x) + " " + std::to_string(a.y + y) + " " + std::to_string(a.z + z) + "\n";
        };
        const std::vector<glm::vec3> n =
            normals(corner(0, 0, 0) + corner(0.4, 0.1, 0.5) + corner(0.1, 0.2, 0.3) + corner(0.3, -0.1, 0.2) + "s off\nf 1 2 3 4\n");
        REQUIRE(n.size() == 4);
        for (const glm::vec3& v : n) CHECK(std::fabs(glm::dot(glm::dvec3(v), glm::dvec3(1.0, 1.0, -1.0) / std::sqrt(3.0))) == doctest::Approx(1.0).epsilon(1e-5));
    }
    // Corners on a line: no plane, +z.
    for (const glm::vec3& v : normals("v 0 0 0\nv 1 1 0\nv 2 2 0\nv 3 3 0\ns off\nf 1 2 3 4\n")) CHECK(v == glm::vec3(0.0f, 0.0f, 1.0f));
    // Smoothed (no s line), the bow-tie adds nothing to its corners' sums: alone, they are +z
    // as before (a sum of 0 has no direction).
    for (const glm::vec3& v : normals(bow_tie + "f 1 2 3 4\n")) CHECK(v == glm::vec3(0.0f, 0.0f, 1.0f));
}

TEST_CASE("cull back on a mirrored object drops the faces facing away, as on the object itself") {
    // A cube seen from outside shows at most 3 faces: at least 3 (6 triangles) face away.
    // Culling them leaves the frame as it is without culling (the depth test hides them), with
    // or without a mirroring transform (scale -1 1 1 turns the winding over on screen).
    // Also at a scale of 1e-110 (the camera too), where the transform's determinant, 1e-330,
    // is below the smallest double.
    const std::string cube = testing::source_path("models/cube.obj");
    const auto frame = [&](const std::string& scale, const std::string& options, RenderStats& stats) {
        std::istringstream in("size 120 120\ncamera eye 1.5" + scale + " 1.2" + scale + " 2.5" + scale + " target 0 0 0 fov 45 near 0.1" +
                              scale + " far 100" + scale + "\nlight directional -0.5 -1 -0.4\n"
                              "material side color 0.9 0.3 0.3 lighting lambert\nmaterial cap color 0.3 0.3 0.9 lighting lambert\n"
                              "mesh " + cube + " scale 1" + scale + " " + options + "\n");
        const Scene scene = parse_scene(in, "cull.scene");
        return render(scene, RenderOptions{}, stats);
    };
    for (const std::string scale : {"", "e-110"})
    for (const std::string mirror : {"", "scale -1 1 1", "scale 1 -1 1 rotate 30 0 1 0", "scale -1 -1 -1"}) {
        CAPTURE(scale);
        CAPTURE(mirror);
        RenderStats all, culled;
        const Framebuffer plain = frame(scale, mirror, all), cut = frame(scale, mirror + " cull back", culled);
        CHECK(all.triangles_culled == 0);
        CHECK(culled.triangles_culled >= 6);
        int drawn = 0, differing = 0;
        for (std::size_t i = 0; i < plain.color.size(); ++i) {
            drawn += plain.drawn(i) ? 1 : 0;
            differing += (plain.color[i] != cut.color[i] || plain.drawn(i) != cut.drawn(i)) ? 1 : 0;
        }
        CHECK(drawn > 2000);
        CHECK(differing == 0);
    }
    // Cut by the near plane (clipped pieces): the cube mirrored by its transform, culled, is the
    // cube mirrored in its file (x negated, each face's corners in the other order), culled.
    const std::string dir = testing::scratch_folder("cull-mirrored");
    const std::string corners = "v -0.5 -0.5 -0.5\nv -0.5 -0.5 0.5\nv -0.5 0.5 -0.5\nv -0.5 0.5 0.5\n";
    const std::string faces = "f 6 5 7 8\nf 1 2 4 3\nf 4 8 7 3\nf 1 5 6 2\nf 2 6 8 4\nf 5 1 3 7\n";
    testing::write_text(dir + "/box.obj", corners + "v 0.5 -0.5 -0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 -0.5\nv 0.5 0.5 0.5\n" + faces);
    std::string mirrored_corners = "v 0.5 -0.5 -0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 -0.5\nv 0.5 0.5 0.5\n"
                                   "v -0.5 -0.5 -0.5\nv -0.5 -0.5 0.5\nv -0.5 0.5 -0.5\nv -0.5 0.5 0.5\n";
    testing::write_text(dir + "/mirror.obj", mirrored_corners + "f 8 7 5 6\nf 3 4 2 1\nf 3 7 8 4\nf 2 6 5 1\nf 4 8 6 2\nf 7 3 1 5\n");
    const auto near_frame = [&](const std::string& mesh, RenderStats& stats) {
        std::istringstream in("size 100 100\ncamera eye 0.2 0.3 0.9 target 0 0 0 fov 60 near 0.5\nlight directional -0.5 -1 -0.4\n"
                              "ambient 0.1 0.1 0.1\nmaterial m color 0.9 0.5 0.3 lighting lambert\nmesh " + mesh + " material m cull back\n");
        return render(parse_scene(in, "near.scene"), RenderOptions{}, stats);
    };
    RenderStats by_transform_stats, in_file_stats;
    const Framebuffer by_transform = near_frame(dir + "/box.obj scale -1 1 1", by_transform_stats);
    const Framebuffer in_file = near_frame(dir + "/mirror.obj", in_file_stats);
    CHECK(by_transform_stats.triangles_clipped > 0);
    CHECK(by_transform_stats.triangles_culled == in_file_stats.triangles_culled);
    int drawn = 0, differing = 0;
    for (std::size_t i = 0; i < by_transform.color.size(); ++i) {
        drawn += by_transform.drawn(i) ? 1 : 0;
        differing += (by_transform.drawn(i) != in_file.drawn(i) || glm::length(by_transform.color[i] - in_file.color[i]) > 1e-5f) ? 1 : 0;
    }
    CHECK(drawn > 1000);
    CHECK(differing == 0);
}

TEST_CASE("OBJ faces are split into k - 2 triangles that cover the face once, concave ones too, wherever the face lies") {
    // Property: the triangles of a face, each turning as the face does, whose areas add up to
    // the face's own (the shoelace formula, worked out here), cover it exactly once, where its
    // edges meet but never cross: a simple face, or one that touches itself (a hole joined by
    // a bridge, a corner it passes twice, a spike of no width).
    const std::string dir = testing::scratch_folder("obj-concave");
    struct Face {
        const char* name;
        std::vector<glm::dvec2> corners;  // counter-clockwise, in the plane z = 0
    };
    const std::vector<Face> faces = {
        {"L", {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}},
        {"U", {{0, 0}, {3, 0}, {3, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}},
        {"dart", {{0.5, -1}, {0, 1.5}, {-0.5, -1}, {0, -0.8}}},  // concave at its last corner
        {"dart turned", {{0, -0.8}, {0.5, -1}, {0, 1.5}, {-0.5, -1}}},
        {"dart turned twice", {{-0.5, -1}, {0, -0.8}, {0.5, -1}, {0, 1.5}}},
        {"dart turned thrice", {{0, 1.5}, {-0.5, -1}, {0, -0.8}, {0.5, -1}}},
        // two squares that touch at a corner (1, 1), written as one face through it twice
        {"pinch", {{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {1, 2}, {1, 1}, {0, 1}}},
        // a square with a spike of no width out to (3, 1) and back
        {"spike", {{0, 0}, {2, 0}, {2, 1}, {3, 1}, {2, 1}, {2, 2}, {0, 2}}},
        {"pentagon", {{0, 0}, {2, 0}, {2.5, 1}, {1, 2}, {-0.5, 1}}},
        {"comb", {{0, 0}, {5, 0}, {5, 3}, {4, 3}, {4, 1}, {3, 1}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}}},
        // a hole (2, 5) (2, 6) (6, 5) (5, 4), joined to the outline by a bridge (2, 4)-(2, 5)
        // that lines up with an edge of each (a review's fuzzer found it covered wrongly)
        {"bridged hole", {{8, 5}, {1, 8}, {2, 4}, {2, 5}, {2, 6}, {6, 5}, {5, 4}, {2, 5}, {2, 4}, {2, 2}}},
        // two holes joined by bridges, and spikes of no width into them (from the same fuzzer)
        {"holes and spikes", {{11, 6}, {13, 12}, {7, 8}, {11, 8}, {9, 4}, {7, 8}, {13, 12}, {2, 15}, {5, 1},
                              {5, 3}, {5, 9}, {4, 13}, {3, 14}, {4, 13}, {5, 11}, {5, 9}, {5, 3}, {8, 13},
                              {5, 1}, {2, 15}, {3, 1}, {1, 14}, {0, 5}, {1, 14}, {3, 1}, {5, 0}, {14, 7}}},
        // two squares joined by a bent corridor of no width; and the same with a corner (9, 7)
        // on the row through the centroid of the wedge outside the bend (from a second review)
        {"corridor", {{0, 0}, {2, 0}, {2, 2}, {5, 3}, {8, 2}, {10, 2}, {10, 4}, {8, 4}, {8, 2}, {5, 3}, {2, 2}, {0, 2}}},
        {"corridor row", {{0, 0}, {2, 0}, {2, 6}, {5, 9}, {8, 6}, {10, 6}, {10, 12}, {8, 12}, {9, 7}, {8, 6}, {5, 9}, {2, 6}, {0, 6}}},
    };
    // The face in the plane z = 0, x = 0 or y = 0 (axis: the one it faces; its corners' (x, y)
    // go to the plane's axes in the order that keeps it counter-clockwise seen from there).
    for (const Face& face : faces)
        for (const glm::dvec2 offset : {glm::dvec2(0, 0), glm::dvec2(-2.5, -0.5), glm::dvec2(-1.5, 3), glm::dvec2(100, -40)})
            for (const bool mirrored : {false, true})  // mirrored: the corners in the other order (clockwise)
                for (const int axis : {2, 0, 1}) {
                CAPTURE(std::string(face.name));
                CAPTURE(offset.x);
                CAPTURE(mirrored);
                CAPTURE(axis);
                std::string obj, f = "f";
                const std::size_t n = face.corners.size();
                double shoelace = 0.0;
                // (the corners as the file's floats, written in full)
                const auto corner = [&](std::size_t i) { return glm::dvec2(glm::vec2(face.corners[i % n] + offset)); };
                for (std::size_t i = 0; i < n; ++i) {
                    const glm::dvec2 a = corner(i), b = corner(i + 1);
                    char line[80];
                    glm::dvec3 p(0.0);
                    p[(axis + 1) % 3] = a.x, p[(axis + 2) % 3] = a.y;
                    std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
                    obj += line;
                    f += " " + std::to_string(mirrored ? n - i : i + 1);
                    shoelace += a.x * b.y - b.x * a.y;
                }
                testing::write_text(dir + "/face.obj", obj + f + "\n");
                const Mesh mesh = load_obj(dir + "/face.obj", [](const ObjMaterialInfo&) { return 0; });
                REQUIRE(mesh.triangles.size() == n - 2);
                double total = 0.0;
                for (const auto& t : mesh.triangles) {
                    const glm::dvec3 a(mesh.vertices[t[0]].position), b(mesh.vertices[t[1]].position), c(mesh.vertices[t[2]].position);
                    const double area = glm::cross(b - a, c - a)[axis];  // twice the signed area, seen from the axis
                    CHECK((mirrored ? -area : area) >= -1e-9);       // turns as the face does
                    total += std::fabs(area);  // (signed areas would add up to the face's whatever the split)
                }
                CHECK(total == doctest::Approx(std::fabs(shoelace)).epsilon(1e-9));
            }
    // Faces of 255 to 300 corners (tinyobjloader keeps a face's count in a byte: 256 read as
    // 0), a regular polygon of radius 1: k - 2 triangles, of area k sin(2 pi / k) / 2 in all.
    for (const int k : {255, 256, 257, 300}) {
        CAPTURE(k);
        std::string obj, f = "f";
        for (int i = 0; i < k; ++i) {
            char line[80];
            std::snprintf(line, sizeof line, "v %.9g %.9g 0\n", std::cos(2 * M_PI * i / k), std::sin(2 * M_PI * i / k));
            obj += line;
            f += " " + std::to_string(i + 1);
        }
        testing::write_text(dir + "/round.obj", obj + f + "\nf 1 2 3\n");
        const Mesh mesh = load_obj(dir + "/round.obj", [](const ObjMaterialInfo&) { return 0; });
        REQUIRE(mesh.triangles.size() == std::size_t(k - 2 + 1));
        double total = 0.0;
        for (std::size_t t = 0; t + 1 < mesh.triangles.size(); ++t) {
            const auto& tri = mesh.triangles[t];
            const glm::dvec3 a(mesh.vertices[tri[0]].position), b(mesh.vertices[tri[1]].position), c(mesh.vertices[tri[2]].position);
            CHECK(glm::cross(b - a, c - a).z >= -1e-9);
            total += glm::cross(b - a, c - a).z / 2.0;
        }
        CHECK(total == doctest::Approx(k * std::sin(2 * M_PI / k) / 2).epsilon(1e-5));
    }
    // Rendered: the L of a review (corners from (-2.5, -0.5)), seen from the front. Its lower
    // left arm holds world point (-2.3, -0.3), at pixel (34, 85): drawn; its notch (-1, 1) is
    // not, at pixel (70, 49) ((x + 1.5) / (4 tan 25) * 60 + 60, (0.5 - y) / (4 tan 25) * 60 + 60).
    testing::write_text(dir + "/L.obj", "v -2.5 -0.5 0\nv -0.5 -0.5 0\nv -0.5 0.5 0\nv -1.5 0.5 0\nv -1.5 1.5 0\nv -2.5 1.5 0\nf 1 2 3 4 5 6\n");
    std::istringstream in("size 120 120\ncamera eye -1.5 0.5 4 target -1.5 0.5 0 up 0 1 0 fov 50\nmesh " + dir + "/L.obj\n");
    RenderStats stats;
    const Framebuffer fb = render(parse_scene(in, "L.scene"), RenderOptions{}, stats);
    CHECK(fb.drawn(fb.index(34, 85)));
    CHECK_FALSE(fb.drawn(fb.index(70, 49)));
    CHECK(stats.triangles_in == 4);
}

TEST_CASE("OBJ faces that outline a maze of unit cells (holes joined by bridges, walls of no width) are covered once") {
    // Random sets of unit cells on a 6 x 6 grid, each joined by a random spanning tree of its
    // neighbours: the wall between two neighbours not joined in the tree stays. The face is
    // the walk around the tree's cells with them on the left, so it passes each remaining inner
    // wall twice (a spike or a bridge of no width, along a line of the grid that other edges
    // lie on too), joins every hole in the cells to the outline, and passes some grid points
    // several times. It winds once around each cell and nowhere else, so its area is the
    // number of cells, worked out here without the face. Straight corners are kept or dropped
    // at random. Then, whatever the split: k - 2 triangles, none turning against the face,
    // their areas adding up to the cell count, and every cell's centre covered by exactly one.
    const std::string dir = testing::scratch_folder("obj-maze");
    std::mt19937 random(20261129);
    const auto chance = [&](double p) { return std::uniform_real_distribution<double>(0.0, 1.0)(random) < p; };
    constexpr int grid = 6;
    // Sides of cell (x, y), counter-clockwise: 0 bottom, 1 right, 2 top, 3 left; side s starts
    // at corner s of (x, y) (x + 1, y) (x + 1, y + 1) (x, y + 1).
    const int step_x[4] = {0, 1, 0, -1}, step_y[4] = {-1, 0, 1, 0};
    const int corner_x[4] = {0, 1, 1, 0}, corner_y[4] = {0, 0, 1, 1};
    struct MazeFace {
        std::vector<glm::ivec2> corners;
        int cells = 0;
        std::vector<glm::ivec2> cell_list;
        int axis = 2;
        bool mirrored = false;
    };
    std::vector<MazeFace> faces;
    while (faces.size() < 300) {
        bool in[grid][grid] = {}, joined[grid][grid][4] = {}, seen[grid][grid] = {};
        for (auto& row : in)
            for (bool& cell : row) cell = chance(0.65);
        const int sx = int(random() % grid), sy = int(random() % grid);
        if (!in[sx][sy]) continue;
        // A random spanning tree of the cells reachable from (sx, sy): a search that takes a
        // random cell off its frontier each time.
        MazeFace face;
        std::vector<glm::ivec2> frontier{{sx, sy}};
        seen[sx][sy] = true;
        while (!frontier.empty()) {
            const std::size_t pick = random() % frontier.size();
            const glm::ivec2 c = frontier[pick];
            frontier.erase(frontier.begin() + std::ptrdiff_t(pick));
            face.cell_list.push_back(c);
            for (int s = 0; s < 4; ++s) {
                const int nx = c.x + step_x[s], ny = c.y + step_y[s];
                if (nx < 0 || ny < 0 || nx >= grid || ny >= grid || !in[nx][ny] || seen[nx][ny]) continue;
                seen[nx][ny] = true, joined[c.x][c.y][s] = joined[nx][ny][(s + 2) % 4] = true;
                frontier.push_back({nx, ny});
            }
        }
        face.cells = int(face.cell_list.size());
        if (face.cells < 2) continue;
        // The walk: from side s of cell c, the next side counter-clockwise is s + 1; where it is
        // joined to a neighbour, the walk goes on in the neighbour, after the shared side.
        // (from a walled side: some cell has one, the leftmost cell its left side)
        glm::ivec2 c = face.cell_list[0];
        int s = 0;
        for (const glm::ivec2 cell : face.cell_list) {
            for (s = 0; s < 4 && joined[cell.x][cell.y][s]; ++s) {
            }
            if (s < 4) {
                c = cell;
                break;
            }
        }
        const glm::ivec2 start = c;
        const int start_side = s;
        std::vector<glm::ivec2> walk;
        do {
            int next = (s + 1) % 4;
            while (joined[c.x][c.y][next]) {  // into the neighbour across side `next`
                c += glm::ivec2(step_x[next], step_y[next]);
                next = (next + 2 + 1) % 4;
            }
            s = next;
            walk.push_back(c + glm::ivec2(corner_x[s], corner_y[s]));  // where side s starts
        } while (!(c == start && s == start_side));
        for (std::size_t i = 0; i < walk.size(); ++i) {
            const glm::ivec2 a = walk[(i + walk.size() - 1) % walk.size()], b = walk[i], d = walk[(i + 1) % walk.size()];
            const glm::ivec2 in_dir = b - a, out_dir = d - b;
            const bool straight = in_dir == out_dir;
            if (!(straight && chance(0.6))) face.corners.push_back(b);
        }
        if (face.corners.size() < 5 || face.corners.size() > 256) continue;
        face.axis = int(random() % 3), face.mirrored = chance(0.5);
        faces.push_back(face);
    }
    // One file of all the faces, each in its plane (offset by 100 along the plane's axes).
    std::string obj, lines;
    std::size_t vertices = 0;
    for (const MazeFace& face : faces) {
        const std::size_t n = face.corners.size();
        std::string f = "f";
        for (std::size_t i = 0; i < n; ++i) {
            int p[3] = {0, 0, 0};
            p[(face.axis + 1) % 3] = face.corners[i].x + 100, p[(face.axis + 2) % 3] = face.corners[i].y - 100;
            obj += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
            f += " " + std::to_string(vertices + (face.mirrored ? n - i : i + 1));
        }
        vertices += n;
        lines += f + "\n";
    }
    testing::write_text(dir + "/maze.obj", obj + lines);
    const Mesh mesh = load_obj(dir + "/maze.obj", [](const ObjMaterialInfo&) { return 0; });
    std::size_t expected = 0;
    for (const MazeFace& face : faces) expected += face.corners.size() - 2;
    REQUIRE(mesh.triangles.size() == expected);
    std::size_t first = 0;
    int wrong_faces = 0;
    for (std::size_t fi = 0; fi < faces.size(); ++fi) {
        const MazeFace& face = faces[fi];
        const std::size_t count = face.corners.size() - 2;
        // Each triangle in the face's grid coordinates, twice its signed area turned so that the
        // face's own winding is positive.
        std::vector<std::array<glm::dvec2, 3>> triangles;
        double total = 0.0;
        bool against = false;
        for (std::size_t t = first; t < first + count; ++t) {
            std::array<glm::dvec2, 3> tri;
            for (int k = 0; k < 3; ++k) {
                const glm::dvec3 p(mesh.vertices[mesh.triangles[t][k]].position);
                tri[k] = {p[(face.axis + 1) % 3] - 100, p[(face.axis + 2) % 3] + 100};
            }
            const double area = (tri[1].x - tri[0].x) * (tri[2].y - tri[0].y) - (tri[1].y - tri[0].y) * (tri[2].x - tri[0].x);
            const double turned = face.mirrored ? -area : area;
            against = against || turned < 0.0;
            total += turned;
            triangles.push_back(tri);
        }
        first += count;
        // Every cell's centre in exactly one triangle, strictly inside it. (A diagonal between
        // grid points can pass through a cell's centre, so the point tried is nudged by 1/64 and
        // 1/128 of a cell: no line through two grid points of the 6 x 6 grid passes through it.)
        int miscovered = 0;
        for (const glm::ivec2 cell : face.cell_list) {
            const glm::dvec2 point(cell.x + 0.5 + 1.0 / 64, cell.y + 0.5 + 1.0 / 128);
            int covering = 0;
            for (const auto& tri : triangles) {
                double sides[3];
                for (int k = 0; k < 3; ++k) {
                    const glm::dvec2 a = tri[k], b = tri[(k + 1) % 3];
                    sides[k] = (b.x - a.x) * (point.y - a.y) - (b.y - a.y) * (point.x - a.x);
                }
                if ((sides[0] > 0 && sides[1] > 0 && sides[2] > 0) || (sides[0] < 0 && sides[1] < 0 && sides[2] < 0)) ++covering;
            }
            if (covering != 1) ++miscovered;
        }
        if (against || total != 2.0 * face.cells || miscovered != 0) {
            ++wrong_faces;
            if (wrong_faces <= 3) {
                std::string corners;
                for (const glm::ivec2 p : face.corners) corners += " (" + std::to_string(p.x) + "," + std::to_string(p.y) + ")";
                CAPTURE(corners);
                CAPTURE(face.axis);
                CAPTURE(face.mirrored);
                CHECK_FALSE(against);
                CHECK(total == 2.0 * face.cells);
                CHECK(miscovered == 0);
            }
        }
    }
    CHECK(wrong_faces == 0);
}
