// Golden images: small frames of the demo scenes compared with committed PNGs under
// tests/golden/. Tolerance: every channel within 3 levels of 255 and a mean difference
// under 0.1 level, which allows for a C library whose pow, exp or sin round differently (the
// frames are the same bytes across g++ and clang, Release and Debug, on x86-64), but not a
// changed picture. Each golden image was inspected by eye when it was committed; a changed golden
// image needs its reason in the commit message.
// To rewrite them after an intended change: TEXR_UPDATE_GOLDEN=1 ./build/texr_tests -tc='golden*'
#include <doctest/doctest.h>

#include <stb_image.h>

#include <cstdlib>
#include <cmath>

#include "helpers.h"
#include "texr/io/frame_writer.h"
#include "texr/render/renderer.h"
#include "texr/scene/parser.h"

using namespace texr;

namespace {

void check_golden(const std::string& scene_file, int width, int height, const std::string& golden_name,
                  const Filter* filter = nullptr) {
    Scene scene = load_scene(testing::source_path(scene_file));
    if (filter)
        for (Texture& t : scene.textures) t.sampler.filter = *filter;
    RenderStats stats;
    const Framebuffer fb = render(scene, {width, height}, stats);
    const std::string golden = testing::source_path("tests/golden/" + golden_name);
    if (std::getenv("TEXR_UPDATE_GOLDEN")) {
        write_frame(fb, golden);
        MESSAGE("rewrote " << golden);
        return;
    }
    int w = 0, h = 0, channels = 0;
    unsigned char* expected = stbi_load(golden.c_str(), &w, &h, &channels, 3);
    REQUIRE_MESSAGE(expected != nullptr, "cannot read golden image " << golden);
    REQUIRE(w == width);
    REQUIRE(h == height);
    const std::vector<std::uint8_t> got = encode_srgb8(fb);
    int worst = 0;
    double total = 0.0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        const int d = std::abs(int(got[i]) - int(expected[i]));
        worst = std::max(worst, d);
        total += d;
    }
    stbi_image_free(expected);
    const double mean = total / double(got.size());
    MESSAGE(golden_name << ": worst channel difference " << worst << ", mean " << mean);
    CHECK(worst <= 3);
    CHECK(mean < 0.1);
}

}  // namespace

TEST_CASE("golden: textured plane receding to the horizon") { check_golden("models/plane.scene", 160, 120, "plane.png"); }

TEST_CASE("golden: demo scene (plane, lit torus, OBJ cube with two materials)") {
    check_golden("models/demo.scene", 200, 150, "demo.png");
}

TEST_CASE("golden: procedural textures (checkerboard, brick, marble, turbulence, a solid checkerboard box)") {
    check_golden("models/procedural.scene", 200, 150, "procedural.png");
}

TEST_CASE("golden: the lecture's techniques together (environment, reflection, bump, slope, light map, billboards, parametric)") {
    check_golden("models/lecture.scene", 200, 150, "lecture.png");
}

TEST_CASE("golden: every filter on the receding benchmark plane") {
    for (int f = 0; f < filter_count; ++f) {
        const Filter filter = Filter(f);
        CAPTURE(filter_name(filter));
        check_golden("models/bench/plane.scene", 192, 144, std::string("plane-") + filter_name(filter) + ".png", &filter);
    }
}

TEST_CASE("a PNG frame decodes to exactly the 8-bit sRGB bytes it was encoded from, as the PPM holds them") {
    // PNG is lossless whatever filter and compression level the writer chooses; stb_image's
    // decoder is the independent reader. Frames: the textured demo (noisy texels) and the
    // plane (large flat sky), at a size whose rows are not a multiple of 4 bytes.
    for (const char* file : {"models/demo.scene", "models/plane.scene"}) {
        CAPTURE(file);
        const Scene scene = load_scene(testing::source_path(file));
        RenderStats stats;
        const Framebuffer fb = render(scene, {161, 97}, stats);
        const std::vector<std::uint8_t> rgb = encode_srgb8(fb), png = encode_frame(fb, FrameFormat::png),
                                        ppm = encode_frame(fb, FrameFormat::ppm);
        int w = 0, h = 0, channels = 0;
        unsigned char* decoded = stbi_load_from_memory(png.data(), int(png.size()), &w, &h, &channels, 3);
        REQUIRE(decoded != nullptr);
        CHECK(w == 161);
        CHECK(h == 97);
        CHECK(channels == 3);
        CHECK(std::vector<std::uint8_t>(decoded, decoded + rgb.size()) == rgb);
        stbi_image_free(decoded);
        const std::string header = "P6\n161 97\n255\n";
        REQUIRE(ppm.size() == header.size() + rgb.size());
        CHECK(std::vector<std::uint8_t>(ppm.begin() + long(header.size()), ppm.end()) == rgb);
        CHECK(png.size() < rgb.size() / 2);  // compressed, not stored
    }
}
