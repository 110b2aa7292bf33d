// Intermediate (two-stage) mapping (texture/intermediate.h and a material's `mapping`):
// (u, v) of hand-worked points for the planar, cylindrical and spherical surfaces, their
// derivatives, a cylinder mapped cylindrically against its own parameterization, messages.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "helpers.h"
#include "texr/texture/intermediate.h"

using namespace texr;
using namespace texr::testing;

TEST_CASE("planar, cylindrical and spherical intermediate surfaces map hand-worked points as the slides say") {
    IntermediateMapping m;
    m.center = {1, 2, 3};
    // planar, axis z (x' = x, y' = z x x' = y), size 0.5: u = x' / 0.5, v = y' / 0.5
    m.kind = Intermediate::planar, m.axis = {0, 0, 1}, m.reference = {1, 0, 0}, m.size = 0.5;
    glm::dvec2 uv = intermediate_uv(m, {1.5, 2.25, 9});
    CHECK(uv.x == doctest::Approx(1.0));
    CHECK(uv.y == doctest::Approx(0.5));
    // cylindrical, axis y (x' = x, y' = y x x = -z), height 2: u = phi / 2 pi, v = z' / 2
    m.kind = Intermediate::cylindrical, m.axis = {0, 1, 0}, m.reference = {1, 0, 0}, m.size = 2.0;
    uv = intermediate_uv(m, m.center + glm::dvec3(0, 1, -1));  // y' = 1: phi = pi / 2
    CHECK(uv.x == doctest::Approx(0.25));
    CHECK(uv.y == doctest::Approx(0.5));
    uv = intermediate_uv(m, m.center + glm::dvec3(-3, 0, 0));  // x' < 0: phi = pi
    CHECK(uv.x == doctest::Approx(0.5));
    uv = intermediate_uv(m, m.center + glm::dvec3(0, 0, 1));  // y' = -1: phi = 3 pi / 2
    CHECK(uv.x == doctest::Approx(0.75));
    // spherical, the same frame: v = 1 - theta / pi, theta from +z' (here +y)
    m.kind = Intermediate::spherical;
    CHECK(intermediate_uv(m, m.center + glm::dvec3(0, 4, 0)).y == doctest::Approx(1.0));
    CHECK(intermediate_uv(m, m.center + glm::dvec3(0, -4, 0)).y == doctest::Approx(0.0));
    uv = intermediate_uv(m, m.center + glm::dvec3(2, 0, 0));
    CHECK(uv.x == doctest::Approx(0.0));
    CHECK(uv.y == doctest::Approx(0.5));
    uv = intermediate_uv(m, m.center + glm::dvec3(1, 1, -1));  // phi = pi / 4, theta = acos(1 / sqrt 3)
    CHECK(uv.x == doctest::Approx(0.125));
    CHECK(uv.y == doctest::Approx(1 - std::acos(1 / std::sqrt(3.0)) / 3.14159265358979323846));
    // Derivatives: planar ones exactly dp . x' / S; cylindrical ones across the seam (phi just
    // below 2 pi) finite, d phi / d(y') = 1 / r at the seam: du = dy' / (2 pi r).
    m.kind = Intermediate::planar, m.axis = {0, 0, 1}, m.size = 0.5;
    UVDerivatives d = intermediate_derivatives(m, {1.2, 2.1, 0}, {0.1, 0.02, 0.5}, {-0.03, 0.2, 0});
    CHECK(d.dudx == doctest::Approx(0.2));
    CHECK(d.dvdx == doctest::Approx(0.04));
    CHECK(d.dudy == doctest::Approx(-0.06));
    CHECK(d.dvdy == doctest::Approx(0.4));
    m.kind = Intermediate::cylindrical, m.axis = {0, 1, 0}, m.size = 2.0;
    d = intermediate_derivatives(m, m.center + glm::dvec3(2, 0, 1e-9), {0, 0, -0.01}, {0, 0.01, 0});  // y' = -z
    CHECK(d.dudx == doctest::Approx(0.01 / (2 * 3.14159265358979323846 * 2)).epsilon(1e-4));
    CHECK(d.dvdy == doctest::Approx(0.005));
}

TEST_CASE("a cylinder mapped cylindrically about its own axis reads what its own (u, v) read") {
    // The parametric cylinder's u = phi / 2 pi and v = z / H are the cylindrical surface's: the
    // two frames differ only where the mesh's interpolated (u, v) and the exact mapping fall
    // on two sides of a texel edge of the 4x2 nearest texture.
    const std::string dir = scratch_folder("intermediate");
    std::string ppm = "P6\n4 2\n255\n";
    for (int k = 0; k < 8; ++k)
        for (int bit = 0; bit < 3; ++bit) ppm += char((k >> bit) & 1 ? 255 : 0);
    write_text(dir + "/t.ppm", ppm);
    const std::string head = "size 96 72\ncamera eye 2.5 1.2 2 target 0 0 0.7 up 0 0 1 fov 60\ntexture t file t.ppm filter nearest\n";
    write_text(dir + "/own.scene", head + "material m texture t\ncylinder 1 1.5 segments 512 material m\n");
    write_text(dir + "/mapped.scene",
               head + "material m texture t mapping cylindrical mapping_axis 0 0 1 mapping_size 1.5\ncylinder 1 1.5 segments 512 material m\n");
    REQUIRE(run_texr("render " + dir + "/own.scene -o " + dir + "/own.ppm").exit_code == 0);
    REQUIRE(run_texr("render " + dir + "/mapped.scene -o " + dir + "/mapped.ppm").exit_code == 0);
    const std::string a = ppm_pixels(dir + "/own.ppm", 96, 72), b = ppm_pixels(dir + "/mapped.ppm", 96, 72);
    REQUIRE(a.size() == 96 * 72 * 3);
    int covered = 0, differ = 0;
    for (std::size_t i = 0; i < a.size(); i += 3) {
        const bool background = a[i] == 0 && a[i + 1] == 0 && a[i + 2] == 0 && b[i] == 0 && b[i + 1] == 0 && b[i + 2] == 0;
        covered += !background;
        differ += a.compare(i, 3, b, i, 3) != 0;
    }
    CHECK(covered > 800);
    CHECK(differ * 100 < covered);  // under 1%: texel edges only
    // explain tells the mapping
    const RunResult r = run_texr("explain " + dir + "/mapped.scene 48 36");
    CHECK(r.output.find("on a cylindrical intermediate surface (two-stage mapping):\n") != std::string::npos);
}

TEST_CASE("intermediate mapping in scene files: options and messages") {
    const std::string dir = scratch_folder("intermediate-scenes");
    const std::string head = "size 32 24\ncamera eye 0 0 3 target 0 0 0\ntexture t procedural checker\n";
    for (const auto& [line, message] : std::vector<std::pair<std::string, std::string>>{
             {"material m texture t mapping conical", "unknown intermediate mapping 'conical' (expected one of: cylindrical, planar, spherical)"},
             {"material m texture t mapping_size 2", "'mapping_size' belongs with 'mapping planar|cylindrical|spherical'"},
             {"material m mapping planar", "material 'm' has no texture to map ('texture NAME')"},
             {"material m texture t mapping planar mapping_axis 0 0 0",
              "the intermediate surface's axis must not be zero (nor beyond a double's range)"},
             {"projector p\nmaterial m texture t projector p mapping planar",
              "a material's texture is either thrown by a projector or mapped, not both"},
         }) {
        CAPTURE(line);
        write_text(dir + "/bad.scene", head + line + "\ntriangle material m v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n");
        const RunResult r = run_texr("render " + dir + "/bad.scene -o " + dir + "/bad.png");
        CHECK(r.exit_code == 1);
        CHECK(r.output.find(message) != std::string::npos);
    }
}

TEST_CASE("mapped and projected textures give the filters a footprint: a receding floor against its supersampled truth") {
    // The checker image on a floor, trilinear, (u, v) from a planar mapping or from a parallel
    // projector above it, against 8x8 supersampling (`texr compare`'s PSNR over the frame).
    // Measured: 24.37 and 32.38 dB; with the derivatives left at 0 (the base level
    // everywhere: aliasing) 14.56 and 26.78 dB.
    const std::string dir = scratch_folder("mapped-footprint");
    const std::string head = "size 128 96\ncamera eye 0 1 0 target 0 0.75 -4 fov 60\ntexture t file " +
                             source_path("models/textures/checker.png") + " filter trilinear\n";
    const std::string quad = " v -50 0 5 0 0 v 50 0 5 0 0 v 50 0 -95 0 0 v -50 0 -95 0 0\n";
    for (const auto& [material, least] : {std::pair<std::string, double>{"mapping planar mapping_axis 0 1 0 mapping_size 2", 20.0},
                                          std::pair<std::string, double>{"projector p", 29.5}}) {
        CAPTURE(material);
        write_text(dir + "/s.scene", head + "projector p eye 0 30 0 target 0 0 -0.0001 parallel 200\nmaterial m texture t " + material +
                                         "\nquad material m" + quad);
        REQUIRE(run_texr("render " + dir + "/s.scene -o " + dir + "/s.ppm").exit_code == 0);
        REQUIRE(run_texr("render " + dir + "/s.scene -o " + dir + "/truth.ppm --spp 8").exit_code == 0);
        const RunResult c = run_texr("compare " + dir + "/s.ppm " + dir + "/truth.ppm");
        const std::size_t at = c.output.find("PSNR ");
        REQUIRE(at != std::string::npos);
        CHECK(std::stod(c.output.substr(at + 5)) > least);
    }
}
