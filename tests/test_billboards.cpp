// Opacity as an alpha test (material `cutout`) and billboards (the `billboard` command): a
// half-transparent quad in front of another, pixel for pixel; billboards where they should
// be on screen, facing the eye; the scene file's rules.
#include <doctest/doctest.h>

#include <stb_image_write.h>

#include <cmath>
#include <array>
#include <cstdint>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "helpers.h"

using namespace texr;
using namespace texr::testing;

namespace {


// A 2x1 RGBA PNG: the left texel green with alpha `left_alpha`, the right one blue, opaque.
void write_two_texels(const std::string& path, unsigned char left_alpha) {
    const unsigned char texels[8] = {0, 255, 0, left_alpha, 0, 0, 255, 255};
    REQUIRE(stbi_write_png(path.c_str(), 2, 1, 4, texels, 8) != 0);
}

}  // namespace

TEST_CASE("a cutout material's texels below the threshold are holes: what is behind shows, and its depth stays") {
    // Camera at z = 1 looking down -z at 90 degrees, 64x64. A red quad at z = 0 and, in front
    // at z = 0.1, a quad textured with the two texels (nearest) across x from -2 to 2: its left
    // half (u < 1/2, screen columns 0..31) reads the left texel, its right half the right one.
    const std::string dir = scratch_folder("cutout");
    // (wrap repeat on this power-of-two image would take the span walk's short paths, which
    // must leave cutout materials to the general one; clamp never does)
    for (const std::string wrap : {"clamp", "repeat"}) {
    CAPTURE(wrap);
    const std::string head = "size 64 64\ncamera eye 0 0 1 target 0 0 0 fov 90\nmaterial red color 1 0 0\n"
                             "texture t file t.png filter nearest wrap " + wrap + "\n";
    const std::string quads = "quad material red v -2 -2 0 0 0 v 2 -2 0 1 0 v 2 2 0 1 1 v -2 2 0 0 1\n"
                              "quad material front v -2 -2 0.1 0 0 v 2 -2 0.1 1 0 v 2 2 0.1 1 1 v -2 2 0.1 0 1\n";
    struct Case {
        unsigned char left_alpha;
        std::string cutout;
        bool hole;  // whether the left half is a hole
    };
    for (const Case& c : {Case{0, "0.5", true}, Case{127, "0.5", true}, Case{128, "0.5", false}, Case{0, "", false},
                          Case{254, "1", true}, Case{255, "1", false}}) {
        CAPTURE(int(c.left_alpha));
        CAPTURE(c.cutout);
        write_two_texels(dir + "/t.png", c.left_alpha);
        write_text(dir + "/s.scene", head + "material front texture t" + (c.cutout.empty() ? "" : " cutout " + c.cutout) + "\n" + quads);
        REQUIRE(run_texr("render " + dir + "/s.scene -o " + dir + "/o.ppm").exit_code == 0);
        const std::string pixels = ppm_pixels(dir + "/o.ppm", 64, 64);
        int wrong = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                const std::size_t i = 3 * std::size_t(y * 64 + x);
                const int r = std::uint8_t(pixels[i]), g = std::uint8_t(pixels[i + 1]), b = std::uint8_t(pixels[i + 2]);
                const bool left = x < 32;
                const bool red = r == 255 && g == 0 && b == 0, green = r == 0 && g == 255 && b == 0, blue = r == 0 && g == 0 && b == 255;
                wrong += left ? !(c.hole ? red : green) : !blue;
            }
        CHECK(wrong == 0);
    }
    // Behind a hole the depth is the red quad's: a green triangle between the two (z = 0.05)
    // shows through the hole, where it would be hidden if the hole had written its depth.
    write_two_texels(dir + "/t.png", 0);
    write_text(dir + "/s.scene", head + "material front texture t cutout 0.5\nmaterial green color 0 1 0\n" + quads +
                                     "quad material green v -1 -1 0.05 0 0 v 1 -1 0.05 1 0 v 1 1 0.05 1 1 v -1 1 0.05 0 1\n");
    REQUIRE(run_texr("render " + dir + "/s.scene -o " + dir + "/o.ppm").exit_code == 0);
    const std::string pixels = ppm_pixels(dir + "/o.ppm", 64, 64);
    CHECK(std::uint8_t(pixels[3 * (32 * 64 + 20) + 1]) == 255);  // (20, 32): the green quad, through the hole
    CHECK(std::uint8_t(pixels[3 * (32 * 64 + 44) + 2]) == 255);  // (44, 32): the blue texel in front of it
    // explain on a drawn pixel says why it is drawn.
    const RunResult r = run_texr("explain " + dir + "/s.scene 44 32");
    CHECK(r.output.find("    cutout: alpha 1.00000 is at least the threshold 0.5: drawn (below it, a hole)\n") != std::string::npos);
    }
    // An opaque texture under every filter, cutout 1: no holes (bicubic's filtered alpha of
    // opaque texels rounds to just below 1).
    std::string opaque(16 * 16 * 4, char(255));
    for (int i = 0; i < 16 * 16; ++i) opaque[std::size_t(4 * i + 1)] = char(i);
    REQUIRE(stbi_write_png((dir + "/opaque.png").c_str(), 16, 16, 4, opaque.data(), 64) != 0);
    for (const std::string filter : {"nearest", "bilinear", "bicubic", "trilinear", "anisotropic", "ewa"}) {
        CAPTURE(filter);
        write_text(dir + "/o.scene", "size 64 48\ncamera eye 0 1 0 target 0 0.75 -4 fov 60\ntexture t file opaque.png filter " + filter +
                                         "\nmaterial m texture t cutout 1\nmaterial n texture t\n"
                                         "quad material m v -50 0 5 0 0 v 50 0 5 40 0 v 50 0 -95 40 40 v -50 0 -95 0 40\n");
        const RunResult with = run_texr("render " + dir + "/o.scene -o " + dir + "/o.ppm --stats");
        REQUIRE(with.exit_code == 0);
        write_text(dir + "/o.scene", "size 64 48\ncamera eye 0 1 0 target 0 0.75 -4 fov 60\ntexture t file opaque.png filter " + filter +
                                         "\nmaterial n texture t\n"
                                         "quad material n v -50 0 5 0 0 v 50 0 5 40 0 v 50 0 -95 40 40 v -50 0 -95 0 40\n");
        const RunResult without = run_texr("render " + dir + "/o.scene -o " + dir + "/o2.ppm --stats");
        const auto shaded = [](const std::string& out) { return out.substr(out.find("pixels shaded"), out.find('\n', out.find("pixels shaded")) - out.find("pixels shaded")); };
        CHECK(shaded(with.output) == shaded(without.output));
        CHECK(read_file(dir + "/o.ppm") == read_file(dir + "/o2.ppm"));
    }
}

TEST_CASE("a billboard is a quad of its size at its centre, facing the eye, about the y axis or in full") {
    // Each billboard is drawn white, lit by a light from behind the eye along the view: a
    // surface facing the eye squarely is lit in full (Lambert), one turned away less. Its
    // corners, projected by the renderer's matrices, bound the pixels it covers.
    const std::string dir = scratch_folder("billboards");
    Camera camera;
    camera.eye = {3, 2, 4}, camera.target = {0, 1, 0}, camera.fov_y_degrees = 50;
    const int w = 96, h = 72;
    const glm::dmat4 view_projection = projection_matrix(camera, double(w) / h) * view_matrix(camera);
    struct Case {
        std::string turn;
        glm::dvec3 center;
    };
    for (const Case& c : {Case{"view", {0, 1, 0}}, Case{"axis", {0, 1, 0}}, Case{"view", {-1, 0.5, -1}}}) {
        CAPTURE(c.turn);
        const glm::dvec3 f = glm::normalize(camera.eye - c.center);
        // The light travels from the eye towards the billboard: -f.
        const std::string scene = "size 96 72\ncamera eye 3 2 4 target 0 1 0 fov 50\nambient 0 0 0\nlight directional " +
                                  std::to_string(-f.x) + " " + std::to_string(-f.y) + " " + std::to_string(-f.z) +
                                  "\nmaterial m color 1 1 1 lighting lambert\nbillboard material m center " + std::to_string(c.center.x) +
                                  " " + std::to_string(c.center.y) + " " + std::to_string(c.center.z) + " size 1 0.5 turn " + c.turn + "\n";
        write_text(dir + "/b.scene", scene);
        const RunResult r = run_texr("render " + dir + "/b.scene -o " + dir + "/b.ppm --stats");
        REQUIRE(r.exit_code == 0);
        const std::string pixels = ppm_pixels(dir + "/b.ppm", w, h);
        // The corners: turn view spans the camera's right and up (square to the view); turn
        // axis the horizontal right and the world's up.
        glm::dvec3 up(0, 1, 0), to_eye = camera.eye - c.center;
        if (c.turn == "axis") to_eye.y = 0.0;
        const glm::dvec3 facing = glm::normalize(to_eye);
        if (c.turn == "view") up = glm::normalize(glm::dvec3(0, 1, 0) - facing.y * facing);
        const glm::dvec3 right = glm::cross(up, facing);
        // The projected corners, in order around the quad, and each pixel centre's signed
        // distance to their edges (inside: all positive with this winding, or all negative).
        glm::dvec2 corner[4];
        int k = 0;
        for (const auto& [sx, sy] : {std::pair{-0.5, -0.25}, std::pair{0.5, -0.25}, std::pair{0.5, 0.25}, std::pair{-0.5, 0.25}}) {
            const glm::dvec4 p = view_projection * glm::dvec4(c.center + sx * right + sy * up, 1.0);
            corner[k++] = {(p.x / p.w * 0.5 + 0.5) * w, (0.5 - p.y / p.w * 0.5) * h};
        }
        const auto nearest_edge = [&](double px, double py) {  // signed: > 0 inside
            double least = 1e9, sign = 0.0;
            for (int e = 0; e < 4; ++e) {
                const glm::dvec2 a = corner[e], b = corner[(e + 1) % 4];
                const double cross = (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
                const double distance = cross / glm::length(b - a);
                if (e == 0) sign = distance >= 0 ? 1.0 : -1.0;
                least = std::min(least, distance * sign);
            }
            return least;
        };
        int inside = 0, outside_lit = 0, covered = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::uint8_t v = std::uint8_t(pixels[3 * std::size_t(y * w + x)]);
                const double edge = nearest_edge(x + 0.5, y + 0.5);
                if (edge > 0.01 && v == 0) ++inside;  // a hole in it
                if (edge < -0.01 && v != 0) ++outside_lit;
                covered += v != 0;
            }
        CHECK(inside == 0);
        CHECK(outside_lit == 0);
        CHECK(covered > 40);
        // Facing the eye in full: N . L = 1 at its centre, 255; about the axis the view from
        // above tilts it away: cos of the angle between f and its horizontal part.
        const glm::dvec4 centre = view_projection * glm::dvec4(c.center, 1.0);
        const int cx = int((centre.x / centre.w * 0.5 + 0.5) * w), cy = int((0.5 - centre.y / centre.w * 0.5) * h);
        const double cosine = c.turn == "view" ? 1.0 : glm::dot(f, facing);
        const double encoded = cosine <= 0.0031308 ? 12.92 * cosine : 1.055 * std::pow(cosine, 1 / 2.4) - 0.055;
        CHECK(std::abs(int(std::uint8_t(pixels[3 * std::size_t(cy * w + cx)])) - int(std::lround(255 * encoded))) <= 1);
    }
}

TEST_CASE("a billboard's texture reads left to right and bottom to top as the viewer sees it") {
    // A 2x2 texture, nearest: bottom row red, white; top row green, blue (the file lists the
    // top row first). A quarter of the way in from each corner, the viewer sees red at the
    // bottom left and blue at the top right, from any side.
    const std::string dir = scratch_folder("billboard-texture");
    write_text(dir + "/t.ppm", std::string("P6\n2 2\n255\n") + std::string("\x00\xff\x00\x00\x00\xff\xff\x00\x00\xff\xff\xff", 12));
    for (const glm::dvec3 eye : {glm::dvec3(3, 2, 4), glm::dvec3(-4, 1, -2), glm::dvec3(0.5, -2, -5)}) {
        CAPTURE(eye.x);
        Camera camera;
        camera.eye = eye, camera.target = {0, 0, 0}, camera.fov_y_degrees = 40;
        const std::string e = std::to_string(eye.x) + " " + std::to_string(eye.y) + " " + std::to_string(eye.z);
        write_text(dir + "/b.scene", "size 64 64\ncamera eye " + e + " target 0 0 0 fov 40\ntexture t file t.ppm filter nearest\n"
                                     "material m texture t\nbillboard material m center 0 0 0 size 2 2 turn view\n");
        REQUIRE(run_texr("render " + dir + "/b.scene -o " + dir + "/b.ppm").exit_code == 0);
        const std::string pixels = ppm_pixels(dir + "/b.ppm", 64, 64);
        const glm::dmat4 m = projection_matrix(camera, 1.0) * view_matrix(camera);
        const glm::dvec3 f = glm::normalize(eye), up = glm::normalize(glm::dvec3(0, 1, 0) - f.y * f), right = glm::cross(up, f);
        const auto colour_at = [&](const glm::dvec3& p) {
            const glm::dvec4 c = m * glm::dvec4(p, 1.0);
            const int x = int((c.x / c.w * 0.5 + 0.5) * 64), y = int((0.5 - c.y / c.w * 0.5) * 64);
            const std::size_t i = 3 * std::size_t(y * 64 + x);
            return std::array<int, 3>{std::uint8_t(pixels[i]), std::uint8_t(pixels[i + 1]), std::uint8_t(pixels[i + 2])};
        };
        CHECK(colour_at(-0.5 * right - 0.5 * up) == std::array<int, 3>{255, 0, 0});
        CHECK(colour_at(0.5 * right + 0.5 * up) == std::array<int, 3>{0, 0, 255});
        CHECK(colour_at(-0.5 * right + 0.5 * up) == std::array<int, 3>{0, 255, 0});
        CHECK(colour_at(0.5 * right - 0.5 * up) == std::array<int, 3>{255, 255, 255});
    }
}

TEST_CASE("billboards and cutout in scene files: options, order, messages") {
    const std::string dir = scratch_folder("billboard-scenes");
    const std::string head = "size 32 24\ncamera eye 0 0 3 target 0 0 0\n";
    const std::string above = "size 32 24\ncamera eye 0 9 0 target 0 0 0 up 0 0 1\n";
    for (const auto& [body, message] : std::vector<std::pair<std::string, std::string>>{
             {"billboard center 0 0 0\n", "3: billboard needs 'center x y z' and 'size W H'"},
             {"billboard center 0 0 0 size 0 1\n", "3: the billboard's width and height must be above 0 (and at most 1e18)"},
             {"billboard center 0 0 0 size 1 1 turn sideways\n", "3: unknown billboard turn 'sideways' (expected one of: axis, view)"},
             {"billboard center 0 0 3 size 1 1 turn view\n", "3: the eye is at the billboard's centre: it has no side to face"},
             {"material m cutout 0.5\nbillboard material m center 0 0 0 size 1 1\n",
              "3: material 'm' has no texture: 'cutout' tests its texture's alpha"},
             {"texture t procedural checker\nmaterial m texture t cutout 0\nbillboard material m center 0 0 0 size 1 1\n",
              "4: the cutout's alpha threshold must be above 0 and at most 1"},
             {"material m opacity 0.5\n",
              "3: unknown material option 'opacity' (expected color, texture, lighting, vertex_colors, bump, reflect, cutout, slope, slope_direction, lightmap, lightmap_repeat, projector, mapping, mapping_center, mapping_axis or mapping_size); "
              "'opacity': texr's opacity is an alpha test, a material's 'cutout THRESHOLD' (blending is not in texr; "
              "docs/scene-format.md)"},
         }) {
        CAPTURE(body);
        write_text(dir + "/bad.scene", body.rfind("above:", 0) == 0 ? above + body.substr(6) : head + body);
        const RunResult r = run_texr("render " + dir + "/bad.scene -o " + dir + "/bad.png");
        CHECK(r.exit_code == 1);
        CHECK(r.output == "texr: " + dir + "/bad.scene:" + message + "\n");
        CHECK_FALSE(file_exists(dir + "/bad.png"));
    }
    // A turn-axis billboard straight below the eye is drawn (seen edge-on, it faces against
    // the camera's view), not refused.
    write_text(dir + "/above.scene", above + "material m color 1 1 1\nbillboard material m center 0 5 0 size 1 1\n");
    CHECK(run_texr("render " + dir + "/above.scene -o " + dir + "/above.ppm").exit_code == 0);
    // The camera line may come after the billboard: it faces the camera the file ends with.
    write_text(dir + "/late.scene", "material m color 1 1 1\nbillboard material m center 0 0 0 size 1 1 turn view\n" + head);
    const RunResult r = run_texr("render " + dir + "/late.scene -o " + dir + "/late.ppm --stats");
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("pixels shaded      ") != std::string::npos);
    CHECK(r.output.find("pixels shaded      0\n") == std::string::npos);
}
