// Slope-based mapping (material `slope`) and light maps (material `lightmap`): frames worked
// out pixel by pixel from the lecture's formulas, explain against the frame, and messages.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "helpers.h"

using namespace texr;
using namespace texr::testing;

namespace {

double linear(double s) { return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4); }
int encoded(double l) { return int(std::lround(255.0 * (l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055))); }

}  // namespace

TEST_CASE("slope-based mapping: alpha = n . w blends the flat and the steep colour, as worked out by hand") {
    // Three unlit quads side by side, each filling a third of a 96x32 frame, seen along -z
    // from far (fov 2 atan(0.005): one unit is 32 pixels); w = (0, 1, 0) (the default).
    const std::string dir = scratch_folder("slope");
    const double flat[3] = {0.3, 0.7, 0.2}, steep[3] = {0.55, 0.45, 0.4};
    // Normals given at every vertex: (0, 0, 1), (0, sin 30, cos 30) and (0, 1, 0), so n . w
    // is 0, 1/2 and 1 (the quads themselves all face the eye).
    write_text(dir + "/s.scene", "size 96 32\ncamera eye 0 0 100 target 0 0 0 fov 0.5729578\n"
                                 "material m slope 0.3 0.7 0.2 0.55 0.45 0.4\n"
                                 "quad material m v -1.5 -0.5 0 0 0 n 0 0 1 v -0.5 -0.5 0 1 0 n 0 0 1 v -0.5 0.5 0 1 1 n 0 0 1 "
                                 "v -1.5 0.5 0 0 1 n 0 0 1\n"
                                 "quad material m v -0.5 -0.5 0 0 0 n 0 0.5 0.8660254 v 0.5 -0.5 0 1 0 n 0 0.5 0.8660254 "
                                 "v 0.5 0.5 0 1 1 n 0 0.5 0.8660254 v -0.5 0.5 0 0 1 n 0 0.5 0.8660254\n"
                                 "quad material m v 0.5 -0.5 0 0 0 n 0 1 0 v 1.5 -0.5 0 1 0 n 0 1 0 v 1.5 0.5 0 1 1 n 0 1 0 "
                                 "v 0.5 0.5 0 0 1 n 0 1 0\n");
    REQUIRE(run_texr("render " + dir + "/s.scene -o " + dir + "/s.ppm").exit_code == 0);
    const std::string pixels = ppm_pixels(dir + "/s.ppm", 96, 32);
    REQUIRE(pixels.size() == 96 * 32 * 3);
    for (const auto& [x, alpha] : {std::pair{16, 0.0}, std::pair{48, 0.5}, std::pair{80, 1.0}}) {
        CAPTURE(x);
        for (int k = 0; k < 3; ++k) {
            const int want = encoded(alpha * linear(flat[k]) + (1 - alpha) * linear(steep[k]));
            CHECK(std::abs(int(std::uint8_t(pixels[3 * std::size_t(16 * 96 + x) + std::size_t(k)])) - want) <= 1);
        }
        const RunResult r = run_texr("explain " + dir + "/s.scene " + std::to_string(x) + " 16");
        const std::array<int, 3> rgb = explained_bytes(r.output);
        for (int k = 0; k < 3; ++k) CHECK(rgb[std::size_t(k)] == int(std::uint8_t(pixels[3 * std::size_t(16 * 96 + x) + std::size_t(k)])));
        CHECK(r.output.find(" (alpha = n . w = ") != std::string::npos);
    }
}

TEST_CASE("slope-based mapping clamps alpha at 0: a surface facing away from w takes the steep colour") {
    const std::string dir = scratch_folder("slope-down");
    write_text(dir + "/s.scene", "size 16 16\ncamera eye 0 0 2 target 0 0 0 fov 90\nmaterial m slope 0.3 0.7 0.2 0.55 0.45 0.4\n"
                                 "quad material m v -5 -5 0 0 0 n 0 -1 0 v 5 -5 0 1 0 n 0 -1 0 v 5 5 0 1 1 n 0 -1 0 v -5 5 0 0 1 n 0 -1 0\n");
    REQUIRE(run_texr("render " + dir + "/s.scene -o " + dir + "/s.ppm").exit_code == 0);
    const std::string pixels = ppm_pixels(dir + "/s.ppm", 16, 16);
    REQUIRE(pixels.size() == 16 * 16 * 3);
    const double steep[3] = {0.55, 0.45, 0.4};
    for (int k = 0; k < 3; ++k) CHECK(std::abs(int(std::uint8_t(pixels[std::size_t(3 * (8 * 16 + 8) + k)])) - encoded(linear(steep[k]))) <= 1);
}

TEST_CASE("a light map multiplies the colour by its irradiance, read at (u, v) / lightmap_repeat, pixel for pixel") {
    // A quad filling a 64x64 frame with UVs 0..2 and a 2x2 light map (nearest) repeated 2 times:
    // the map is read at (u, v) / 2, so its four texels fill the four quarters of the frame.
    // The material is white and has no texture: each quarter shows its texel's bytes (decoded
    // from sRGB and encoded again); with a red-and-white checkerboard texture of scale 4 (one
    // cell per quarter of u and v), the product.
    const std::string dir = scratch_folder("lightmap");
    // Texels (file order: top row first): top (40, 80, 120), (200, 100, 50); bottom (255, 255, 255), (10, 20, 30).
    const unsigned char map[12] = {40, 80, 120, 200, 100, 50, 255, 255, 255, 10, 20, 30};
    write_text(dir + "/e.ppm", "P6\n2 2\n255\n" + std::string(reinterpret_cast<const char*>(map), 12));
    const std::string head = "size 64 64\ncamera eye 0 0 0.5 target 0 0 0 fov 90\ntexture e file e.ppm filter nearest\n";
    const std::string quad = "quad material m v -0.5 -0.5 0 0 0 v 0.5 -0.5 0 2 0 v 0.5 0.5 0 2 2 v -0.5 0.5 0 0 2\n";
    write_text(dir + "/a.scene", head + "material m lightmap e lightmap_repeat 2\n" + quad);
    REQUIRE(run_texr("render " + dir + "/a.scene -o " + dir + "/a.ppm").exit_code == 0);
    std::string pixels = ppm_pixels(dir + "/a.ppm", 64, 64);
    REQUIRE(pixels.size() == 64 * 64 * 3);
    const auto texel = [&](int x, int y, int k) {  // the map's texel under frame pixel (x, y): column x / 32, row y / 32 from the top
        return int(map[3 * ((y / 32) * 2 + x / 32) + k]);
    };
    int wrong = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            for (int k = 0; k < 3; ++k) wrong += int(std::uint8_t(pixels[3 * std::size_t(y * 64 + x) + std::size_t(k)])) != texel(x, y, k);
    CHECK(wrong == 0);
    // With a checkerboard texture (red where the cell's parity is 1, white where 0), scale 4 over
    // u in 0..2: cells of a quarter frame... of 8 pixels (u 0..2 over 64 pixels, 4 cells per unit).
    write_text(dir + "/b.scene", head + "texture c procedural checker scale 4 color0 1 1 1 color1 1 0 0\n"
                                        "material m texture c lightmap e lightmap_repeat 2\n" + quad);
    REQUIRE(run_texr("render " + dir + "/b.scene -o " + dir + "/b.ppm").exit_code == 0);
    pixels = ppm_pixels(dir + "/b.ppm", 64, 64);
    wrong = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const double u = 2.0 * (x + 0.5) / 64, v = 2.0 * (1.0 - (y + 0.5) / 64);
            const bool red = int(std::floor(4 * u) + std::floor(4 * v)) % 2 == 1;
            for (int k = 0; k < 3; ++k) {
                const double c = (red && k > 0) ? 0.0 : 1.0;
                const int want = encoded(c * linear(texel(x, y, k) / 255.0));
                wrong += std::abs(int(std::uint8_t(pixels[3 * std::size_t(y * 64 + x) + std::size_t(k)])) - want) > 1;
            }
        }
    CHECK(wrong == 0);
    const RunResult r = run_texr("explain " + dir + "/b.scene 40 10");
    CHECK(r.output.find("    x light map     ") != std::string::npos);
    const std::array<int, 3> rgb = explained_bytes(r.output);
    for (int k = 0; k < 3; ++k) CHECK(rgb[std::size_t(k)] == int(std::uint8_t(pixels[3 * std::size_t(10 * 64 + 40) + std::size_t(k)])));
}

TEST_CASE("slope and light map options in scene files") {
    const std::string dir = scratch_folder("mapping-scenes");
    const std::string head = "size 32 24\ncamera eye 0 0 3 target 0 0 0\ntexture s procedural noise solid on\n";
    for (const auto& [line, message] : std::vector<std::pair<std::string, std::string>>{
             {"material m slope_direction 0 1 0", "'slope_direction' belongs with 'slope FLAT STEEP' (r g b each)"},
             {"material m slope 1 1 1 0 0 0 slope_direction 0 0 0",
              "the slope mapping's direction must not be zero (nor beyond a double's range)"},
             {"material m lightmap_repeat 2", "'lightmap_repeat' belongs with 'lightmap TEXTURE'"},
             {"material m lightmap s", "texture 's' is solid: a light map is read at (u, v) (leave out 'solid on')"},
             {"material m lightmap nope", "unknown texture 'nope' (define it with a 'texture' line first)"},
         }) {
        CAPTURE(line);
        write_text(dir + "/bad.scene", head + line + "\ntriangle material m v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n");
        const RunResult r = run_texr("render " + dir + "/bad.scene -o " + dir + "/bad.png");
        CHECK(r.exit_code == 1);
        CHECK(r.output == "texr: " + dir + "/bad.scene:4: " + message + "\n");
    }
}
