// Image loading (PNG, JPEG, TGA, BMP, Radiance HDR through stb_image), orientation, colour
// spaces, and filtering in linear space.
#include <doctest/doctest.h>

#include <stb_image_write.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>
#include <thread>
#include <vector>

#include "helpers.h"
#include "texr/core/color.h"
#include "texr/render/renderer.h"
#include "texr/scene/parser.h"
#include "texr/texture/image.h"
#include "texr/texture/reconstruct.h"

using namespace texr;

namespace {

// A 4 x 2 image whose file rows are: top = red, green, blue, white; bottom = grey levels.
constexpr int w = 4, h = 2;
const std::uint8_t pixels[w * h * 3] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255,
                                        0,   0, 0, 64, 64, 64, 128, 128, 128, 192, 192, 192};

// The scene `text` (file paths relative to models/), parsed and rendered once with the
// default options; `pixels`: the pixels the frame shaded.
Scene render_scene_text(const std::string& text, std::uint64_t& pixels) {
    std::istringstream in(text);
    Scene scene = parse_scene(in, testing::source_path("models/textures.scene"));
    RenderStats stats;
    render(scene, {}, stats);
    pixels = stats.pixels_shaded;
    return scene;
}

}  // namespace

TEST_CASE("PNG, TGA, BMP and JPEG load with v = 0 at the bottom row of the file") {
    const std::string dir = testing::scratch_folder("formats");
    REQUIRE(stbi_write_png((dir + "/a.png").c_str(), w, h, 3, pixels, w * 3));
    REQUIRE(stbi_write_tga((dir + "/a.tga").c_str(), w, h, 3, pixels));
    REQUIRE(stbi_write_bmp((dir + "/a.bmp").c_str(), w, h, 3, pixels));
    REQUIRE(stbi_write_jpg((dir + "/a.jpg").c_str(), w, h, 3, pixels, 100));
    for (const char* name : {"a.png", "a.tga", "a.bmp", "a.jpg"}) {
        CAPTURE(name);
        const Image image = load_image(dir + "/" + name, ColorSpace::linear);
        REQUIRE(image.width() == w);
        REQUIRE(image.height() == h);
        const double tolerance = std::string(name) == "a.jpg" ? 12.0 / 255.0 : 1e-6;  // JPEG is lossy
        for (int i = 0; i < w; ++i)
            for (int row = 0; row < h; ++row) {
                const Color4 t = image.texel(i, h - 1 - row);  // file row 0 is texel row h - 1
                for (int c = 0; c < 3; ++c) CHECK(std::fabs(t[c] - pixels[(row * w + i) * 3 + c] / 255.0) <= tolerance);
                CHECK(t[3] == 1.0f);
            }
    }
}

TEST_CASE("PPM and PGM samples are read against the header's largest value") {
    // Sample k of largest value m means k / m (stb_image reads k / 255 whatever m is): read as
    // data (k / 255 of the 8-bit texel), so the texel is k / m to within half an 8-bit step,
    // exactly where m divides 255.
    const std::string dir = testing::scratch_folder("pnm-largest");
    struct Case {
        std::string header, samples;
        int largest;
    };
    for (const Case& c : {Case{"P6\n2 1\n3\n", std::string("\x00\x01\x02\x03\x03\x00", 6), 3},
                          Case{"P5\n3 1\n15\n", std::string("\x0f\x07\x01", 3), 15},
                          Case{"P5\n3 1\n200\n", std::string("\x64\xc8\x01", 3), 200},
                          Case{"P5\n2 1\n255\n", std::string("\x80\xff", 2), 255}}) {
        CAPTURE(c.header);
        testing::write_text(dir + "/t.pnm", c.header + c.samples);
        const Image image = load_image(dir + "/t.pnm", ColorSpace::linear);
        const bool rgb = c.header[1] == '6';
        REQUIRE(image.width() == int(c.samples.size()) / (rgb ? 3 : 1));
        for (int i = 0; i < image.width(); ++i)
            for (int channel = 0; channel < 3; ++channel) {
                const int k = static_cast<unsigned char>(c.samples[std::size_t(rgb ? 3 * i + channel : i)]);
                const double want = double(k) / c.largest;
                const double tolerance = 255 % c.largest == 0 ? 1e-6 : 0.5 / 255.0 + 1e-6;
                CHECK(std::fabs(image.texel(i, 0)[channel] - want) <= tolerance);
            }
    }
    // A comment may start right after a number: the header's numbers are 2, 1 and the value
    // after the comment (stb_image reads them so, and texr scales by that value).
    for (const auto& [file, white] : std::vector<std::pair<std::string, double>>{
             {"P5\n2 1#200 GIMP\n255\n" + std::string("\x00\x80", 2), 128.0 / 255.0},  // largest 255: 0x80 as is
             {"P5\n2 1#5\n3\n" + std::string("\x00\x03", 2), 1.0},                    // largest 3: 3 is white
             {"P5\n2 1#3\n255\n" + std::string("\x00\xff", 2), 1.0}}) {              // largest 255 (was refused)
        CAPTURE(file);
        testing::write_text(dir + "/c.pgm", file);
        const Image image = load_image(dir + "/c.pgm", ColorSpace::linear);
        CHECK(image.texel(0, 0).x == 0.0f);
        CHECK(std::fabs(image.texel(1, 0).x - white) <= 1e-6);
    }
    // A sample above the largest value is refused.
    testing::write_text(dir + "/over.pgm", std::string("P5\n2 1\n3\n\x03\x04", 12));
    try {
        load_image(dir + "/over.pgm", ColorSpace::linear);
        FAIL("over.pgm was read");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()) == dir + "/over.pgm: not a readable image: a sample of 4 above the PPM/PGM header's largest value, 3");
    }
}

TEST_CASE("Radiance HDR loads as linear float, values above 1 kept") {
    const std::string dir = testing::scratch_folder("hdr");
    const float data[2 * 3] = {4.0f, 0.5f, 0.25f, 0.125f, 16.0f, 1.0f};  // exact in RGBE
    REQUIRE(stbi_write_hdr((dir + "/a.hdr").c_str(), 2, 1, 3, data));
    const Image image = load_image(dir + "/a.hdr", ColorSpace::srgb);  // HDR ignores the sRGB request
    REQUIRE(image.is_hdr());
    CHECK(image.texel(0, 0).x == doctest::Approx(4.0f));
    CHECK(image.texel(0, 0).y == doctest::Approx(0.5f));
    CHECK(image.texel(1, 0).y == doctest::Approx(16.0f));
}

TEST_CASE("sRGB texels are decoded before filtering, data texels are not") {
    // Black and white side by side: halfway between them, linear filtering gives linear 0.5
    // (sRGB 188), not sRGB 128 (which would be linear 0.216).
    const std::vector<std::uint8_t> rgba = {0, 0, 0, 255, 255, 255, 255, 255};
    Sampler s;
    s.wrap_u = s.wrap_v = Wrap::clamp;
    const Image colour = Image::ldr(2, 1, ColorSpace::srgb, rgba);
    CHECK(sample_bilinear(colour, s, 0.5, 0.5).x == doctest::Approx(0.5f));
    CHECK(linear_to_srgb8(sample_bilinear(colour, s, 0.5, 0.5).x) == 188);
    // A data image is read as stored: byte 128 is 128 / 255, and halfway is the byte average.
    const Image data = Image::ldr(2, 1, ColorSpace::linear, {128, 0, 0, 255, 0, 0, 0, 255});
    CHECK(data.texel(0, 0).x == doctest::Approx(128.0f / 255.0f));
    CHECK(sample_bilinear(data, s, 0.5, 0.5).x == doctest::Approx(64.0f / 255.0f));
    // And sRGB decoding matches the IEC 61966-2-1 curve at a few hand-worked points.
    CHECK(srgb8_to_linear_table()[0] == 0.0f);
    CHECK(srgb8_to_linear_table()[255] == doctest::Approx(1.0f));
    CHECK(srgb8_to_linear_table()[10] == doctest::Approx(10.0 / 255.0 / 12.92));
    CHECK(srgb8_to_linear_table()[128] == doctest::Approx(std::pow((128.0 / 255.0 + 0.055) / 1.055, 2.4)));
}

TEST_CASE("mip levels are built only for textures that get minified") {
    auto make_scene = [](double distance) {
        Scene scene = testing::camera_scene(64, 64, {0, 0, 0}, {0, 0, -1}, 60.0, 0.1, 1000.0);
        std::vector<std::uint8_t> rgba(16 * 16 * 4, 200);
        Texture t;
        t.image = std::make_shared<const Image>(Image::ldr(16, 16, ColorSpace::srgb, rgba));
        t.mipmap = std::make_shared<MipMap>(t.image);
        t.sampler.filter = Filter::trilinear;
        scene.textures.push_back(t);
        Material m;
        m.texture = 0;
        scene.materials.push_back(m);
        // A square facing the camera: near, 16 texels span about 64 pixels (magnified);
        // far, they span a few pixels (minified).
        Vertex a, b, c, d;
        a.position = glm::vec3(-1, -1, float(-distance)), a.uv = {0, 0};
        b.position = glm::vec3(1, -1, float(-distance)), b.uv = {1, 0};
        c.position = glm::vec3(1, 1, float(-distance)), c.uv = {1, 1};
        d.position = glm::vec3(-1, 1, float(-distance)), d.uv = {0, 1};
        testing::add_triangle(scene, {a, b, c}, 0);
        testing::add_triangle(scene, {a, c, d}, 0);
        return scene;
    };
    const Scene near = make_scene(1.5), far = make_scene(60.0);
    RenderStats stats;
    render(near, {}, stats);
    CHECK_FALSE(near.textures[0].mipmap->built());
    render(far, {}, stats);
    CHECK(far.textures[0].mipmap->built());
}

TEST_CASE("textures of one image share its box levels, node registration gets levels per wrap mode and border") {
    std::istringstream text(
        "texture a file textures/detail.png filter trilinear\n"
        "texture b file textures/detail.png filter ewa wrap clamp\n"
        "texture c file textures/detail.png filter trilinear registration node\n"
        "texture d file textures/detail.png filter nearest_mip_nearest registration node wrap repeat\n"
        "texture e file textures/detail.png filter trilinear registration node wrap clamp\n"
        "texture f file textures/detail.png filter trilinear registration node wrap border border 1 0 0 1\n"
        "texture g file textures/detail.png filter trilinear registration node wrap border border 0 0 1 1\n"
        "texture h file textures/detail.png filter trilinear registration node border 0 0 1 1\n"
        "material m texture a\n"
        "triangle material m v 0 0 0 0 0 v 1 0 0 1 0 v 0 1 0 0 1\n");
    const Scene scene = parse_scene(text, testing::source_path("models/textures.scene"));
    REQUIRE(scene.textures.size() == 8);
    const auto mip = [&](int k) { return scene.textures[std::size_t(k)].mipmap.get(); };
    CHECK(mip(0) == mip(1));  // cell: the wrap mode does not change box levels
    CHECK_FALSE(mip(0)->node_levels());
    CHECK(mip(2)->node_levels());
    CHECK(mip(2) == mip(3));  // node, repeat both
    CHECK(mip(2) != mip(0));
    CHECK(mip(4) != mip(2));
    CHECK(mip(5) != mip(6));  // border colours differ, and border wrap reads them
    CHECK(mip(7) == mip(2));  // repeat never reads the border colour
    CHECK(&mip(0)->base() == &mip(5)->base());  // one image in memory
}

TEST_CASE("a border colour is in its image's colour space: sRGB decoded for colour images, as written for data and HDR") {
    const std::string dir = testing::scratch_folder("border-space");
    const unsigned char grey[4 * 3] = {128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128, 128};
    REQUIRE(stbi_write_png((dir + "/g.png").c_str(), 2, 2, 3, grey, 2 * 3));
    const float hdr[2 * 3] = {2.0f, 2.0f, 2.0f, 2.0f, 2.0f, 2.0f};
    REQUIRE(stbi_write_hdr((dir + "/g.hdr").c_str(), 2, 1, 3, hdr));
    std::istringstream text(
        "texture colour file g.png wrap border border 0.5 0.5 1 0.25\n"
        "texture data file g.png colorspace linear wrap border border 0.5 0.5 1 0.25\n"
        "texture data_first file g.png border 0.5 0.5 1 0.25 wrap border colorspace linear\n"
        "texture hdr file g.hdr wrap border border 0.5 0.5 1 0.25\n"
        "texture unset file g.png colorspace linear wrap border\n"
        "material m texture colour\n"
        "triangle material m v 0 0 0 0 0 v 1 0 0 1 0 v 0 1 0 0 1\n");
    const Scene scene = parse_scene(text, dir + "/s.scene");
    REQUIRE(scene.textures.size() == 5);
    // sRGB 0.5 is ((0.5 + 0.055) / 1.055)^2.4 = 0.21404 linear; 1 is 1.
    const Color4 colour = scene.textures[0].sampler.border;
    CHECK(colour.x == doctest::Approx(0.21404).epsilon(1e-4));
    CHECK(colour.z == doctest::Approx(1.0));
    CHECK(colour.w == 0.25f);  // alpha is never encoded
    for (int k : {1, 2, 3}) {
        CAPTURE(k);
        CHECK(scene.textures[std::size_t(k)].sampler.border == Color4(0.5f, 0.5f, 1.0f, 0.25f));
    }
    CHECK(scene.textures[4].sampler.border == Color4(0.0f, 0.0f, 0.0f, 1.0f));  // the default
    // And through the sampler: a data texture's border reads 0.5 where the texels read 128/255.
    const Texture& data = scene.textures[1];
    CHECK(sample_nearest(*data.image, data.sampler, 1.5, 0.5).x == 0.5f);
    CHECK(sample_nearest(*data.image, data.sampler, 0.5, 0.5).x == doctest::Approx(128.0 / 255.0));
}

TEST_CASE("--spp: the ground truth is the mean of spp x spp bilinear lookups at stratified sub-pixel centres") {
    // An 8x8 data image, 0 but for texel (2, 2) = 1, on a square that fills a 4x4 frame
    // exactly (fov 90 at distance 1): each pixel covers 2x2 texels. With spp 4 the samples
    // of pixel column 1 sit at texel x = 2.25, 2.75, 3.25, 3.75; bilinear (cell registration,
    // lattice x - 1/2) reads there 0.75, 0.75, 0.25, 0 of the white column: mean 0.4375. Rows
    // likewise (row 2 from the top covers texel rows 2..3 from the bottom), so pixel (1, 2)
    // is 0.4375^2 = 0.19140625. Pixel (0, 2): x = 0.25 .. 1.75 read 0, 0, 0, 0.25: 0.0625,
    // times 0.4375 = 0.02734375; pixel (1, 3) the same by symmetry; pixel (2, 1): 0.
    // (Nearest lookups would give 0.25 at pixel (1, 2), samples on the pixel's corners 0.25,
    // a single row of samples per pixel 0.21875.)
    const std::string dir = testing::scratch_folder("spp-truth");
    std::vector<unsigned char> pixels(8 * 8 * 3, 0);
    const int file_row = 7 - 2;  // v = 0 is the image's bottom row
    for (int c = 0; c < 3; ++c) pixels[std::size_t(file_row * 8 + 2) * 3 + std::size_t(c)] = 255;
    REQUIRE(stbi_write_png((dir + "/dot.png").c_str(), 8, 8, 3, pixels.data(), 8 * 3));
    std::istringstream text(
        "size 4 4\n"
        "camera eye 0 0 1 target 0 0 0 up 0 1 0 fov 90\n"
        "texture t file dot.png colorspace linear filter nearest\n"
        "material m texture t\n"
        "quad material m v -1 -1 0 0 0 v 1 -1 0 1 0 v 1 1 0 1 1 v -1 1 0 0 1\n");
    const Scene scene = parse_scene(text, dir + "/s.scene");
    RenderOptions options;
    options.spp = 4;
    RenderStats stats;
    const Framebuffer fb = render(scene, options, stats);
    const auto at = [&](int x, int y) { return fb.color[fb.index(x, y)].x; };
    CHECK(at(1, 2) == doctest::Approx(0.19140625).epsilon(1e-5));
    CHECK(at(0, 2) == doctest::Approx(0.02734375).epsilon(1e-5));
    CHECK(at(1, 3) == doctest::Approx(0.02734375).epsilon(1e-5));
    CHECK(at(2, 1) == doctest::Approx(0.0).scale(1.0));
    CHECK(stats.texels_fetched == 16u * 4u * 16u);  // 16 pixels, 16 bilinear samples of 4 texels each
    // The same frame without --spp reads the texture's own filter (nearest) at pixel centres:
    // pixel (1, 2)'s centre is texel corner (3, 3), which nearest reads as texel (3, 3): 0.
    options.spp = 1;
    CHECK(render(scene, options, stats).color[fb.index(1, 2)].x == 0.0f);
}

TEST_CASE("HDR texels near the float maximum: anisotropic, EWA and the --spp ground truth return their value, not inf or NaN") {
    // A Radiance checker of RGBE (128, 128, 128, 252) and (128, 128, 128, 251) texels:
    // 128 x 2^(e - 136) = 2^123 and 2^122, finite floats, tens of which summed in float pass
    // the float maximum (3.4e38). A filter that sums many texels or probes must not return
    // inf (or, blending two levels, inf - inf = NaN). The same checker scaled by 2^-100
    // (exponents 152 and 151) overflows nothing; times material colours 2^-123 and 2^-23,
    // the two frames must match (to float rounding: the first sums in double where the
    // second sums in float) and read the same number of texels.
    const std::string dir = testing::scratch_folder("hdr-overflow");
    const auto checker = [&](const std::string& name, int high_exponent) {
        std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16 +X 16\n";
        for (int k = 0; k < 16 * 16; ++k) {
            const int exponent = high_exponent - ((k % 16 + k / 16) % 2);
            hdr += std::string("\x80\x80\x80", 3) + char(exponent);
        }
        testing::write_text(dir + "/" + name, hdr);
    };
    checker("big.hdr", 252);
    checker("small.hdr", 152);
    for (const std::string filter : {"trilinear", "anisotropic", "ewa", "bilinear"}) {
        for (const int spp : {1, 8}) {
            if (spp > 1 && filter != "bilinear") continue;  // (the ground truth reads the base level bilinearly whatever the filter)
            CAPTURE(filter);
            CAPTURE(spp);
            std::vector<Framebuffer> frames;
            std::uint64_t texels[2] = {0, 0};
            for (int k = 0; k < 2; ++k) {
                const float colour = std::ldexp(1.0f, k == 0 ? -123 : -23);
                char material[128];
                std::snprintf(material, sizeof material, "material m texture t color %.9g %.9g %.9g\n", colour, colour, colour);
                std::istringstream text("size 96 72\n"
                                        "camera eye 0 0 3 target 0 0 0 up 0 1 0 fov 45 near 0.01 far 100\n"
                                        "texture t file " + std::string(k == 0 ? "big.hdr" : "small.hdr") + " filter " + filter +
                                        " max_anisotropy 64\n" + material +
                                        "quad material m v -1 -1 0 0 0 v 1 -1 0 40 0 v 1 1 0 40 40 v -1 1 0 0 40 scale 3 rotate -88 1 0 0\n");
                const Scene scene = parse_scene(text, dir + "/s.scene");
                RenderOptions options;
                options.spp = spp;
                RenderStats stats;
                frames.push_back(render(scene, options, stats));
                texels[k] = stats.texels_fetched;
            }
            int covered = 0, wrong = 0;
            for (std::size_t i = 0; i < frames[0].color.size(); ++i) {
                if (!frames[1].drawn(i)) continue;
                ++covered;
                for (int c = 0; c < 3; ++c) {
                    const float want = frames[1].color[i][c], got = frames[0].color[i][c];
                    if (!(std::fabs(got - want) <= 1e-5f * want)) ++wrong;  // (NaN is wrong)
                }
            }
            CHECK(covered > 1000);
            CHECK(wrong == 0);
            CHECK(texels[0] == texels[1]);
        }
    }
}

TEST_CASE("a scene whose textures are never minified builds no mip levels") {
    // Through the parser (the in-code test above builds its Scene by hand): a trilinear
    // texture on a square seen close up, magnified everywhere.
    std::uint64_t pixels = 0;
    const Scene scene = render_scene_text(
        "size 64 64\n"
        "camera eye 0 0 1 target 0 0 0 up 0 1 0 fov 90\n"
        "texture t file textures/checker.png filter trilinear\n"
        "texture unused file textures/detail.png filter ewa\n"
        "material m texture t\n"
        "quad material m v -1 -1 0 0 0 v 1 -1 0 0.01 0 v 1 1 0 0.01 0.01 v -1 1 0 0 0.01\n",
        pixels);
    CHECK(pixels == 64u * 64u);
    CHECK_FALSE(scene.textures[0].mipmap->built());
    CHECK_FALSE(scene.textures[1].mipmap->built());
}

TEST_CASE("an 8-bit image's decoded copy holds what texel() reads, and bilinear reads the same bits from it") {
    // Random bytes on a 16x8 image, as colour (sRGB table) and as data (k / 255).
    std::uint64_t state = 99;
    const auto next = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return state >> 11;
    };
    std::vector<std::uint8_t> rgba(16 * 8 * 4);
    for (auto& b : rgba) b = std::uint8_t(next() % 256);
    for (const ColorSpace space : {ColorSpace::srgb, ColorSpace::linear}) {
        const Image image = Image::ldr(16, 8, space, rgba);
        CHECK(image.decoded_bytes() == 0u);  // not made until asked for
        const float* decoded = image.decoded_texels();
        REQUIRE(decoded != nullptr);
        CHECK(image.decoded_bytes() == 16u * 8u * 4u * sizeof(float));
        CHECK(image.decoded_texels() == decoded);  // made once
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 16; ++i) {
                const float* t = decoded + (std::size_t(j) * 16 + std::size_t(i)) * 4;
                const Color4 want = image.texel(i, j);
                CHECK((t[0] == want.x && t[1] == want.y && t[2] == want.z && t[3] == want.w));
                CHECK(t[3] == doctest::Approx(rgba[(std::size_t(j) * 16 + std::size_t(i)) * 4 + 3] / 255.0).epsilon(1e-6));
            }
        // Bilinear from the copy and from the bytes: the same bits, also beyond one period
        // and for negative coordinates.
        const LdrLevel bytes = image.ldr_level(), copy = image.ldr_level(true);
        REQUIRE(bytes.decoded == nullptr);
        REQUIRE(copy.decoded == decoded);
        for (int n = 0; n < 3000; ++n) {
            const double scale = n < 1000 ? 1.0 : n < 2000 ? 100.0 : 1e7;
            const double u = (double(next()) * 0x1p-53 * 2.0 - 1.0) * scale, v = (double(next()) * 0x1p-53 * 2.0 - 1.0) * scale;
            const Color4 a = bilinear_in(bytes, u, v), b = bilinear_in(copy, u, v),
                         c = bilinear_in<TexelSource::decoded>(copy, u, v), d = bilinear_in<TexelSource::bytes>(copy, u, v);
            CAPTURE(u);
            CAPTURE(v);
            CHECK((a.x == b.x && a.y == b.y && a.z == b.z && a.w == b.w));
            CHECK((a.x == c.x && a.y == c.y && a.z == c.z && a.w == c.w));
            CHECK((a.x == d.x && a.y == d.y && a.z == d.z && a.w == d.w));
        }
    }
    // HDR images have no copy (their texels are float already).
    const Image hdr = Image::hdr(2, 2, std::vector<float>(16, 0.5f));
    CHECK(hdr.decoded_texels() == nullptr);
    CHECK(hdr.ldr_level(true).decoded == nullptr);
}

#if defined(__SSE2__)
TEST_CASE("the short paths' cells in SSE2 lanes, one level or two at once, are the scalar cells to the bit") {
    // Levels described by their sizes alone (a cell is worked out without reading texels).
    const auto level = [](int w, int h) {
        LdrLevel l;
        l.width = w, l.height = h, l.mask_u = w - 1, l.mask_v = h - 1;
        l.row_bytes = std::size_t(w) * 4;
        while ((std::size_t(1) << l.row_shift) < l.row_bytes) ++l.row_shift;
        return l;
    };
    std::uint64_t state = 5;
    const auto next = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return state >> 11;
    };
    const auto same = [](const reconstruct_detail::ShortPathCell& a, const reconstruct_detail::ShortPathCell& b) {
        return a.row0 == b.row0 && a.row1 == b.row1 && a.column0 == b.column0 && a.column1 == b.column1 &&
               std::memcmp(&a.fx, &b.fx, sizeof a.fx) == 0 && std::memcmp(&a.fy, &b.fy, sizeof a.fy) == 0;
    };
    int differing = 0, checked = 0, below_whole = 0;
    for (const auto& sizes : {std::array<int, 4>{16, 8, 8, 4}, std::array<int, 4>{1024, 1024, 512, 512},
                              std::array<int, 4>{2, 1, 1, 1}, std::array<int, 4>{4096, 256, 2048, 128}}) {
        const LdrLevel a = level(sizes[0], sizes[1]), b = level(sizes[2], sizes[3]);
        for (int n = 0; n < 40000; ++n) {
            // Coordinates from a texel to the short paths' limit (|u W| + 1 < 1e15), and the
            // points where x = u W - 1/2 is whole or a rounding away from it, on either side of 0.
            const double limit = (short_path_limit - 1.0) / std::max(a.width, a.height);
            const double scale = n % 4 == 0 ? 1.0 : n % 4 == 1 ? 1e3 : n % 4 == 2 ? 1e7 : limit;
            double u = (double(next()) * 0x1p-53 * 2.0 - 1.0) * scale, v = (double(next()) * 0x1p-53 * 2.0 - 1.0) * scale;
            if (n % 5 == 0) {
                const double whole = std::floor(u * a.width);
                u = (whole + 0.5) / a.width;
                if (n % 3 == 1) u = std::nextafter(u, -1e300);
                if (n % 3 == 2) u = std::nextafter(u, 1e300);
                v = -std::ldexp(1.0, -int(next() % 60)) / a.height + 0.5 / a.height;  // just below a whole x
            }
            using reconstruct_detail::short_path_cell_scalar;
            reconstruct_detail::ShortPathCell ca, cb;
            reconstruct_detail::short_path_cells(a, b, u, v, ca, cb);
            const reconstruct_detail::ShortPathCell want_a = short_path_cell_scalar(a, u, v), want_b = short_path_cell_scalar(b, u, v);
            using reconstruct_detail::short_path_cell;
            const bool ok = same(ca, want_a) && same(cb, want_b) && same(short_path_cell(a, u, v), want_a) &&
                            same(short_path_cell(b, u, v), want_b);
            if (!ok) {
                CAPTURE(u);
                CAPTURE(v);
                CHECK(ok);
            }
            differing += !ok, ++checked;
            below_whole += v * a.height - 0.5 < 0.0 && v * a.height - 0.5 > -1e-6;
        }
    }
    CHECK(differing == 0);
    CHECK(below_whole > 1000);  // fractions just below a whole number were among them
    MESSAGE(checked << " pairs of cells compared");
}
#endif

TEST_CASE("decoded copies stop at the size limit and at the process's budget, and give their bytes back") {
    // Above max_decoded_texels (1024 x 1024) an image has no copy.
    const Image big = Image::ldr(2048, 1024, ColorSpace::srgb, std::vector<std::uint8_t>(2048u * 1024u * 4u, 7));
    CHECK(big.decoded_texels() == nullptr);
    CHECK(big.decoded_bytes() == 0u);
    // 1024 x 1024 images have 16 MiB copies: the 256 MiB budget holds 16 of them. Of 17
    // images decoded by 4 threads at once, 16 get a copy and one none (it still reads its
    // bytes); which one depends on timing.
    static_assert(Image::decoded_budget_bytes == 16 * (std::size_t(16) << 20));
    const std::vector<std::uint8_t> rgba(1024u * 1024u * 4u, 200);
    std::vector<std::unique_ptr<Image>> images;
    for (int k = 0; k < 17; ++k) images.push_back(std::make_unique<Image>(Image::ldr(1024, 1024, ColorSpace::srgb, rgba)));
    std::atomic<int> next{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&] {
            for (int k = next++; k < 17; k = next++) images[std::size_t(k)]->decoded_texels();
        });
    for (std::thread& t : threads) t.join();
    int copies = 0, refused = -1;
    for (int k = 0; k < 17; ++k) {
        const bool has = images[std::size_t(k)]->decoded_texels() != nullptr;
        CHECK(images[std::size_t(k)]->decoded_bytes() == (has ? std::size_t(16) << 20 : 0u));
        has ? ++copies : refused = k;
    }
    REQUIRE(copies == 16);
    // An image freed gives its copy's bytes back: a new image gets a copy again, while the
    // refused one stays without (its choice is made once).
    images[std::size_t(refused == 0 ? 1 : 0)].reset();
    CHECK(images[std::size_t(refused)]->decoded_texels() == nullptr);
    const Image again = Image::ldr(1024, 1024, ColorSpace::srgb, rgba);
    CHECK(again.decoded_texels() != nullptr);
    CHECK(again.decoded_texels()[0] == srgb8_to_linear_table()[200]);
}

TEST_CASE("decoded copies are made only for the textures that a blending filter reads") {
    // Three textures of one 8-bit image each on a magnified square: nearest reads bytes, so
    // its image gets no copy; bilinear and trilinear (whose levels are never built here)
    // get one of the base; a texture no object uses gets none.
    std::uint64_t pixels = 0;
    const Scene scene = render_scene_text(
        "size 32 32\n"
        "camera eye 0 0 1 target 0 0 0 up 0 1 0 fov 90\n"
        "texture n file textures/checker.png filter nearest\n"
        "texture b file textures/uvgrid.png filter bilinear\n"
        "texture t file textures/detail.png filter trilinear\n"
        "texture unused file textures/detail.png filter bilinear colorspace linear\n"
        "material mn texture n\n"
        "material mb texture b\n"
        "material mt texture t\n"
        "quad material mn v -1 -1 0 0 0 v 0 -1 0 0.01 0 v 0 0 0 0.01 0.01 v -1 0 0 0 0.01\n"
        "quad material mb v 0 -1 0 0 0 v 1 -1 0 0.01 0 v 1 0 0 0.01 0.01 v 0 0 0 0 0.01\n"
        "quad material mt v -1 0 0 0 0 v 1 0 0 0.01 0 v 1 1 0 0.01 0.01 v -1 1 0 0 0.01\n",
        pixels);
    REQUIRE(scene.textures.size() == 4u);
    for (const Texture& t : scene.textures) REQUIRE(t.image->is_ldr_pow2());
    CHECK(pixels == 32u * 32u);
    CHECK(scene.textures[0].image->decoded_bytes() == 0u);
    CHECK(scene.textures[1].image->decoded_bytes() == std::size_t(scene.textures[1].image->bytes()) * sizeof(float));
    CHECK(scene.textures[2].image->decoded_bytes() == std::size_t(scene.textures[2].image->bytes()) * sizeof(float));
    CHECK_FALSE(scene.textures[2].mipmap->built());
    CHECK(scene.textures[3].image->decoded_bytes() == 0u);

    // Bilinear spans that cross texture rows quickly read the bytes (the copy would miss the
    // cache more often), and make no copy: here v runs over 10 periods of 256 rows across 32
    // pixels, 80 rows a pixel, while u stays put.
    const Scene rows = render_scene_text(
        "size 32 32\n"
        "camera eye 0 0 1 target 0 0 0 up 0 1 0 fov 90\n"
        "texture b file textures/uvgrid.png filter bilinear\n"
        "material mb texture b\n"
        "quad material mb v -1 -1 0 0 0 v 1 -1 0 0 10 v 1 1 0 0.01 10 v -1 1 0 0.01 0\n",
        pixels);
    CHECK(pixels == 32u * 32u);
    CHECK(rows.textures[0].image->decoded_bytes() == 0u);
}

TEST_CASE("the sRGB curves: the linear piece up to its threshold, and 8-bit encoding correctly rounded away from byte boundaries") {
    // IEC 61966-2-1: c <= 0.04045 decodes as c / 12.92 (the threshold itself included).
    CHECK(srgb_to_linear(0.04045f) == 0.04045f / 12.92f);
    CHECK(srgb_to_linear(0.04f) == 0.04f / 12.92f);
    // Encoding to a byte goes through a table of 2^16 linear steps, each index rounded to
    // the nearest step: the byte is the correctly rounded one, floor(255 c + 1/2) with c the
    // curve worked out here in double, except within half a step's change (at the steepest,
    // 12.92 x 255 / 65535 / 2 = 0.025 of a byte) of a rounding boundary; truncating the index
    // instead is off by up to a whole step. Every float from 1e-6 to 1 by 2^-20, and all the
    // table's steps.
    const auto reference = [](double x) {
        const double c = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
        return 255.0 * c;
    };
    int wrong = 0, checked = 0;
    const auto check = [&](float x) {
        const double exact = reference(double(x));
        if (std::fabs(exact - std::floor(exact) - 0.5) < 0.03) return;  // within 0.03 of a boundary
        ++checked;
        wrong += linear_to_srgb8(x) != int(std::floor(exact + 0.5));
    };
    for (int k = 1; k < (1 << 20); ++k) check(float(k) / float(1 << 20));
    for (int i = 1; i < 65536; ++i) check(float(i) / 65535.0f), check(std::nextafter(float(i) / 65535.0f, 0.0f));
    CHECK(wrong == 0);
    CHECK(checked > 1000000);
    CHECK(linear_to_srgb8(0.0f) == 0);
    CHECK(linear_to_srgb8(1.0f) == 255);
    CHECK(linear_to_srgb8(std::nanf("")) == 0);
}
