// Procedural textures (texture/procedural.h): the lecture's checkerboards, tile and brick at
// hand-worked points, gradient noise against its own definition on the lattice's edges and
// faces, turbulence and its band limit, and frames whose every pixel is worked out by hand.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "helpers.h"
#include "texr/texture/procedural.h"

using namespace texr;
using namespace texr::testing;

namespace {

Procedural pattern(Pattern kind, double scale = 1.0) {
    Procedural p;
    p.pattern = kind, p.scale = scale;
    p.color0 = Color(0.0f), p.color1 = Color(1.0f);
    return p;
}

// 1 where the pattern gives color1 (white), 0 where color0 (black).
int which(const Procedural& p, double x, double y, double z = 0.0) {
    const Color4 c = procedural_value(p, {x, y, z}, 0.0);
    REQUIRE((c == Color4(0, 0, 0, 1) || c == Color4(1, 1, 1, 1)));
    return c.x == 1.0f ? 1 : 0;
}

// A small deterministic sequence in [0, 1) (64-bit LCG, top 53 bits).
struct Sequence {
    std::uint64_t state = 12345;
    double next() {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return double(state >> 11) / 9007199254740992.0;
    }
};

}  // namespace

TEST_CASE("checker, tile and brick give the lecture's colours at hand-worked points") {
    const Procedural checker = pattern(Pattern::checker);
    CHECK(which(checker, 0.25, 0.25) == 0);   // cell (0, 0): parity 0
    CHECK(which(checker, 1.25, 0.25) == 1);   // (1, 0)
    CHECK(which(checker, -0.25, 0.25) == 1);  // (-1, 0): odd, though -1 % 2 is -1 in C
    CHECK(which(checker, -0.25, -0.25) == 0); // (-1, -1)
    CHECK(which(checker, 1e7 + 0.5, 0.5) == 0);
    CHECK(which(checker, 1e7 + 1.5, 0.5) == 1);
    CHECK(which(checker, 0.5, 0.5, 1.5) == 0);  // w is not read without solid
    CHECK(which(pattern(Pattern::checker, 4.0), 0.3, 0.0) == 1);  // 1.2: cell (1, 0)
    Procedural solid = checker;
    solid.solid = true;
    CHECK(which(solid, 0.5, 0.5, 1.5) == 1);   // (0, 0, 1)
    CHECK(which(solid, -0.5, 0.5, 1.5) == 0);  // (-1, 0, 1)

    Procedural tile = pattern(Pattern::tile);  // mortar 0.1, in color1
    CHECK(which(tile, 0.05, 0.5) == 1);
    CHECK(which(tile, 0.5, 0.5) == 0);
    CHECK(which(tile, 0.5, 1.05) == 1);
    CHECK(which(tile, -0.95, 0.5) == 1);  // fu = 0.05
    CHECK(which(tile, -0.85, 0.5) == 0);  // fu = 0.15
    tile.mortar = 0.0;
    CHECK(which(tile, 0.0, 0.0) == 0);  // no mortar at all

    const Procedural brick = pattern(Pattern::brick);
    CHECK(which(brick, 0.05, 0.5) == 1);   // row 0: fu = 0.05, mortar
    CHECK(which(brick, 0.05, 1.5) == 0);   // row 1, shifted: u = -0.45, fu = 0.55
    CHECK(which(brick, 0.55, 1.5) == 1);   // row 1: u = 0.05
    CHECK(which(brick, 0.55, -0.5) == 1);  // row -1 is odd too
    CHECK(which(brick, 0.55, -1.5) == 0);  // row -2: not shifted, fu = 0.55
}

TEST_CASE("gradient noise is 0 on the lattice, the fade-blended corner gradients on its edges and faces, and repeats every 256") {
    // fade(t) = 6t^5 - 15t^4 + 10t^3
    CHECK(fade(0.0) == 0.0);
    CHECK(fade(1.0) == 1.0);
    CHECK(fade(0.5) == 0.5);
    CHECK(fade(0.25) == doctest::Approx(6.0 / 1024.0 - 15.0 / 256.0 + 10.0 / 64.0).epsilon(1e-15));
    Sequence r;
    for (int n = 0; n < 1000; ++n) {
        const long long i = (long long)(r.next() * 2000.0) - 1000, j = (long long)(r.next() * 2000.0) - 1000,
                        k = (long long)(r.next() * 2000.0) - 1000;
        CAPTURE(i);
        CAPTURE(j);
        CAPTURE(k);
        // Every gradient is one of the 12 directions to a cube's edges' midpoints.
        const glm::dvec3 g = lattice_gradient(i, j, k);
        CHECK(std::fabs(g.x) + std::fabs(g.y) + std::fabs(g.z) == 2.0);
        CHECK(((g.x == 0.0) + (g.y == 0.0) + (g.z == 0.0)) == 1);
        CHECK(gradient_noise({double(i), double(j), double(k)}) == 0.0);
        // On the edge from (i, j, k) to (i + 1, j, k) only its two ends count:
        // (1 - a) g0 . (t, 0, 0) + a g1 . (t - 1, 0, 0), a = fade(t).
        const double t = r.next(), a = fade(t);
        const glm::dvec3 g0 = lattice_gradient(i, j, k), g1 = lattice_gradient(i + 1, j, k);
        CHECK(gradient_noise({i + t, double(j), double(k)}) == doctest::Approx((1 - a) * g0.x * t + a * g1.x * (t - 1)).epsilon(1e-12));
        // On the face z = k, the four corners of the cell, blended by fade(s) and fade(t).
        const double s = r.next(), b = fade(s);
        const auto corner = [&](int di, int dj) {
            const glm::dvec3 gc = lattice_gradient(i + di, j + dj, k);
            return gc.x * (s - di) + gc.y * (t - dj);
        };
        const double expected = (1 - fade(t)) * ((1 - b) * corner(0, 0) + b * corner(1, 0)) + fade(t) * ((1 - b) * corner(0, 1) + b * corner(1, 1));
        CHECK(gradient_noise({i + s, j + t, double(k)}) == doctest::Approx(expected).epsilon(1e-12));
        // Period 256 on every axis, exactly (at fractions that keep every bit when 256 k is
        // added: multiples of 1/1024).
        const auto exact = [](double f) { return std::floor(f * 1024.0) / 1024.0; };
        const glm::dvec3 p(i + exact(s), j + exact(t), k + exact(r.next()));
        CHECK(gradient_noise(p) == gradient_noise(p + glm::dvec3(256.0, 0.0, 0.0)));
        CHECK(gradient_noise(p) == gradient_noise(p + glm::dvec3(0.0, -512.0, 0.0)));
        CHECK(gradient_noise(p) == gradient_noise(p + glm::dvec3(0.0, 0.0, 256.0 * 1000.0)));
    }
    // Bounded, centred and not flat, over many points; not finite: 0.
    double largest = 0.0, sum = 0.0;
    const int count = 200000;
    for (int n = 0; n < count; ++n) {
        const double v = gradient_noise({r.next() * 300.0 - 150.0, r.next() * 300.0 - 150.0, r.next() * 300.0 - 150.0});
        largest = std::max(largest, std::fabs(v)), sum += v;
    }
    CHECK(largest <= 1.05);
    CHECK(largest >= 0.6);
    CHECK(std::fabs(sum / count) < 0.01);
    CHECK(gradient_noise({std::nan(""), 0.0, 0.0}) == 0.0);
    CHECK(gradient_noise({INFINITY, 0.5, 0.5}) == 0.0);
}

TEST_CASE("turbulence sums |noise(2^i p)| / 2^i over the octaves its footprint allows, the last by its fraction") {
    // log2(1 / (2 f)) + 1 octaves, within [1, most]; no footprint: all of them.
    CHECK(turbulence_octaves(0.0, 8) == 8.0);
    CHECK(turbulence_octaves(1.0 / 64.0, 8) == 6.0);
    CHECK(turbulence_octaves(1.0 / 64.0, 4) == 4.0);
    CHECK(turbulence_octaves(1.0, 8) == 0.0);  // even the first octave is finer than the pixel
    CHECK(turbulence_octaves(4.0, 8) == 0.0);  // (not below 0)
    CHECK(turbulence_octaves(1.0 / 3.0, 8) == doctest::Approx(std::log2(1.5) + 1.0));
    CHECK(turbulence_octaves(std::nan(""), 5) == 5.0);
    const glm::dvec3 p(3.7, -1.2, 0.4);
    const auto n = [&](double f) { return std::fabs(gradient_noise(f * p)); };
    const double m = 0.2;  // (any mean: the octaves not evaluated count by it)
    CHECK(turbulence(p, 1.0, 1, m) == n(1.0));
    CHECK(turbulence(p, 3.0, 3, m) == doctest::Approx(n(1) + n(2) / 2 + n(4) / 4).epsilon(1e-15));
    CHECK(turbulence(p, 2.5, 3, m) == doctest::Approx(n(1) + n(2) / 2 + (0.5 * n(4) + 0.5 * m) / 4).epsilon(1e-15));
    CHECK(turbulence(p, 2.0, 5, m) == doctest::Approx(n(1) + n(2) / 2 + m / 4 + m / 8 + m / 16).epsilon(1e-15));
    CHECK(turbulence(p, 3.0 - 1e-9, 5, m) == doctest::Approx(turbulence(p, 3.0, 5, m)).epsilon(1e-8));  // no jump at a whole count
    // The means the missing octaves take: |noise| over the plane z = 0 and over space.
    Sequence r;
    double plane = 0.0, space = 0.0;
    const int count = 1000000;
    for (int k = 0; k < count; ++k) {
        plane += std::fabs(gradient_noise({r.next() * 256.0, r.next() * 256.0, 0.0}));
        space += std::fabs(gradient_noise({r.next() * 256.0, r.next() * 256.0, r.next() * 256.0}));
    }
    CHECK(plane / count == doctest::Approx(mean_abs_noise_2d).epsilon(0.005));
    CHECK(space / count == doctest::Approx(mean_abs_noise_3d).epsilon(0.005));
    // Marble: the blend (1 + sin(x + amplitude turbulence)) / 2 from color0 to color1.
    Procedural marble = pattern(Pattern::marble, 2.0);
    marble.amplitude = 3.0, marble.octaves = 5;
    const glm::dvec3 at(0.4, 1.3, 0.0);
    const double t = 0.5 * (1.0 + std::sin(0.8 + 3.0 * turbulence(2.0 * at, 5.0, 5, mean_abs_noise_2d)));
    CHECK(procedural_value(marble, at, 0.0).x == doctest::Approx(t).epsilon(1e-6));
    // Its footprint in the texture's units is scaled too: 1/128 of a unit at scale 2 is 1/64
    // of the pattern's, 6 octaves of the 8 (the other 2 by their mean).
    // (and its sine is averaged over the footprint, 1/64 of the pattern's x: k = sin(f/2) / (f/2))
    const double k = std::sin(1.0 / 128.0) / (1.0 / 128.0);
    const double t6 = 0.5 * (1.0 + k * std::sin(0.8 + 3.0 * turbulence(2.0 * at, 6.0, 8, mean_abs_noise_2d)));
    marble.octaves = 8;
    CHECK(procedural_value(marble, at, 1.0 / 128.0).x == doctest::Approx(t6).epsilon(1e-6));
}

TEST_CASE("a procedural checkerboard and tile fill a frame pixel for pixel as worked out by hand, 2D and solid") {
    // A unit square at distance 0.5 seen at 90 degrees fills the 64x64 frame: pixel (x, y)'s
    // centre is at u = (x + 0.5) / 64, v = 1 - (y + 0.5) / 64 (v up, rows down), and at the
    // world position (u - 0.5, v - 0.5, 0).
    const std::string dir = scratch_folder("procedural-frame");
    const std::string head = "size 64 64\ncamera eye 0 0 0.5 target 0 0 0 fov 90\n";
    const std::string quad = "quad material m v -0.5 -0.5 0 0 0 v 0.5 -0.5 0 1 0 v 0.5 0.5 0 1 1 v -0.5 0.5 0 0 1\n";
    struct Case {
        std::string texture;
        int (*expected)(double u, double v);
    };
    const Case cases[] = {
        {"procedural checker scale 8", [](double u, double v) { return int(std::floor(8 * u) + std::floor(8 * v)) % 2; }},
        {"procedural checker scale 5 solid on",
         [](double u, double v) { return int(std::fabs(std::fmod(std::floor(5 * (u - 0.5)) + std::floor(5 * (v - 0.5)), 2.0))); }},
        {"procedural tile scale 4 mortar 0.25",
         [](double u, double v) { return (4 * u - std::floor(4 * u) < 0.25 || 4 * v - std::floor(4 * v) < 0.25) ? 1 : 0; }},
    };
    for (const Case& c : cases) {
        CAPTURE(c.texture);
        write_text(dir + "/s.scene", head + "texture t " + c.texture + " color0 0 0 0 color1 1 1 1\nmaterial m texture t\n" + quad);
        for (const std::string threads : {"1", "2"}) {
            const RunResult r = run_texr("render " + dir + "/s.scene -o " + dir + "/o.ppm --threads " + threads);
            REQUIRE(r.exit_code == 0);
            const std::string pixels = ppm_pixels(dir + "/o.ppm", 64, 64);
            int wrong = 0;
            for (int y = 0; y < 64; ++y)
                for (int x = 0; x < 64; ++x) {
                    const int want = c.expected((x + 0.5) / 64.0, 1.0 - (y + 0.5) / 64.0) ? 255 : 0;
                    const std::size_t i = 3 * std::size_t(y * 64 + x);
                    for (int k = 0; k < 3; ++k) wrong += std::uint8_t(pixels[i + std::size_t(k)]) != want;
                }
            CHECK(wrong == 0);
        }
    }
}

TEST_CASE("procedural textures in scene files: options, messages, --stats, explain, solid meshes without UVs, bench") {
    const std::string dir = scratch_folder("procedural-scenes");
    const std::string head = "size 32 24\ncamera eye 0 0 3 target 0 0 0\n";
    const std::string triangle = "triangle material m v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n";
    for (const auto& [line, message] : std::vector<std::pair<std::string, std::string>>{
             {"texture t procedural checker filter bilinear",
              "'filter' is an image texture's option: texture 't' is procedural (it has no texels to read, filter or wrap)"},
             {"texture t file x.png scale 2",
              "'scale' is a procedural texture's option: texture 't' reads an image (give 'procedural PATTERN' instead of 'file')"},
             {"texture t procedural tile solid on",
              "the tile pattern is 2D: 'solid on' applies to checker, noise, turbulence and marble"},
             {"texture t procedural checker mortar 0.1", "'mortar' applies to the tile and brick patterns, not to checker"},
             {"texture t procedural noise octaves 3", "'octaves' applies to the turbulence and marble patterns, not to noise"},
             {"texture t procedural turbulence amplitude 3", "'amplitude' applies to the marble pattern, not to turbulence"},
             {"texture t procedural marble octaves 0", "octaves must be a whole number from 1 to 30"},
             {"texture t procedural marble octaves 2.5", "octaves must be a whole number from 1 to 30"},
             {"texture t procedural checker scale 0", "the pattern's scale must be above 0 and at most 1e9"},
             {"texture t procedural brick mortar 1.5", "the mortar's width must be between 0 and 1 (a fraction of a cell)"},
             {"texture t procedural", "expected procedural pattern after 'procedural', found the end of the line"},
             {"texture t", "texture 't' needs 'file PATH' (or 'procedural PATTERN')"},
         }) {
        CAPTURE(line);
        write_text(dir + "/bad.scene", head + line + "\nmaterial m texture t\n" + triangle);
        const RunResult r = run_texr("render " + dir + "/bad.scene -o " + dir + "/bad.png");
        CHECK(r.exit_code == 1);
        CHECK(r.output == "texr: " + dir + "/bad.scene:3: " + message + "\n");
        CHECK_FALSE(file_exists(dir + "/bad.png"));
    }
    // --stats names each procedural texture; the material's needs follow its pattern.
    write_text(dir + "/s.scene", head + "texture t procedural marble scale 4 amplitude 2\ntexture c procedural checker solid on\n"
                                        "material m texture t\nmaterial n texture c\n" + triangle +
                                        "triangle material n v -1 -1 -0.5 0 0 v 1 -1 -0.5 1 0 v 0 1 -0.5 0.5 1\n");
    RunResult r = run_texr("render " + dir + "/s.scene -o " + dir + "/s.ppm --stats");
    REQUIRE(r.exit_code == 0);
    CHECK(r.output.find("texture t            procedural marble: no texels\n") != std::string::npos);
    CHECK(r.output.find("texture c            procedural checker, solid: no texels\n") != std::string::npos);
    CHECK(r.output.find(" needs uv, uv derivatives; skips normal, vertex colour, world position\n") != std::string::npos);  // m
    CHECK(r.output.find(" needs world position; skips uv, uv derivatives, normal, vertex colour\n") != std::string::npos);  // n
    CHECK(r.output.find("texels fetched     0\n") != std::string::npos);
    // explain tells the checker's cell and parity at a pixel the triangle covers.
    write_text(dir + "/e.scene", head + "texture c procedural checker scale 4 color0 0 0 0 color1 1 1 1\nmaterial m texture c\n" + triangle);
    r = run_texr("explain " + dir + "/e.scene 16 14");
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("5. Texture 'c' (procedural checker; no texels, filter or wrap):\n") != std::string::npos);
    CHECK(r.output.find("    pattern coordinates = scale 4 x (u, v, 0) = (") != std::string::npos);
    CHECK(r.output.find("): parity (lu + lv) % 2 = ") != std::string::npos);
    // A mesh without texture coordinates takes a solid texture, not a 2D one.
    write_text(dir + "/flat.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
    write_text(dir + "/m.scene", head + "texture c procedural checker solid on\nmaterial m texture c\nmesh flat.obj material m\n");
    CHECK(run_texr("render " + dir + "/m.scene -o " + dir + "/m.ppm").exit_code == 0);
    write_text(dir + "/m2.scene", head + "texture c procedural checker\nmaterial m texture c\nmesh flat.obj material m\n");
    r = run_texr("render " + dir + "/m2.scene -o " + dir + "/m2.ppm");
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("has faces without texture coordinates (vt) drawn with material 'm', which uses texture 'c'") != std::string::npos);
    // texr bench scores image textures: a procedural one in its scenes is refused.
    std::system(("mkdir -p " + dir + "/models/bench").c_str());
    write_text(dir + "/models/bench/plane.scene", head + "texture c procedural checker\nmaterial m texture c\n" + triangle);
    r = run_texr("bench threads --quick --models " + dir + "/models --out " + dir + "/out");
    CHECK(r.exit_code == 1);
    CHECK(r.output == "texr: " + dir + "/models/bench/plane.scene: texture 'c' is procedural: texr bench times and scores image "
                                      "textures (their filters and span modes)\n");
}

TEST_CASE("turbulence on a receding plane: fewer octaves where pixels cover more, the same bytes on any thread count") {
    const std::string dir = scratch_folder("procedural-turbulence");
    write_text(dir + "/p.scene", "size 96 72\ncamera eye 0 1 0 target 0 0.75 -4 fov 60\n"
                                 "texture t procedural turbulence scale 2 octaves 10\nmaterial m texture t\n"
                                 "quad material m v -50 0 5 0 0 v 50 0 5 100 0 v 50 0 -95 100 100 v -50 0 -95 0 100\n");
    REQUIRE(run_texr("render " + dir + "/p.scene -o " + dir + "/a.ppm --threads 1").exit_code == 0);
    REQUIRE(run_texr("render " + dir + "/p.scene -o " + dir + "/b.ppm --threads 3").exit_code == 0);
    CHECK(read_file(dir + "/a.ppm") == read_file(dir + "/b.ppm"));
    // explain's octave count against log2(1 / (2 f)) + 1 for the footprint f it prints, and
    // fewer octaves near the horizon (row 40) than near the eye (row 71).
    double octaves_at[2] = {0, 0};
    int k = 0;
    for (const int row : {40, 71}) {
        const RunResult r = run_texr("explain " + dir + "/p.scene 48 " + std::to_string(row));
        REQUIRE(r.exit_code == 0);
        const std::size_t at = r.output.find("    footprint ");
        REQUIRE(at != std::string::npos);
        const double f = std::stod(r.output.substr(at + 14));
        const std::size_t kept = r.output.find("2 footprints: ", at);
        REQUIRE(kept != std::string::npos);
        const double octaves = std::stod(r.output.substr(kept + 14));
        CAPTURE(r.output);
        CHECK(octaves == doctest::Approx(std::min(10.0, std::max(0.0, std::log2(1.0 / (2.0 * f)) + 1.0))).epsilon(1e-3));
        octaves_at[k++] = octaves;
    }
    CHECK(octaves_at[0] < octaves_at[1]);
}

TEST_CASE("every gradient direction occurs, as often as the 16-entry table makes it, and the patterns' blends are the docs'") {
    // Over 64^3 lattice points: the 8 directions listed once take about 1/16 each, the 4 listed
    // twice about 2/16.
    std::map<std::tuple<int, int, int>, int> counts;
    const int n = 64;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                const glm::dvec3 g = lattice_gradient(i, j, k);
                ++counts[{int(g.x), int(g.y), int(g.z)}];
            }
    CHECK(counts.size() == 12);
    const double total = double(n) * n * n;
    for (const auto& [g, count] : counts) {
        const auto [x, y, z] = g;
        const bool twice = (x == 1 && y == 1 && z == 0) || (x == -1 && y == 1 && z == 0) || (x == 0 && y == -1 && z == 1) ||
                           (x == 0 && y == -1 && z == -1);
        CAPTURE(x);
        CAPTURE(y);
        CAPTURE(z);
        CHECK(count / total == doctest::Approx((twice ? 2.0 : 1.0) / 16.0).epsilon(0.15));
    }
    // noise: (w n + 1) / 2 from color0 (0) to color1 (1), w = clamp(log2(1 / (2 f)) + 1, 0, 1).
    const Procedural noise = pattern(Pattern::noise);
    const glm::dvec3 at(3.3, 7.1, 0.0);
    const double n0 = gradient_noise(at);
    CHECK(procedural_value(noise, at, 0.0).x == doctest::Approx((n0 + 1.0) / 2.0).epsilon(1e-6));
    CHECK(procedural_value(noise, at, 1.0 / 3.0).x == doctest::Approx((n0 + 1.0) / 2.0).epsilon(1e-6));  // w = 1
    CHECK(procedural_value(noise, at, 1.0).x == 0.5f);  // w = 0: its mean
    const double w = std::log2(1.0 / 1.4) + 1.0;
    CHECK(procedural_value(noise, at, 0.7).x == doctest::Approx((w * n0 + 1.0) / 2.0).epsilon(1e-6));
    // turbulence: min(1, turbulence), at every octave for a point.
    Procedural turb = pattern(Pattern::turbulence, 3.0);
    turb.octaves = 4;
    const double t = turbulence(3.0 * at, 4.0, 4, mean_abs_noise_2d);
    REQUIRE(t < 1.0);
    CHECK(procedural_value(turb, at, 0.0).x == doctest::Approx(t).epsilon(1e-6));
    // Not finite: color0, for every pattern.
    for (int p = 0; p < pattern_count; ++p) CHECK(procedural_value(pattern(Pattern(p), 3.0), {1e308, 1e308, 0.0}, 0.0) == Color4(0, 0, 0, 1));
    CHECK(turbulence_octaves(INFINITY, 8) == 0.0);
    // Checker cells far beyond 2^53 keep their parity: (2^60, 1) is odd.
    CHECK(which(pattern(Pattern::checker), std::ldexp(1.0, 60), 1.5) == 1);
}

TEST_CASE("a solid checkerboard on a floor lying on a cell boundary is one cell deep, not speckled, and explain says what was written") {
    // A floor at y = 1 under a solid checkerboard of scale 1: its cells are those of
    // (floor(x) + 1 + floor(z)) mod 2, every pixel's point found by unprojecting its centre.
    const std::string dir = scratch_folder("procedural-boundary");
    Camera camera;
    camera.eye = {0.3, 2, 0.2}, camera.target = {0, 1, -4}, camera.fov_y_degrees = 60;
    write_text(dir + "/f.scene", "size 80 60\ncamera eye 0.3 2 0.2 target 0 1 -4 up 0 1 0 fov 60\n"
                                 "texture floor procedural checker scale 1 solid on color0 0 0 0 color1 1 1 1\nmaterial fl texture floor\n"
                                 "quad material fl v -50 1 50 0 0 v 50 1 50 1 0 v 50 1 -50 1 1 v -50 1 -50 0 1\n");
    REQUIRE(run_texr("render " + dir + "/f.scene -o " + dir + "/f.ppm").exit_code == 0);
    const std::string pixels = ppm_pixels(dir + "/f.ppm", 80, 60);
    const glm::dmat4 inverse = glm::inverse(projection_matrix(camera, 80.0 / 60.0) * view_matrix(camera));
    int checked = 0, wrong = 0;
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 80; ++x) {
            const glm::dvec4 far = inverse * glm::dvec4(2.0 * (x + 0.5) / 80 - 1.0, 1.0 - 2.0 * (y + 0.5) / 60, 1.0, 1.0);
            const glm::dvec3 ray = glm::dvec3(far) / far.w - camera.eye;
            if (!(ray.y < -1e-3)) continue;  // (the sky)
            const glm::dvec3 point = camera.eye + ray * ((1.0 - camera.eye.y) / ray.y);
            // (the corners' 1/256-pixel snapping moves the floor's points by some 1e-4 of their
            // distance: pixels that near a cell's side in x or z are left alone)
            const double margin = 1e-4 * glm::length(point - camera.eye);
            if (std::fabs(point.x - std::round(point.x)) < margin || std::fabs(point.z - std::round(point.z)) < margin) continue;
            if (std::fabs(point.x) > 49 || std::fabs(point.z) > 49) continue;
            const int want = int(std::fabs(std::fmod(std::floor(point.x) + 1.0 + std::floor(point.z), 2.0))) ? 255 : 0;
            ++checked;
            if (std::uint8_t(pixels[3 * std::size_t(y * 80 + x)]) != want) {
                ++wrong;
                MESSAGE("pixel " << x << ", " << y << " at (" << point.x << ", " << point.z << ")");
            }
        }
    CHECK(checked > 2000);
    CHECK(wrong == 0);
    // explain's bytes are the frame's, for 2D and solid patterns, along a row.
    write_text(dir + "/all.scene",
               "size 80 60\ncamera eye 0 1.2 3 target 0 0.4 0 fov 60\nlight directional -0.3 -1 -0.4\nambient 0.2 0.2 0.2\n"
               "texture a procedural marble scale 3 amplitude 2\ntexture b procedural turbulence scale 2 solid on\n"
               "texture c procedural noise scale 6\ntexture d procedural brick scale 3\n"
               "texture e procedural marble scale 2 solid on\ntexture f procedural checker scale 2.5 solid on\n"
               "material ma texture a\nmaterial mb texture b lighting lambert\nmaterial mc texture c\nmaterial md texture d\n"
               "material me texture e\nmaterial mf texture f\n"
               "quad material ma v -3 0 3 0 0 v -1 0 3 1 0 v -1 0 -3 1 3 v -3 0 -3 0 3\n"
               "quad material mb v -1 0 3 0 0 v 1 0 3 1 0 v 1 0 -3 1 3 v -1 0 -3 0 3\n"
               "quad material mc v 1 0 3 0 0 v 3 0 3 1 0 v 3 0 -3 1 3 v 1 0 -3 0 3\n"
               "quad material md v -3 0 -3 0 0 v -1 0 -3 1 0 v -1 2 -3 1 1 v -3 2 -3 0 1\n"
               "quad material me v -1 0 -3 0 0 v 1 0 -3 1 0 v 1 2 -3 1 1 v -1 2 -3 0 1\n"
               "quad material mf v 1 0 -3 0 0 v 3 0 -3 1 0 v 3 2 -3 1 1 v 1 2 -3 0 1\n");
    REQUIRE(run_texr("render " + dir + "/all.scene -o " + dir + "/all.ppm").exit_code == 0);
    const std::string all = ppm_pixels(dir + "/all.ppm", 80, 60);
    int compared = 0;
    for (const int y : {12, 30, 50})
        for (int x = 1; x < 80; x += 6) {
            const RunResult r = run_texr("explain " + dir + "/all.scene " + std::to_string(x) + " " + std::to_string(y));
            REQUIRE(r.exit_code == 0);
            const std::array<int, 3> rgb = explained_bytes(r.output);
            CAPTURE(x);
            CAPTURE(y);
            for (int k = 0; k < 3; ++k) CHECK(rgb[k] == int(std::uint8_t(all[3 * std::size_t(y * 80 + x) + std::size_t(k)])));
            compared += r.output.find("(procedural ") != std::string::npos;
        }
    CHECK(compared >= 30);
    // A solid turbulence floor is band-limited by the world position's footprint: fewer
    // octaves far off (row 29, below the horizon at row 26.7) than near (row 59).
    write_text(dir + "/solid.scene", "size 80 60\ncamera eye 0 1 0 target 0 0.75 -4 fov 60\n"
                                     "texture t procedural turbulence scale 2 solid on octaves 10\nmaterial m texture t\n"
                                     "quad material m v -50 0 5 0 0 v 50 0 5 1 0 v 50 0 -95 1 1 v -50 0 -95 0 1\n");
    double octaves[2];
    int k = 0;
    for (const int row : {29, 59}) {
        const RunResult r = run_texr("explain " + dir + "/solid.scene 40 " + std::to_string(row));
        const std::size_t kept = r.output.find("2 footprints: ");
        REQUIRE(kept != std::string::npos);
        octaves[k++] = std::stod(r.output.substr(kept + 14));
    }
    CHECK(octaves[0] < octaves[1]);
    CHECK(octaves[0] < 10.0);
}
