// The lecture's parametric surfaces (sphere, cylinder, disc commands): every vertex at the
// slides' p(u, v) with its (u, v), triangles facing out, and the (u, v) a pixel reads close
// to the parameterization inverted at the pixel's surface point.
#include <doctest/doctest.h>

#include <cmath>
#include <sstream>
#include <string>

#include <glm/geometric.hpp>

#include "helpers.h"

using namespace texr;
using namespace texr::testing;

namespace {

constexpr double pi = 3.14159265358979323846;

Scene parsed(const std::string& text) {
    std::istringstream in(text);
    return parse_scene(in, "test.scene");
}

}  // namespace

TEST_CASE("sphere, cylinder and disc vertices lie at the slides' p(u, v), and their triangles face out") {
    struct Case {
        std::string line;
        glm::dvec3 (*p)(double u, double v);
        int vertices, triangles;
    };
    const Case cases[] = {
        // sphere 2, 16 segments: 17 x 9 vertices; the rows at the poles give one triangle per cell.
        // theta = pi (1 - v): texr's v counts from an image's bottom row.
        {"sphere 2 segments 16",
         [](double u, double v) {
             const double t = pi * (1 - v);
             return 2.0 * glm::dvec3(std::sin(t) * std::cos(2 * pi * u), std::sin(t) * std::sin(2 * pi * u), std::cos(t));
         },
         17 * 9, 16 * 8 * 2 - 2 * 16},
        {"cylinder 0.5 3 segments 12", [](double u, double v) { return glm::dvec3(0.5 * std::cos(2 * pi * u), 0.5 * std::sin(2 * pi * u), 3 * v); },
         13 * 2, 12 * 2},
        // disc 1.5, 16 segments: 4 rings; the centre's cells give one triangle each
        {"disc 1.5 segments 16",
         [](double u, double v) { return glm::dvec3(1.5 * v * std::cos(2 * pi * u), 1.5 * v * std::sin(2 * pi * u), 0.0); },
         17 * 5, 16 * 4 * 2 - 16},
    };
    for (const Case& c : cases) {
        CAPTURE(c.line);
        const Scene scene = parsed("size 32 24\n" + c.line + "\n");
        REQUIRE(scene.meshes.size() == 1);
        const Mesh& mesh = scene.meshes[0];
        CHECK(int(mesh.vertices.size()) == c.vertices);
        CHECK(int(mesh.triangles.size()) == c.triangles);
        for (const Vertex& v : mesh.vertices) {
            const glm::dvec3 want = c.p(v.uv.x, v.uv.y);
            CHECK(glm::length(glm::dvec3(v.position) - want) < 1e-6);
        }
        // Each triangle's winding agrees with its vertices' normals (outward).
        int inward = 0;
        for (const auto& t : mesh.triangles) {
            const glm::dvec3 a(mesh.vertices[t[0]].position), b(mesh.vertices[t[1]].position), d(mesh.vertices[t[2]].position);
            const glm::dvec3 n(mesh.vertices[t[0]].normal);
            inward += glm::dot(glm::cross(b - a, d - a), n) <= 0.0;
        }
        CHECK(inward == 0);
    }
}

TEST_CASE("a pixel on a sphere, a cylinder or a disc reads close to the parameterization inverted at its surface point") {
    // explain gives the (u, v) the pixel reads and the surface point; the slides' p inverted
    // there: sphere u = atan2(y, x) / 2 pi, v = 1 - acos(z / r) / pi; cylinder
    // u = atan2(y, x) / 2 pi, v = z / H; disc u = atan2(y, x) / 2 pi, v = |(x, y)| / R (u in [0, 1)).
    const std::string dir = scratch_folder("parametric");
    struct Case {
        std::string line;
        int x, y;
        glm::dvec2 (*inverse)(const glm::dvec3& p);
        std::string camera = "camera eye 0.8 -0.6 4 target 0 0 0.5 up 0 1 0 fov 60";
    };
    const Case cases[] = {
        {"sphere 1 segments 256", 40, 20,
         [](const glm::dvec3& p) {
             const double u = std::atan2(p.y, p.x) / (2 * pi);
             return glm::dvec2(u < 0 ? u + 1 : u, 1 - std::acos(p.z / glm::length(p)) / pi);
         }},
        {"cylinder 1 2 segments 256", 36, 20,
         [](const glm::dvec3& p) {
             const double u = std::atan2(p.y, p.x) / (2 * pi);
             return glm::dvec2(u < 0 ? u + 1 : u, p.z / 2.0);
         },
         "camera eye 4 1.5 1.2 target 0 0 1 up 0 0 1 fov 60"},
        {"disc 1.5 segments 256", 38, 26,
         [](const glm::dvec3& p) {
             const double u = std::atan2(p.y, p.x) / (2 * pi);
             return glm::dvec2(u < 0 ? u + 1 : u, glm::length(glm::dvec2(p.x, p.y)) / 1.5);
         }},
    };
    for (const Case& c : cases) {
        CAPTURE(c.line);
        // The camera looks down on the object from +z, slightly to the side (at the cylinder's
        // side from beside it); a solid texture
        // makes explain print the world position the pixel read (the object is untransformed:
        // world = object space), and it prints (u, v) from the plane equations anyway.
        write_text(dir + "/p.scene", "size 64 48\n" + c.camera + "\n"
                                     "texture t procedural checker scale 8 solid on\nmaterial m texture t\n" + c.line + " material m\n");
        const RunResult r = run_texr("explain " + dir + "/p.scene " + std::to_string(c.x) + " " + std::to_string(c.y));
        REQUIRE(r.exit_code == 0);
        CAPTURE(r.output);
        double u = 0, v = 0;
        const std::size_t at = r.output.find("    u = u'/q = ");
        REQUIRE(at != std::string::npos);
        REQUIRE(std::sscanf(r.output.c_str() + at, "    u = u'/q = %lf   v = v'/q = %lf", &u, &v) == 2);
        const std::size_t w = r.output.find("(stepped along the row): (");
        REQUIRE(w != std::string::npos);
        glm::dvec3 p;
        REQUIRE(std::sscanf(r.output.c_str() + w, "(stepped along the row): (%lf, %lf, %lf)", &p.x, &p.y, &p.z) == 3);
        const glm::dvec2 want = c.inverse(p);
        // A 256-segment mesh reads within about 1e-4 of the exact (u, v).
        CHECK(std::fabs(u - want.x) < 2e-3);
        CHECK(std::fabs(v - want.y) < 2e-3);
    }
}

TEST_CASE("parametric surfaces in scene files: sizes, segments, options") {
    const std::string dir = scratch_folder("parametric-scenes");
    for (const auto& [line, message] : std::vector<std::pair<std::string, std::string>>{
             {"sphere 0", "the sphere's radius must be above 0 and at most 1e18"},
             {"cylinder 1 -2", "the cylinder's height must be above 0 and at most 1e18"},
             {"disc 1 segments 7", "segments must be a whole number from 8 to 1024"},
             {"sphere 1 segments 2048", "segments must be a whole number from 8 to 1024"},
             {"sphere 1 segments 8 segments 16", "'segments' is given a second time in this 'sphere' command (first on line 2): give it once"},
             {"disc 1 wedge 3", "unknown disc option 'wedge' (expected segments, material, cull, translate, rotate or scale)"},
             {"cylinder 1", "expected the cylinder's height after '1', found the end of the line"},
         }) {
        CAPTURE(line);
        write_text(dir + "/bad.scene", "size 32 24\n" + line + "\n");
        const RunResult r = run_texr("render " + dir + "/bad.scene -o " + dir + "/bad.png");
        CHECK(r.exit_code == 1);
        CHECK(r.output == "texr: " + dir + "/bad.scene:2: " + message + "\n");
    }
}

TEST_CASE("an image on the sphere reads left to right and bottom to top from outside, not mirrored") {
    // Eight colours in a 4x2 image (nearest): texel (i, row from the top j) has colour 4 j + i
    // (bit 0 red, 1 green, 2 blue). Seen from (0, -3, 0) with z up, the sphere shows u from
    // about 0.5 (left edge) to 1 (right edge): columns 2 and 3; its upper half is the image's
    // top row.
    const std::string dir = scratch_folder("parametric-orientation");
    std::string ppm = "P6\n4 2\n255\n";
    for (int k = 0; k < 8; ++k)
        for (int bit = 0; bit < 3; ++bit) ppm += char((k >> bit) & 1 ? 255 : 0);
    write_text(dir + "/t.ppm", ppm);
    write_text(dir + "/s.scene", "size 64 64\ncamera eye 0 -3 0 target 0 0 0 up 0 0 1 fov 45\ntexture t file t.ppm filter nearest\n"
                                 "material m texture t\nsphere 1 segments 128 material m\n");
    REQUIRE(run_texr("render " + dir + "/s.scene -o " + dir + "/s.ppm").exit_code == 0);
    const std::string pixels = ppm_pixels(dir + "/s.ppm", 64, 64);
    REQUIRE(pixels.size() == 64 * 64 * 3);
    const auto colour = [&](int x, int y) {
        int k = 0;
        for (int bit = 0; bit < 3; ++bit) k |= (std::uint8_t(pixels[3 * std::size_t(y * 64 + x) + std::size_t(bit)]) == 255 ? 1 : 0) << bit;
        return k;
    };
    CHECK(colour(24, 24) == 2);      // left, top row: column 2
    CHECK(colour(40, 24) == 3);      // right, top row: column 3
    CHECK(colour(24, 40) == 4 + 2);  // left, bottom row
    CHECK(colour(40, 40) == 4 + 3);  // right, bottom row
}
