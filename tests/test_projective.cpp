// Projective textures (texture/projective.h and the `projector` command): where a projector
// throws (u, v) at hand-worked points, its derivatives against differences, and frames whose
// every pixel's texel is worked out from the surface point.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "helpers.h"
#include "texr/texture/projective.h"

using namespace texr;
using namespace texr::testing;

namespace {

Projector parsed_projector(const std::string& line) {
    std::istringstream in("size 8 8\n" + line + "\ntriangle v 0 0 0 0 0 v 1 0 0 1 0 v 0 1 0 0 1\n");
    const Scene scene = parse_scene(in, "test.scene");
    REQUIRE(scene.projectors.size() == 1);
    return scene.projectors[0];
}

}  // namespace

TEST_CASE("a projector throws (u, v) = ((c.x / c.w + 1) / 2, (c.y / c.w + 1) / 2): perspective and parallel, by hand") {
    // At distance 5 along -z, 90 degrees: tan 45 = 1, so x = 1 is 1/5 of the half-width.
    const Projector p = parsed_projector("projector p eye 0 0 5 target 0 0 0 fov 90");
    const glm::dvec3 none(0.0);
    ProjectedUV t = project(p, {0, 0, 0}, none, none);
    CHECK(t.ahead);
    CHECK(t.u == doctest::Approx(0.5));
    CHECK(t.v == doctest::Approx(0.5));
    t = project(p, {1, 0, 0}, none, none);
    CHECK(t.u == doctest::Approx(0.6));
    t = project(p, {0, 2.5, 0}, none, none);
    CHECK(t.v == doctest::Approx(0.75));
    t = project(p, {1, 1, 3}, none, none);  // distance 2: 1/2 of the half-width
    CHECK(t.u == doctest::Approx(0.75));
    CHECK(t.v == doctest::Approx(0.75));
    CHECK_FALSE(project(p, {0, 0, 6}, none, none).ahead);  // behind
    // aspect 2: the width spans twice the height
    const Projector wide = parsed_projector("projector p eye 0 0 5 target 0 0 0 fov 90 aspect 2");
    CHECK(project(wide, {1, 0, 0}, none, none).u == doctest::Approx(0.55));
    // parallel, 4 units high: x = 1 is half the half-height
    const Projector parallel = parsed_projector("projector p eye 0 0 5 target 0 0 0 parallel 4");
    t = project(parallel, {1, -1, -20}, none, none);
    CHECK(t.u == doctest::Approx(0.75));
    CHECK(t.v == doctest::Approx(0.25));
    CHECK_FALSE(project(parallel, {0, 0, 6}, none, none).ahead);  // behind a parallel projector too (its c.w is always 1)
    // The derivatives: along a direction dP, against a central difference.
    const glm::dvec3 point(0.3, -0.2, 1.0), dx(0.01, 0.002, -0.003), dy(-0.001, 0.02, 0.004);
    t = project(p, point, dx, dy);
    const double h = 1e-4;
    const ProjectedUV ax = project(p, point + h * dx, none, none), bx = project(p, point - h * dx, none, none);
    const ProjectedUV ay = project(p, point + h * dy, none, none), by = project(p, point - h * dy, none, none);
    CHECK(t.d.dudx == doctest::Approx((ax.u - bx.u) / (2 * h)).epsilon(1e-6));
    CHECK(t.d.dvdx == doctest::Approx((ax.v - bx.v) / (2 * h)).epsilon(1e-6));
    CHECK(t.d.dudy == doctest::Approx((ay.u - by.u) / (2 * h)).epsilon(1e-6));
    CHECK(t.d.dvdy == doctest::Approx((ay.v - by.v) / (2 * h)).epsilon(1e-6));
}

TEST_CASE("a projected texture's texels land where the projector throws them, pixel for pixel, seen from elsewhere") {
    // A 2x2 texture (nearest, clamp) thrown by a projector at (0, 0, 2) onto the plane z = 0;
    // the camera looks from (0.6, 0.4, 1.5). Each pixel's surface point (its centre's ray meets
    // z = 0) gives u = (x / 2 + 1) / 2, v = (y / 2 + 1) / 2 (90 degrees at distance 2), and its
    // texel (u < 1/2: left column; v < 1/2: bottom row).
    const std::string dir = scratch_folder("projective");
    const unsigned char texels[12] = {0, 255, 0, 0, 0, 255, 255, 0, 0, 255, 255, 255};  // top: green, blue; bottom: red, white
    write_text(dir + "/t.ppm", "P6\n2 2\n255\n" + std::string(reinterpret_cast<const char*>(texels), 12));
    write_text(dir + "/s.scene", "size 64 48\ncamera eye 0.6 0.4 1.5 target 0 0 0 fov 70\n"
                                 "texture t file t.ppm filter nearest wrap clamp\nprojector p eye 0 0 2 target 0 0 0 fov 90\n"
                                 "material m texture t projector p\n"
                                 "quad material m v -3 -3 0 0 0 v 3 -3 0 0 0 v 3 3 0 0 0 v -3 3 0 0 0\n");
    const RunResult r = run_texr("render " + dir + "/s.scene -o " + dir + "/s.ppm");
    REQUIRE(r.exit_code == 0);
    const std::string pixels = ppm_pixels(dir + "/s.ppm", 64, 48);
    REQUIRE(pixels.size() == 64 * 48 * 3);
    Camera camera;
    camera.eye = {0.6, 0.4, 1.5}, camera.target = {0, 0, 0}, camera.fov_y_degrees = 70;
    const glm::dmat4 inverse = glm::inverse(projection_matrix(camera, 64.0 / 48.0) * view_matrix(camera));
    int checked = 0, wrong = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            const glm::dvec4 far = inverse * glm::dvec4(2.0 * (x + 0.5) / 64 - 1.0, 1.0 - 2.0 * (y + 0.5) / 48, 1.0, 1.0);
            const glm::dvec3 ray = glm::dvec3(far) / far.w - camera.eye;
            const glm::dvec3 p = camera.eye + ray * (-camera.eye.z / ray.z);
            if (std::fabs(p.x) > 2.9 || std::fabs(p.y) > 2.9) continue;
            const double u = (p.x / 2 + 1) / 2, v = (p.y / 2 + 1) / 2;
            if (std::fabs(u - 0.5) < 1e-3 || std::fabs(v - 0.5) < 1e-3) continue;  // (the texel edges)
            const int column = u < 0.5 ? 0 : 1, row_from_top = v < 0.5 ? 1 : 0;
            const unsigned char* want = texels + 3 * (2 * row_from_top + column);
            ++checked;
            for (int k = 0; k < 3; ++k) wrong += std::uint8_t(pixels[3 * std::size_t(y * 64 + x) + std::size_t(k)]) != want[k];
        }
    CHECK(checked > 2500);
    CHECK(wrong == 0);
    // Behind the projector nothing is thrown: a plane behind it shows the border colour (red),
    // whatever the projector's kind.
    for (const std::string kind : {"fov 90", "parallel 3"}) {
        CAPTURE(kind);
        write_text(dir + "/b.scene", "size 32 32\ncamera eye 0 0 6 target 0 0 3 fov 60\n"
                                     "texture t file t.ppm filter bilinear wrap border border 1 0 0 1\nprojector p eye 0 0 2 target 0 0 0 " +
                                         kind + "\nmaterial m texture t projector p\n"
                                                "quad material m v -3 -3 3 0 0 v 3 -3 3 0 0 v 3 3 3 0 0 v -3 3 3 0 0\n");
        REQUIRE(run_texr("render " + dir + "/b.scene -o " + dir + "/b.ppm").exit_code == 0);
        const std::string behind = ppm_pixels(dir + "/b.ppm", 32, 32);
        REQUIRE(behind.size() == 32 * 32 * 3);
        int red = 0;
        for (std::size_t i = 0; i < behind.size(); i += 3)
            red += std::uint8_t(behind[i]) == 255 && behind[i + 1] == 0 && behind[i + 2] == 0;
        CHECK(red == 32 * 32);
    }
    // explain tells the throw, and its bytes are the frame's.
    const RunResult e = run_texr("explain " + dir + "/s.scene 20 30");
    CHECK(e.output.find("5. Texture 't', thrown by projector 'p' (perspective):\n") != std::string::npos);
    const std::array<int, 3> rgb = explained_bytes(e.output);
    for (int k = 0; k < 3; ++k) CHECK(rgb[std::size_t(k)] == int(std::uint8_t(pixels[3 * std::size_t(30 * 64 + 20) + std::size_t(k)])));
}

TEST_CASE("projectors in scene files: options and messages") {
    const std::string dir = scratch_folder("projective-scenes");
    const std::string head = "size 32 24\ncamera eye 0 0 3 target 0 0 0\ntexture t procedural checker\n";
    for (const auto& [body, message] : std::vector<std::pair<std::string, std::string>>{
             {"projector p eye 0 0 1 target 0 0 1\n", "4: the projector's eye and target must be apart (and within a double's range)"},
             {"projector p eye 0 5 0 target 0 0 0\n", "4: the projector's up must not be zero or parallel to its view"},
             {"projector p fov 30 parallel 2\n", "4: a projector is either perspective ('fov') or parallel ('parallel'), not both"},
             {"projector p fov 180\n", "4: the projector's fov must be at least 1e-6 and below 180 degrees"},
             {"material m projector q\n", "4: unknown projector 'q' (define it with a 'projector' line first)"},
             {"projector p\nmaterial m projector p\n", "5: material 'm' has no texture for its projector to throw ('texture NAME')"},
             {"projector p\nprojector p\n", "5: projector 'p' is defined a second time (first on line 4)"},
         }) {
        CAPTURE(body);
        write_text(dir + "/bad.scene", head + body + "triangle v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n");
        const RunResult r = run_texr("render " + dir + "/bad.scene -o " + dir + "/bad.png");
        CHECK(r.exit_code == 1);
        CHECK(r.output == "texr: " + dir + "/bad.scene:" + message + "\n");
    }
    // A mesh without texture coordinates takes a projected texture.
    write_text(dir + "/flat.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
    write_text(dir + "/ok.scene", head + "projector p eye 0 0 2\nmaterial m texture t projector p\nmesh flat.obj material m\n");
    const RunResult r = run_texr("render " + dir + "/ok.scene -o " + dir + "/ok.ppm --stats");
    CHECK(r.exit_code == 0);
    CHECK(r.output.find(" needs world position; skips uv, uv derivatives, normal, vertex colour\n") != std::string::npos);
}
