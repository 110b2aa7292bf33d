// Environment and reflection maps (texture/environment.h): the latitude-longitude formula at
// hand-worked directions, the pixel rays against the renderer's own projection, and frames
// whose background and mirror are worked out pixel by pixel with the map's texels.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "helpers.h"
#include "texr/texture/environment.h"

using namespace texr;
using namespace texr::testing;

namespace {

constexpr double pi = 3.14159265358979323846;

// A 4x2 PPM map of the eight colours whose channels are 0 or 255: texel (i, j) (row j from
// the top of the file) holds colour number 4 j + i, bit 0 red, bit 1 green, bit 2 blue.
std::string eight_colour_map() {
    std::string ppm = "P6\n4 2\n255\n";
    for (int k = 0; k < 8; ++k)
        for (int bit = 0; bit < 3; ++bit) ppm += char((k >> bit) & 1 ? 255 : 0);
    return ppm;
}

// The colour number the map shows along direction d with nearest filtering, repeat in u and
// clamp in v (texr's v = 0 is the image's bottom row), or -1 where (u, v) lies within 1e-6 of
// a texel edge (a tie this test leaves alone).
int map_colour(const glm::dvec3& d) {
    const double u = 0.5 + std::atan2(d.x, -d.z) / (2.0 * pi);
    const double v = 0.5 + std::asin(d.y / glm::length(d)) / pi;
    const double x = u * 4.0, y = v * 2.0;
    if (std::fabs(x - std::round(x)) < 1e-6 || std::fabs(y - std::round(y)) < 1e-6) return -1;
    const int i = int(std::floor(x)) % 4, j_from_bottom = std::clamp(int(std::floor(y)), 0, 1);
    return 4 * (1 - j_from_bottom) + i;
}

int pixel_colour(const std::string& pixels, int width, int x, int y) {
    const std::size_t i = 3 * std::size_t(y * width + x);
    int k = 0;
    for (int bit = 0; bit < 3; ++bit) {
        const auto c = std::uint8_t(pixels[i + std::size_t(bit)]);
        REQUIRE((c == 0 || c == 255));
        k |= (c == 255 ? 1 : 0) << bit;
    }
    return k;
}


}  // namespace

TEST_CASE("the latitude-longitude map's (u, v) of hand-worked directions, and the reflection of a view ray") {
    const auto check = [](glm::dvec3 d, double u, double v) {
        CAPTURE(d.x);
        CAPTURE(d.y);
        CAPTURE(d.z);
        const glm::dvec2 uv = latlong_uv(d);
        CHECK(uv.x == doctest::Approx(u).epsilon(1e-12));
        CHECK(uv.y == doctest::Approx(v).epsilon(1e-12));
    };
    check({0, 0, -1}, 0.5, 0.5);    // ahead (-z): the middle
    check({1, 0, 0}, 0.75, 0.5);    // +x: a quarter turn on
    check({-1, 0, 0}, 0.25, 0.5);
    check({0, 0, 1}, 1.0, 0.5);     // behind: the edge, u = 1 (0 after repeat)
    check({0, 5, 0}, 0.5, 1.0);     // straight up: the top row
    check({0, -1, 0}, 0.5, 0.0);    // straight down
    check({1, 1, -1}, 0.625, 0.5 + std::asin(1.0 / std::sqrt(3.0)) / pi);
    check({0, 0, 0}, 0.5, 0.5);     // no direction
    CHECK(reflect_direction({0.6, 0, -0.8}, {0, 0, 1}) == glm::dvec3(0.6, 0, 0.8));
    CHECK(reflect_direction({0, -1, 0}, {0, 1, 0}) == glm::dvec3(0, 1, 0));
}

TEST_CASE("each pixel's ray, projected by the renderer's own matrices, lands on the pixel's centre") {
    Camera camera;
    camera.eye = {1, 2, 3}, camera.target = {-2, 0.5, -1}, camera.up = {0, 1, 0}, camera.fov_y_degrees = 50;
    const int width = 40, height = 30;
    const glm::dmat4 m = projection_matrix(camera, double(width) / height) * view_matrix(camera);
    for (int y = 0; y < height; y += 7)
        for (int x = 0; x < width; x += 3) {
            const glm::dvec4 clip = m * glm::dvec4(camera.eye + pixel_ray(camera, width, height, x, y), 1.0);
            // (the viewport as the renderer's setup has it: x right, y down)
            CHECK((clip.x / clip.w * 0.5 + 0.5) * width == doctest::Approx(x + 0.5).epsilon(1e-9));
            CHECK((0.5 - clip.y / clip.w * 0.5) * height == doctest::Approx(y + 0.5).epsilon(1e-9));
        }
}

TEST_CASE("an environment map is the background along each pixel's ray, and a mirror shows it along R, pixel for pixel") {
    const std::string dir = scratch_folder("environment");
    write_text(dir + "/map.ppm", eight_colour_map());
    const std::string map = "texture sky file map.ppm filter nearest wrap_u repeat wrap_v clamp\nenvironment sky\n";
    // The background: a camera looking up and to the side, a small triangle far off to its right.
    Camera camera;
    camera.eye = {0, 0, 0}, camera.target = {-1, 0.6, -0.5}, camera.fov_y_degrees = 100;
    write_text(dir + "/bg.scene", "size 64 48\ncamera eye 0 0 0 target -1 0.6 -0.5 fov 100\n" + map +
                                      "material m color 1 1 1\ntriangle material m v 50 0 0 0 0 v 50 1 0 1 0 v 50 0 1 0 1\n");
    RunResult r = run_texr("render " + dir + "/bg.scene -o " + dir + "/bg.ppm");
    REQUIRE(r.exit_code == 0);
    std::string pixels = ppm_pixels(dir + "/bg.ppm", 64, 48);
    const glm::dmat4 inverse = glm::inverse(projection_matrix(camera, 64.0 / 48.0) * view_matrix(camera));
    int checked = 0, wrong = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            // The pixel's ray by unprojecting its centre (independent of pixel_ray).
            const glm::dvec4 far = inverse * glm::dvec4(2.0 * (x + 0.5) / 64 - 1.0, 1.0 - 2.0 * (y + 0.5) / 48, 1.0, 1.0);
            const int want = map_colour(glm::dvec3(far) / far.w - camera.eye);
            if (want < 0) continue;
            ++checked;
            wrong += pixel_colour(pixels, 64, x, y) != want;
        }
    CHECK(checked > 3000);
    CHECK(wrong == 0);
    // A mirror filling the frame (a unit square at z = 0, the eye at distance 0.5, 90 degrees),
    // all reflection: every pixel shows the map along R = (V.x, V.y, -V.z), V the view ray.
    write_text(dir + "/mirror.scene", "size 64 64\ncamera eye 0 0 0.5 target 0 0 0 fov 90\n" + map +
                                          "material m color 0 0 0 reflect 1\n"
                                          "quad material m v -0.5 -0.5 0 0 0 v 0.5 -0.5 0 1 0 v 0.5 0.5 0 1 1 v -0.5 0.5 0 0 1\n");
    r = run_texr("render " + dir + "/mirror.scene -o " + dir + "/mirror.ppm --threads 2");
    REQUIRE(r.exit_code == 0);
    pixels = ppm_pixels(dir + "/mirror.ppm", 64, 64);
    checked = 0, wrong = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const glm::dvec3 view((x + 0.5) / 64 - 0.5, 0.5 - (y + 0.5) / 64, -0.5);  // eye to the square's point
            const int want = map_colour({view.x, view.y, -view.z});
            if (want < 0) continue;
            ++checked;
            wrong += pixel_colour(pixels, 64, x, y) != want;
        }
    CHECK(checked > 3500);
    CHECK(wrong == 0);
    // explain: the background's ray and (u, v); the mirror's V, R and (u, v).
    r = run_texr("explain " + dir + "/bg.scene 0 0");
    CHECK(r.output.find("no triangle covers it: the environment map 'sky' shows, seen along the pixel's ray\n") != std::string::npos);
    CHECK(r.output.find("    u = 1/2 + atan2(d.x, -d.z) / 2 pi = ") != std::string::npos);
    r = run_texr("explain " + dir + "/mirror.scene 32 32");
    CAPTURE(r.output);
    CHECK(r.output.find("    reflection: (0.00000, 0.00000, 0.00000) x (1 - 1) + the environment map along R x 1\n") != std::string::npos);
    CHECK(r.output.find("R = V - 2 (N . V) N = (0.01562, -0.01562, 0.99976)\n") != std::string::npos);  // (1/64, -1/64, 1) normalised
}

TEST_CASE("environment and reflect in scene files: order, ranges, and what a reflecting material needs") {
    const std::string dir = scratch_folder("environment-scenes");
    write_text(dir + "/map.ppm", eight_colour_map());
    const std::string head = "size 32 24\ncamera eye 0 0 3 target 0 0 0\ntexture sky file map.ppm\n";
    const std::string triangle = "triangle material m v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n";
    for (const auto& [body, message] : std::vector<std::pair<std::string, std::string>>{
             {"material m reflect 0.5\nenvironment sky\n",
              "4: material 'm' reflects the environment: give the 'environment TEXTURE' line before it"},
             {"environment sky\nmaterial m reflect 1.5\n", "5: the share reflected must be between 0 and 1"},
             {"environment nope\nmaterial m\n", "4: unknown texture 'nope' (define it with a 'texture' line first)"},
             {"environment sky\nenvironment sky\nmaterial m\n", "5: 'environment' is given a second time (first on line 4)"},
         }) {
        CAPTURE(body);
        write_text(dir + "/bad.scene", head + body + triangle);
        const RunResult r = run_texr("render " + dir + "/bad.scene -o " + dir + "/bad.png");
        CHECK(r.exit_code == 1);
        CHECK(r.output == "texr: " + dir + "/bad.scene:" + message + "\n");
        CHECK_FALSE(file_exists(dir + "/bad.png"));
    }
    write_text(dir + "/ok.scene", head + "environment sky\nmaterial m reflect 0.25\n" + triangle);
    const RunResult r = run_texr("render " + dir + "/ok.scene -o " + dir + "/ok.ppm --stats");
    CHECK(r.exit_code == 0);
    CHECK(r.output.find(" needs normal, world position; skips uv, uv derivatives, vertex colour\n") != std::string::npos);
}

TEST_CASE("a partial reflection blends the lit colour with the map, a solid procedural map is read by direction, and bumps bend reflections") {
    const std::string dir = scratch_folder("environment-blend");
    write_text(dir + "/map.ppm", eight_colour_map());
    const std::string map = "texture sky file map.ppm filter nearest wrap_u repeat wrap_v clamp\nenvironment sky\n";
    // The full mirror of the test above at reflect 0.3, its own colour sRGB (0.8, 0.5, 0.2),
    // unlit: each channel (1 - 0.3) c + 0.3 m, with m the map's 0 or 1.
    write_text(dir + "/m.scene", "size 64 64\ncamera eye 0 0 0.5 target 0 0 0 fov 90\n" + map +
                                     "material m color 0.8 0.5 0.2 reflect 0.3\n"
                                     "quad material m v -0.5 -0.5 0 0 0 v 0.5 -0.5 0 1 0 v 0.5 0.5 0 1 1 v -0.5 0.5 0 0 1\n");
    REQUIRE(run_texr("render " + dir + "/m.scene -o " + dir + "/m.ppm").exit_code == 0);
    std::string pixels = ppm_pixels(dir + "/m.ppm", 64, 64);
    const auto linear = [](double s) { return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4); };
    const auto encoded = [](double l) { return int(std::lround(255.0 * (l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055))); };
    const double own[3] = {linear(0.8), linear(0.5), linear(0.2)};
    int checked = 0, off = 0;
    for (int y = 0; y < 64; y += 3)
        for (int x = 0; x < 64; x += 3) {
            const glm::dvec3 view((x + 0.5) / 64 - 0.5, 0.5 - (y + 0.5) / 64, -0.5);
            const int k = map_colour({view.x, view.y, -view.z});
            if (k < 0) continue;
            ++checked;
            for (int bit = 0; bit < 3; ++bit) {
                const int want = encoded(0.7 * own[bit] + 0.3 * ((k >> bit) & 1));
                off += std::abs(int(std::uint8_t(pixels[3 * std::size_t(y * 64 + x) + std::size_t(bit)])) - want) > 1;
            }
        }
    CHECK(checked > 300);
    CHECK(off == 0);
    // A solid procedural map is read at the unit direction: a solid checkerboard of scale 2,
    // (floor 2x + floor 2y + floor 2z) mod 2 of the unit ray, white where odd.
    Camera camera;
    camera.eye = {0, 0, 0}, camera.target = {0.3, 0.2, -1}, camera.fov_y_degrees = 120;
    write_text(dir + "/s.scene", "size 48 48\ncamera eye 0 0 0 target 0.3 0.2 -1 fov 120\n"
                                 "texture sky procedural checker scale 2 solid on color0 0 0 0 color1 1 1 1\nenvironment sky\n"
                                 "material m\ntriangle material m v 50 0 0 0 0 v 50 1 0 1 0 v 50 0 1 0 1\n");
    REQUIRE(run_texr("render " + dir + "/s.scene -o " + dir + "/s.ppm").exit_code == 0);
    pixels = ppm_pixels(dir + "/s.ppm", 48, 48);
    checked = 0, off = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x) {
            const glm::dvec3 d = glm::normalize(pixel_ray(camera, 48, 48, x, y)) * 2.0;
            if (std::fabs(d.x - std::round(d.x)) < 1e-3 || std::fabs(d.y - std::round(d.y)) < 1e-3 || std::fabs(d.z - std::round(d.z)) < 1e-3)
                continue;
            const int odd = int(std::fabs(std::fmod(std::floor(d.x) + std::floor(d.y) + std::floor(d.z), 2.0)));
            ++checked;
            off += std::uint8_t(pixels[3 * std::size_t(y * 48 + x)]) != (odd ? 255 : 0);
        }
    CHECK(checked > 2000);
    CHECK(off == 0);
    // A bump-mapped mirror reflects along the bumped normal: its frame differs from the flat
    // mirror's, and explain's bytes are the frame's.
    write_text(dir + "/b.scene", "size 64 64\ncamera eye 0 0 0.5 target 0 0 0 fov 90\n" + map +
                                     "texture n procedural noise scale 3\nmaterial m color 0 0 0 reflect 1 bump n 0.2\n"
                                     "quad material m v -0.5 -0.5 0 0 0 v 0.5 -0.5 0 1 0 v 0.5 0.5 0 1 1 v -0.5 0.5 0 0 1\n");
    write_text(dir + "/f.scene", "size 64 64\ncamera eye 0 0 0.5 target 0 0 0 fov 90\n" + map +
                                     "material m color 0 0 0 reflect 1\n"
                                     "quad material m v -0.5 -0.5 0 0 0 v 0.5 -0.5 0 1 0 v 0.5 0.5 0 1 1 v -0.5 0.5 0 0 1\n");
    REQUIRE(run_texr("render " + dir + "/b.scene -o " + dir + "/b.ppm").exit_code == 0);
    REQUIRE(run_texr("render " + dir + "/f.scene -o " + dir + "/f.ppm").exit_code == 0);
    CHECK(read_file(dir + "/b.ppm") != read_file(dir + "/f.ppm"));
    pixels = ppm_pixels(dir + "/b.ppm", 64, 64);
    for (const auto& [x, y] : {std::pair{10, 10}, std::pair{31, 40}, std::pair{50, 20}, std::pair{60, 60}}) {
        const RunResult r = run_texr("explain " + dir + "/b.scene " + std::to_string(x) + " " + std::to_string(y));
        const std::array<int, 3> rgb = explained_bytes(r.output);
        for (int k = 0; k < 3; ++k) CHECK(rgb[k] == int(std::uint8_t(pixels[3 * std::size_t(y * 64 + x) + std::size_t(k)])));
    }
}
