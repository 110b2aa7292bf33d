// Bump mapping (texture/bump.h): a height ramp on a square whose every shaded pixel is worked
// out by hand from the lecture's N' = N + D, the same with mirrored texture coordinates, the
// same scene turned a quarter turn, and the scene file's rules.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "helpers.h"
#include "texr/texture/bump.h"

using namespace texr;
using namespace texr::testing;

namespace {

// The 8-bit sRGB byte of a linear value (IEC 61966-2-1), rounded.
int srgb_byte(double linear) {
    const double c = linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
    return int(std::lround(255.0 * std::clamp(c, 0.0, 1.0)));
}

// A 16x16 grey ramp along x: texel column i holds byte 16 i, read (linear) as 16 i / 255.
std::string ramp_pgm() {
    std::string pgm = "P5\n16 16\n255\n";
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) pgm += char(16 * x);
    return pgm;
}

// Renders `scene` to a 64x64 PPM in `dir` and returns its pixels.
std::string render_pixels(const std::string& dir, const std::string& scene) {
    write_text(dir + "/s.scene", scene);
    const RunResult r = run_texr("render " + dir + "/s.scene -o " + dir + "/o.ppm");
    CAPTURE(r.output);
    REQUIRE(r.exit_code == 0);
    const std::string ppm = read_file(dir + "/o.ppm");
    const std::string header = "P6\n64 64\n255\n";
    REQUIRE(ppm.size() == header.size() + 64 * 64 * 3);
    return ppm.substr(header.size());
}

}  // namespace

TEST_CASE("surface tangents solve the two edge equations, and the bumped normal is the lecture's N + D") {
    const glm::dvec3 p[3] = {{1, 2, 3}, {3, 2, 3}, {1, 2, 0}};
    const double u[3] = {0.0, 0.5, 0.0}, v[3] = {0.0, 0.0, 0.25};
    const SurfaceTangents t = surface_tangents(p, u, v);
    // p1 - p0 = (2, 0, 0) over du 0.5: O_u = (4, 0, 0); p2 - p0 = (0, 0, -3) over dv 0.25: O_v = (0, 0, -12).
    CHECK(t.o_u == glm::dvec3(4, 0, 0));
    CHECK(t.o_v == glm::dvec3(0, 0, -12));
    // O_u x O_v = (0, 48, 0): along N = (0, 1, 0), area 48. N + (B_u (N x O_v) - B_v (N x O_u)) / 48.
    BumpSlope slope;
    slope.b_u = 2.0, slope.b_v = -3.0;
    const glm::dvec3 n(0, 1, 0);
    // N x O_v = (1 * -12 - 0, 0, 0) = (-12, 0, 0); N x O_u = (0, 0, -4).
    const glm::dvec3 expected = n + (2.0 * glm::dvec3(-12, 0, 0) - -3.0 * glm::dvec3(0, 0, -4)) / 48.0;
    const glm::dvec3 got = bumped_normal(n, t, slope);
    CHECK(got.x == doctest::Approx(expected.x));
    CHECK(got.y == doctest::Approx(expected.y));
    CHECK(got.z == doctest::Approx(expected.z));
    // The other side (N against O_u x O_v): the same tilt, seen from there.
    const glm::dvec3 flipped = bumped_normal(-n, t, slope);
    CHECK(flipped.y == doctest::Approx(-1.0));
    CHECK(flipped.x == doctest::Approx(-(-2.0 * -12.0 / 48.0)));
    // Degenerate UVs: no tangents, the normal as it is.
    const double same[3] = {0.5, 0.5, 0.5};
    CHECK(bumped_normal(n, surface_tangents(p, same, v), slope) == n);
}

TEST_CASE("a bump ramp tilts a square's normal by its slope: every pixel's shade by hand, mirrored UVs, a quarter turn") {
    // A unit square at z = 0 fills the 64x64 frame (eye at distance 0.5, 90 degrees); its UVs
    // run 0..1 across it, so O_u = (1, 0, 0), O_v = (0, 1, 0) and |O_u x O_v| = 1. The ramp,
    // bilinear with clamp (cell registration), is B(u) = H (16 / 255)(16 u - 1/2) between the
    // first and last texel centres, so B_u = H 256 / 255 there (its central difference over one
    // texel is exact on a line) and B_v = 0. With H = 0.255, B_u = 0.256:
    //   N' = N + B_u (N x O_v) = (0, 0, 1) + 0.256 (-1, 0, 0) = (-0.256, 0, 1).
    const std::string dir = scratch_folder("bump-ramp");
    write_text(dir + "/ramp.pgm", ramp_pgm());
    const double b_u = 0.256, length = std::sqrt(1.0 + b_u * b_u);
    struct Case {
        const char* what;
        std::string quad, camera, light;
        double expected;  // the irradiance, max(0, N' . L) / |N'|
    };
    const std::string square = "quad material m v -0.5 -0.5 0 0 0 v 0.5 -0.5 0 1 0 v 0.5 0.5 0 1 1 v -0.5 0.5 0 0 1";
    const std::string mirrored = "quad material m v -0.5 -0.5 0 1 0 v 0.5 -0.5 0 0 0 v 0.5 0.5 0 0 1 v -0.5 0.5 0 1 1";
    const std::string front = "camera eye 0 0 0.5 target 0 0 0 fov 90\n";
    const Case cases[] = {
        {"light along -z", square, front, "light directional 0 0 -1", 1.0 / length},
        {"light from +x", square, front, "light directional -1 0 -1", (1.0 - b_u) / std::sqrt(2.0) / length},
        // Mirrored: u grows towards -x, the height too, so the normal tilts to +x: (0.256, 0, 1).
        {"mirrored UVs, light from +x", mirrored, front, "light directional -1 0 -1", (1.0 + b_u) / std::sqrt(2.0) / length},
        // The whole scene turned 90 degrees about y ((x, y, z) -> (z, y, -x)): the same picture.
        {"a quarter turn", square + " rotate 90 0 1 0", "camera eye 0.5 0 0 target 0 0 0 fov 90\n", "light directional -1 0 1",
         (1.0 - b_u) / std::sqrt(2.0) / length},
    };
    for (const Case& c : cases) {
        CAPTURE(c.what);
        const std::string scene = "size 64 64\n" + c.camera + "ambient 0 0 0\n" + c.light +
                                  " color 1 1 1\ntexture ramp file ramp.pgm colorspace linear wrap clamp\n"
                                  "material m color 1 1 1 lighting lambert bump ramp 0.255\n" + c.quad + "\n";
        const std::string pixels = render_pixels(dir, scene);
        const int want = srgb_byte(c.expected);
        int checked = 0, off = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                // Columns whose u (or 1 - u, mirrored) keeps u +- 1/16 between the first and last
                // texel centres, 1.5/16 to 14.5/16, with a pixel to spare.
                const double u = (x + 0.5) / 64.0;
                if (u < 1.6 / 16.0 || u > 14.4 / 16.0) continue;
                const std::size_t i = 3 * std::size_t(y * 64 + x);
                for (int k = 0; k < 3; ++k) off += std::abs(int(std::uint8_t(pixels[i + std::size_t(k)])) - want) > 1;
                ++checked;
            }
        CHECK(checked > 2900);
        CHECK(off == 0);
    }
    // Without the bump map the square is flat: the first light's full irradiance, 255.
    const std::string flat = render_pixels(dir, "size 64 64\n" + front + "ambient 0 0 0\nlight directional 0 0 -1 color 1 1 1\n"
                                                "material m color 1 1 1 lighting lambert\n" + square + "\n");
    CHECK(std::uint8_t(flat[3 * (32 * 64 + 32)]) == 255);
    // explain tells the slope, the tangents and N'.
    write_text(dir + "/e.scene", "size 64 64\n" + front + "ambient 0 0 0\nlight directional 0 0 -1 color 1 1 1\n"
                                 "texture ramp file ramp.pgm colorspace linear wrap clamp\n"
                                 "material m color 1 1 1 lighting lambert bump ramp 0.255\n" + square + "\n");
    const RunResult r = run_texr("explain " + dir + "/e.scene 32 32");
    CAPTURE(r.output);
    CHECK(r.output.find("      B_u = (B(u + h, v) - B(u - h, v)) / 2h = 0.256 (h = 0.0625), B_v = 0 (h = 0.0625) (h: a texel, or the "
                        "pixel's footprint where wider)\n") != std::string::npos);
    CHECK(r.output.find("      the triangle's O_u = (1, 0, 0), O_v = (0, 1, 0); |O_u x O_v| = 1 (along N: s = 1)\n") != std::string::npos);
    CHECK(r.output.find(", normalised: (-0.24800, 0.00000, 0.96876)\n") != std::string::npos);  // (-0.256, 0, 1) / 1.03225
}

TEST_CASE("bump maps in scene files: lighting, solid textures, meshes without UVs, a material without a texture") {
    const std::string dir = scratch_folder("bump-scenes");
    const std::string head = "size 32 24\ncamera eye 0 0 3 target 0 0 0\nlight directional 0 0 -1\ntexture n procedural noise scale 4\n";
    const std::string triangle = "triangle material m v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n";
    for (const auto& [line, message] : std::vector<std::pair<std::string, std::string>>{
             {"material m bump n 0.1", "a bump map changes only the shading normal: material 'm' needs 'lighting lambert' or 'reflect' for it to show"},
             {"material m lighting lambert bump nope 0.1", "unknown texture 'nope' (define it with a 'texture' line first)"},
             {"material m lighting lambert bump n x",
              "expected the bump's height (world units for a texture value of 1), found 'x'"},
             {"material m lighting lambert bump n 2e6", "the bump's height must be between -1e6 and 1e6"},
         }) {
        CAPTURE(line);
        write_text(dir + "/bad.scene", head + line + "\n" + triangle);
        const RunResult r = run_texr("render " + dir + "/bad.scene -o " + dir + "/bad.png");
        CHECK(r.exit_code == 1);
        CHECK(r.output == "texr: " + dir + "/bad.scene:5: " + message + "\n");
        CHECK_FALSE(file_exists(dir + "/bad.png"));
    }
    write_text(dir + "/solid.scene", head + "texture s procedural noise solid on\nmaterial m lighting lambert bump s 0.1\n" + triangle);
    RunResult r = run_texr("render " + dir + "/solid.scene -o " + dir + "/o.png");
    CHECK(r.exit_code == 1);
    CHECK(r.output == "texr: " + dir + "/solid.scene:6: texture 's' is solid: a bump map is read at (u, v) (leave out 'solid on')\n");
    // A mesh without texture coordinates cannot be bump-mapped.
    write_text(dir + "/flat.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
    write_text(dir + "/mesh.scene", head + "material m lighting lambert bump n 0.1\nmesh flat.obj material m\n");
    r = run_texr("render " + dir + "/mesh.scene -o " + dir + "/o.png");
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("has faces without texture coordinates (vt) drawn with material 'm', which uses texture 'n' as its bump map") !=
          std::string::npos);
    // A bump map is read at the scene's (u, v), whatever the material's own texture and its wrap
    // (the setup moves a triangle's (u, v) by whole periods of that texture's wrap): on UVs
    // from 1 to 2, with and without a white texture of wrap repeat, the same picture.
    write_text(dir + "/white.ppm", std::string("P6\n1 1\n255\n\xff\xff\xff", 14));
    const std::string quads = "quad material m v -1 -1 0 1 1 v 0 -1 0 2 1 v 0 1 0 2 2 v -1 1 0 1 2\n"
                              "quad material m v 0 -1 0 2 1 v 1 -1 0 3 1 v 1 1 0 3 2 v 0 1 0 2 2\n";
    write_text(dir + "/plain.scene", head + "material m lighting lambert bump n 0.05\n" + quads);
    write_text(dir + "/white.scene", head + "texture w file white.ppm wrap repeat\nmaterial m texture w lighting lambert bump n 0.05\n" + quads);
    REQUIRE(run_texr("render " + dir + "/plain.scene -o " + dir + "/plain.ppm").exit_code == 0);
    REQUIRE(run_texr("render " + dir + "/white.scene -o " + dir + "/textured.ppm").exit_code == 0);
    CHECK(read_file(dir + "/plain.ppm") == read_file(dir + "/textured.ppm"));
    // Likewise a light map (clamped, so that where it is read shows): on those UVs, / 2.
    write_text(dir + "/lplain.scene", head + "texture l procedural noise scale 3\nmaterial m lightmap l lightmap_repeat 2\n" + quads);
    write_text(dir + "/lwhite.scene", head + "texture l procedural noise scale 3\ntexture w file white.ppm wrap repeat\n"
                                             "material m texture w lightmap l lightmap_repeat 2\n" + quads);
    REQUIRE(run_texr("render " + dir + "/lplain.scene -o " + dir + "/lplain.ppm").exit_code == 0);
    REQUIRE(run_texr("render " + dir + "/lwhite.scene -o " + dir + "/lwhite.ppm").exit_code == 0);
    CHECK(read_file(dir + "/lplain.ppm") == read_file(dir + "/lwhite.ppm"));
    // A bump map on a material with no texture of its own, on 1 and 3 threads and every span
    // mode: drawn, and the same bytes for every thread count.
    write_text(dir + "/ok.scene", head + "material m lighting lambert bump n 0.05\n" + triangle);
    for (const std::string span : {"incremental", "exact", "affine16", "adaptive"}) {
        CAPTURE(span);
        REQUIRE(run_texr("render " + dir + "/ok.scene -o " + dir + "/a.ppm --threads 1 --span " + span).exit_code == 0);
        REQUIRE(run_texr("render " + dir + "/ok.scene -o " + dir + "/b.ppm --threads 3 --span " + span).exit_code == 0);
        CHECK(read_file(dir + "/a.ppm") == read_file(dir + "/b.ppm"));
    }
    r = run_texr("render " + dir + "/ok.scene -o " + dir + "/a.ppm --stats");
    CHECK(r.output.find(" needs uv, uv derivatives, normal, world position; skips vertex colour\n") != std::string::npos);
}
