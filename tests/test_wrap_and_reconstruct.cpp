// Wrap modes and the nearest / bilinear reconstruction filters against hand-worked values.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/common.hpp>

#include "helpers.h"
#include "texr/texture/reconstruct.h"
#include "texr/texture/wrap.h"

using namespace texr;

TEST_CASE("wrap functions on texture coordinates: hand-worked values for every mode") {
    // u:                 -0.25   1.0    1.75   -3.5   1e7
    // repeat u-floor(u):  0.75   0      0.75    0.5   0
    // mirror (floor odd -> 1-t): floor -1 odd: 0.25; 1 odd: 1; 1 odd: 0.25; -4 even: 0.5; even: 0
    // clamp:              0      1      1       0     1
    // border outside?:    yes    no     yes     yes   yes
    const double u[] = {-0.25, 1.0, 1.75, -3.5, 1e7};
    const double repeat[] = {0.75, 0.0, 0.75, 0.5, 0.0};
    const double mirror[] = {0.25, 1.0, 0.25, 0.5, 0.0};
    const double clamp[] = {0.0, 1.0, 1.0, 0.0, 1.0};
    const bool border[] = {true, false, true, true, true};
    for (int i = 0; i < 5; ++i) {
        CAPTURE(u[i]);
        CHECK(wrap_repeat(u[i]) == doctest::Approx(repeat[i]));
        CHECK(wrap_mirror(u[i]) == doctest::Approx(mirror[i]));
        CHECK(wrap_clamp(u[i]) == clamp[i]);
        CHECK(outside_border(u[i]) == border[i]);
    }
    CHECK(outside_border(std::nan("")));  // nowhere inside: the samplers read the border there
    CHECK(wrap_repeat(1e7 + 0.25) == doctest::Approx(0.25));  // the fraction survives at 1e7
    CHECK(wrap_mirror(1e7 + 1.25) == doctest::Approx(0.75));  // floor 1e7+1 is odd
}

TEST_CASE("wrap functions on texel indices agree with OpenGL's rules") {
    // n = 4 texels. repeat: i mod 4. mirror: period 8, 0 1 2 3 3 2 1 0.
    CHECK(wrap_repeat_index(-1, 4) == 3);
    CHECK(wrap_repeat_index(4, 4) == 0);
    CHECK(wrap_repeat_index(-9, 4) == 3);
    CHECK(wrap_mirror_index(-1, 4) == 0);
    CHECK(wrap_mirror_index(-4, 4) == 3);
    CHECK(wrap_mirror_index(-5, 4) == 3);
    CHECK(wrap_mirror_index(4, 4) == 3);
    CHECK(wrap_mirror_index(7, 4) == 0);
    CHECK(wrap_mirror_index(8, 4) == 0);
    CHECK(wrap_clamp_index(-3, 4) == 0);
    CHECK(wrap_clamp_index(9, 4) == 3);
    CHECK(wrap_border_index(-1, 4) == -1);
    CHECK(wrap_border_index(4, 4) == -1);
    CHECK(wrap_border_index(2, 4) == 2);
}

namespace {

// A float image whose texel (i, j) has the grey value given row by row from the bottom.
Image grey_image(int w, int h, std::initializer_list<float> values) {
    std::vector<float> rgba;
    for (float v : values) rgba.insert(rgba.end(), {v, v, v, 1.0f});
    return Image::hdr(w, h, rgba);
}

float grey(const Color4& c) { return c.x; }

Color4 sample(const Image& image, const Sampler& s, double u, double v) {
    return s.filter == Filter::nearest ? sample_nearest(image, s, u, v) : sample_bilinear(image, s, u, v);
}

Sampler sampler(Filter f, Wrap w, Registration r) {
    Sampler s;
    s.filter = f;
    s.wrap_u = s.wrap_v = w;
    s.registration = r;
    s.border = {9.0f, 9.0f, 9.0f, 1.0f};
    return s;
}

}  // namespace

TEST_CASE("nearest and bilinear on a 2x2 texture, both registrations") {
    // Texels (i, j) with j from the bottom: (0,0)=0 (1,0)=1 (0,1)=2 (1,1)=3.
    const Image img = grey_image(2, 2, {0, 1, 2, 3});
    SUBCASE("cell registration: centres at 1/4 and 3/4") {
        const Sampler lin = sampler(Filter::bilinear, Wrap::clamp, Registration::cell);
        CHECK(grey(sample(img, lin, 0.25, 0.25)) == doctest::Approx(0.0));
        CHECK(grey(sample(img, lin, 0.75, 0.75)) == doctest::Approx(3.0));
        CHECK(grey(sample(img, lin, 0.5, 0.5)) == doctest::Approx(1.5));     // the mean of all four
        CHECK(grey(sample(img, lin, 0.375, 0.25)) == doctest::Approx(0.25));  // x = 0.25
        CHECK(grey(sample(img, lin, 0.0, 0.0)) == doctest::Approx(0.0));      // clamp to edge
        const Sampler near = sampler(Filter::nearest, Wrap::clamp, Registration::cell);
        CHECK(grey(sample(img, near, 0.49, 0.51)) == doctest::Approx(2.0));  // lu = 0, lv = 1
        CHECK(grey(sample(img, near, 1.0, 1.0)) == doctest::Approx(3.0));    // min(floor(2), 1) = 1
        CHECK(grey(sample(img, near, 0.5, 0.0)) == doctest::Approx(1.0));
    }
    SUBCASE("node registration: texels at 0 and 1") {
        const Sampler lin = sampler(Filter::bilinear, Wrap::clamp, Registration::node);
        CHECK(grey(sample(img, lin, 0.0, 0.0)) == doctest::Approx(0.0));
        CHECK(grey(sample(img, lin, 1.0, 1.0)) == doctest::Approx(3.0));
        CHECK(grey(sample(img, lin, 0.5, 0.5)) == doctest::Approx(1.5));
        CHECK(grey(sample(img, lin, 0.25, 0.0)) == doctest::Approx(0.25));
        CHECK(grey(sample(img, lin, 0.25, 0.5)) == doctest::Approx(1.25));  // 0.25 + 0.5 * 2
        const Sampler near = sampler(Filter::nearest, Wrap::clamp, Registration::node);
        CHECK(grey(sample(img, near, 0.49, 0.51)) == doctest::Approx(2.0));
        CHECK(grey(sample(img, near, 0.51, 0.49)) == doctest::Approx(1.0));
    }
    SUBCASE("where the registrations differ: at u = 0.25 cell reads texel 0, node halfway") {
        CHECK(grey(sample(img, sampler(Filter::bilinear, Wrap::clamp, Registration::cell), 0.25, 0.25)) == doctest::Approx(0.0));
        CHECK(grey(sample(img, sampler(Filter::bilinear, Wrap::clamp, Registration::node), 0.25, 0.25)) ==
              doctest::Approx(0.75));  // 0.25*1 + 0.25*2
    }
}

TEST_CASE("bilinear on a 3x3 texture with every wrap mode") {
    // Row 0 (bottom): 0 1 2; row 1: 3 4 5; row 2: 6 7 8 -> value = i + 3 j.
    const Image img = grey_image(3, 3, {0, 1, 2, 3, 4, 5, 6, 7, 8});
    // Cell registration, v at the centre of row 1 (v = 0.5), u at x = -0.5 + 3u.
    SUBCASE("repeat: u = 0 lies halfway between texel 2 (wrapped) and texel 0") {
        CHECK(grey(sample(img, sampler(Filter::bilinear, Wrap::repeat, Registration::cell), 0.0, 0.5)) ==
              doctest::Approx(0.5 * 5 + 0.5 * 3));
        CHECK(grey(sample(img, sampler(Filter::bilinear, Wrap::repeat, Registration::cell), 1e7, 0.5)) ==
              doctest::Approx(4.0));
    }
    SUBCASE("mirror: u = 0 reads texel 0 twice; u = -1/6 is texel 0's mirror image") {
        CHECK(grey(sample(img, sampler(Filter::bilinear, Wrap::mirror, Registration::cell), 0.0, 0.5)) == doctest::Approx(3.0));
        CHECK(grey(sample(img, sampler(Filter::bilinear, Wrap::mirror, Registration::cell), -1.0 / 6.0, 0.5)) ==
              doctest::Approx(3.0));
        CHECK(grey(sample(img, sampler(Filter::bilinear, Wrap::mirror, Registration::cell), -0.5, 0.5)) ==
              doctest::Approx(4.0));  // x = -2: mirrored texel 1
    }
    SUBCASE("clamp: far outside reads the edge texel") {
        CHECK(grey(sample(img, sampler(Filter::bilinear, Wrap::clamp, Registration::cell), -3.5, 0.5)) == doctest::Approx(3.0));
        CHECK(grey(sample(img, sampler(Filter::bilinear, Wrap::clamp, Registration::cell), 1e7, 0.5)) == doctest::Approx(5.0));
    }
    SUBCASE("border: outside is the border colour; the edge blends half of it") {
        const Sampler b = sampler(Filter::bilinear, Wrap::border, Registration::cell);
        CHECK(grey(sample(img, b, -0.25, 0.5)) == doctest::Approx(9.0));
        CHECK(grey(sample(img, b, 0.0, 0.5)) == doctest::Approx(0.5 * 9 + 0.5 * 3));
        CHECK(grey(sample(img, sampler(Filter::nearest, Wrap::border, Registration::cell), 1.0, 0.5)) == doctest::Approx(5.0));
        CHECK(grey(sample(img, sampler(Filter::nearest, Wrap::border, Registration::cell), 1.01, 0.5)) == doctest::Approx(9.0));
    }
}

TEST_CASE("every reconstruction filter is periodic in u with repeat and mirror, up to 1e7, in both registrations") {
    // The lookup paths themselves (not only the slides' coordinate functions): u and u + k
    // read the same for whole k with repeat, and for even k with mirror; mirror also reads
    // u and -u the same.
    std::vector<float> rgba;
    for (int i = 0; i < 5 * 3; ++i) {
        const float value = float((i * 37) % 11);
        rgba.insert(rgba.end(), {value, value, value, 1.0f});
    }
    const Image img = Image::hdr(5, 3, rgba);
    for (Registration r : {Registration::cell, Registration::node})
        for (Wrap w : {Wrap::repeat, Wrap::mirror})
            for (Filter f : {Filter::nearest, Filter::bilinear, Filter::bicubic}) {
                CAPTURE(int(r));
                CAPTURE(int(w));
                const std::string name = filter_name(f);
                CAPTURE(name);
                Sampler s = sampler(f, w, r);
                const auto read = [&](double u, double v) {
                    return f == Filter::bicubic ? sample_bicubic(img, s, u, v).x : sample(img, s, u, v).x;
                };
                for (double u : {0.03, 0.31, 0.5, 0.77, 0.99})
                    for (double k : {2.0, 250.0, -4.0, 1e7}) {
                        CHECK(read(u + k, 0.4) == doctest::Approx(read(u, 0.4)).epsilon(1e-4));
                        if (w == Wrap::mirror) CHECK(read(-u, 0.4) == doctest::Approx(read(u, 0.4)).epsilon(1e-4));
                    }
            }
}

TEST_CASE("bilinear on the 3x3 texture in node registration: texels at 0, 1/2 and 1") {
    // value = i + 3 j; node registration puts texel i at u = i / 2.
    const Image img = grey_image(3, 3, {0, 1, 2, 3, 4, 5, 6, 7, 8});
    const Sampler clamp = sampler(Filter::bilinear, Wrap::clamp, Registration::node);
    CHECK(grey(sample(img, clamp, 0.0, 0.0)) == doctest::Approx(0.0));
    CHECK(grey(sample(img, clamp, 0.5, 0.5)) == doctest::Approx(4.0));
    CHECK(grey(sample(img, clamp, 1.0, 1.0)) == doctest::Approx(8.0));
    CHECK(grey(sample(img, clamp, 0.25, 0.5)) == doctest::Approx(3.5));  // halfway between texels 0 and 1
    // Repeat in node registration has period 1 in u: u = 1.25 reads like u = 0.25.
    const Sampler repeat = sampler(Filter::bilinear, Wrap::repeat, Registration::node);
    CHECK(grey(sample(img, repeat, 1.25, 0.5)) == doctest::Approx(3.5));
    // And nearest in node registration rounds to the closest texel: u = 0.3 -> texel 1.
    CHECK(grey(sample(img, sampler(Filter::nearest, Wrap::clamp, Registration::node), 0.3, 0.0)) == doctest::Approx(1.0));
}

TEST_CASE("nearest and bilinear with clamp at u = +-1e7 read the right and left edges") {
    const Image img = grey_image(3, 1, {10, 20, 30});
    for (Filter f : {Filter::nearest, Filter::bilinear}) {
        const Sampler s = sampler(f, Wrap::clamp, Registration::cell);
        CHECK(grey(sample(img, s, 1e7, 0.5)) == doctest::Approx(30.0));
        CHECK(grey(sample(img, s, -1e7, 0.5)) == doctest::Approx(10.0));
    }
}

TEST_CASE("the short path for repeat on power-of-two 8-bit images reads what the general path reads") {
    // An 8x4 image of 8-bit data texels (decoded as k / 255) takes the bit-mask path; an HDR
    // copy holding the same values takes the general path, which removes whole periods.
    // Both must agree, for negative coordinates and up to |u| = 1e7, and with a reference
    // worked out here with std::floor and fmod in long double.
    const int w = 8, h = 4;
    std::vector<std::uint8_t> bytes;
    std::vector<float> floats;
    for (int k = 0; k < w * h; ++k) {
        const auto value = std::uint8_t((k * 53 + 17) % 256);
        bytes.insert(bytes.end(), {value, value, value, 255});
        const float f = float(value) / 255.0f;
        floats.insert(floats.end(), {f, f, f, 1.0f});
    }
    const Image ldr = Image::ldr(w, h, ColorSpace::linear, bytes);
    const Image hdr = Image::hdr(w, h, floats);
    REQUIRE(ldr.is_ldr_pow2());
    REQUIRE_FALSE(hdr.is_ldr_pow2());
    const auto texel = [&](long double i, long double j) {  // wrapped by repeat
        const long double a = std::fmod(std::fmod(i, (long double)w) + w, (long double)w);
        const long double b = std::fmod(std::fmod(j, (long double)h) + h, (long double)h);
        return floats[std::size_t((int(b) * w + int(a)) * 4)];
    };
    std::uint64_t state = 12345;
    const auto random = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) * 0x1p-53;
    };
    const Sampler s = sampler(Filter::bilinear, Wrap::repeat, Registration::cell);
    // Both paths agree also where rounding is hardest: just below 0 and below a whole
    // period (the texel before the seam), and from 1e15 texels on, where both read 0.
    for (double u : {-1e-17, -1e-300, 1.0 - 1e-17, 3.0 - 1e-16, 1.25e14 + 0.125, 5e14, 1e16, -3e17}) {
        CAPTURE(u);
        CHECK(sample_nearest(ldr, s, u, 0.3).x == sample_nearest(hdr, s, u, 0.3).x);
        CHECK(sample_bilinear(ldr, s, u, 0.3).x == sample_bilinear(hdr, s, u, 0.3).x);
        CHECK(sample_nearest(ldr, s, 0.3, u).x == sample_nearest(hdr, s, 0.3, u).x);
        CHECK(sample_bilinear(ldr, s, 0.3, u).x == sample_bilinear(hdr, s, 0.3, u).x);
    }
    CHECK(sample_nearest(ldr, s, -1e-17, 0.3).x == texel(w - 1, 1));  // floor(-tiny) = -1: the last column
    for (double scale : {1.0, 100.0, 1e4, 1e7})
        for (int n = 0; n < 2000; ++n) {
            const double u = (2.0 * random() - 1.0) * scale, v = (2.0 * random() - 1.0) * scale;
            CAPTURE(u);
            CAPTURE(v);
            CHECK(sample_bilinear(ldr, s, u, v).x == sample_bilinear(hdr, s, u, v).x);
            CHECK(sample_nearest(ldr, s, u, v).x == sample_nearest(hdr, s, u, v).x);
            // The reference: nearest is texel floor(u n), bilinear blends around u n - 1/2.
            const long double x = (long double)u * w, y = (long double)v * h;
            CHECK(sample_nearest(ldr, s, u, v).x == texel(std::floor(x), std::floor(y)));
            const long double bx = x - 0.5L, by = y - 0.5L, i = std::floor(bx), j = std::floor(by);
            const long double fu = bx - i, fv = by - j;
            const long double expected = (1 - fu) * ((1 - fv) * texel(i, j) + fv * texel(i, j + 1)) +
                                         fu * ((1 - fv) * texel(i + 1, j) + fv * texel(i + 1, j + 1));
            CHECK(sample_bilinear(ldr, s, u, v).x == doctest::Approx(double(expected)).epsilon(1e-5));
        }
}

TEST_CASE("just below a texel boundary in the period below 0, every wrap mode reads the texel floor(u n) gives") {
    // A 4x1 float texture holding its own index (0, 1, 2, 3). u = -0.25 less one ulp puts the
    // lattice coordinate at u 4 = -1.0000000000000002, so floor(u 4) = -2: repeat reads
    // texel 2, mirror (OpenGL: ... 1 0 | 0 1 2 3 | 3 2 1 0 ...) reads texel 1, clamp texel 0,
    // border the border colour. (Removing a period in double, -1.0000000000000002 + 4 rounds
    // to 3, one texel on.)
    const Image image = Image::hdr(4, 1, {0, 0, 0, 1, 1, 1, 1, 1, 2, 2, 2, 1, 3, 3, 3, 1});
    const double u = std::nextafter(-0.25, -1.0);
    CHECK(sample_nearest(image, sampler(Filter::nearest, Wrap::repeat, Registration::cell), u, 0.5).x == 2.0f);
    CHECK(sample_nearest(image, sampler(Filter::nearest, Wrap::mirror, Registration::cell), u, 0.5).x == 1.0f);
    CHECK(sample_nearest(image, sampler(Filter::nearest, Wrap::clamp, Registration::cell), u, 0.5).x == 0.0f);
    Sampler border = sampler(Filter::nearest, Wrap::border, Registration::cell);
    border.border = Color4(0.5f);
    CHECK(sample_nearest(image, border, u, 0.5).x == 0.5f);

    // Every boundary k / n for k = -1 .. -(n-1) and one ulp either side of it, on an odd and an
    // even size: the texel is floor(x) of the lattice coordinate x = u n as computed, wrapped
    // by the index rules (worked out here in integers).
    for (const int n : {7, 8}) {
        std::vector<float> texels;
        for (int i = 0; i < n; ++i) texels.insert(texels.end(), {float(i), float(i), float(i), 1.0f});
        const Image row = Image::hdr(n, 1, texels);
        for (int k = 1; k < n; ++k)
            for (const double t : {std::nextafter(-double(k) / n, -1.0), -double(k) / n, std::nextafter(-double(k) / n, 0.0)}) {
                const long long whole = (long long)std::floor(t * n);
                const int repeat = int(((whole % n) + n) % n);
                const int m = int(((whole % (2 * n)) + 2 * n) % (2 * n)), mirror = m < n ? m : 2 * n - 1 - m;
                CAPTURE(t);
                CHECK(sample_nearest(row, sampler(Filter::nearest, Wrap::repeat, Registration::cell), t, 0.5).x == float(repeat));
                CHECK(sample_nearest(row, sampler(Filter::nearest, Wrap::mirror, Registration::cell), t, 0.5).x == float(mirror));
            }
    }
}

TEST_CASE("node registration's nearest rounds the lattice coordinate to the nearest node exactly") {
    // Two texels (0 and 1) at u = 0 and u = 1. x = u (n - 1) = u. Just below 1/2 the nearest
    // node is 0 (x + 1/2 would round up to 1); just below -1/2 it is node -1, which mirror
    // reflects onto node 1, and just above -1/2 node 0.
    const Image image = Image::hdr(2, 1, {0, 0, 0, 1, 1, 1, 1, 1});
    const Sampler mirror = sampler(Filter::nearest, Wrap::mirror, Registration::node);
    CHECK(sample_nearest(image, mirror, 0.49999999999999994, 0.5).x == 0.0f);
    CHECK(sample_nearest(image, mirror, 0.5, 0.5).x == 1.0f);
    CHECK(sample_nearest(image, mirror, std::nextafter(-0.5, -1.0), 0.5).x == 1.0f);
    CHECK(sample_nearest(image, mirror, std::nextafter(-0.5, 0.0), 0.5).x == 0.0f);
}

TEST_CASE("bilinear's general path agrees with the short path just below texel boundaries under 0") {
    // A 1024x1 8-bit image takes the short path (bit masks on floor(x)); the same values as
    // floats take the general path. At u = -0.10791015625000001 (x = u 1024 - 1/2 just
    // below -111) both must read texels 912 and 913 with the same weights.
    std::vector<std::uint8_t> bytes;
    std::vector<float> floats;
    for (int i = 0; i < 1024; ++i) {
        const auto value = std::uint8_t((i * 37 + 11) % 256);
        bytes.insert(bytes.end(), {value, value, value, 255});
        floats.insert(floats.end(), {value / 255.0f, value / 255.0f, value / 255.0f, 1.0f});
    }
    const Image ldr = Image::ldr(1024, 1, ColorSpace::linear, bytes);
    const Image hdr = Image::hdr(1024, 1, floats);
    REQUIRE(ldr.is_ldr_pow2());
    const Sampler s = sampler(Filter::bilinear, Wrap::repeat, Registration::cell);
    CHECK(sample_bilinear(ldr, s, -0.10791015625000001, 0.5).x == sample_bilinear(hdr, s, -0.10791015625000001, 0.5).x);
    for (int k = 1; k < 1024; k += 7)
        for (const double t : {std::nextafter((0.5 - k) / 1024, -1.0), std::nextafter((0.5 - k) / 1024, 0.0)}) {
            CAPTURE(t);
            CHECK(sample_bilinear(ldr, s, t, 0.5).x == sample_bilinear(hdr, s, t, 0.5).x);
            CHECK(sample_nearest(ldr, s, t, 0.5).x == sample_nearest(hdr, s, t, 0.5).x);
        }
}

TEST_CASE("a NaN coordinate with border wrap reads the border colour in both registrations, with clamp the first texel") {
    // Texel (i, j) holds i + 3 j. At v = 1/2 both registrations put the lattice exactly on row
    // 1 (cell: 1.5 - 1/2; node: 1/2 (3 - 1)), and a NaN u reads column 0 with clamp: texel 3.
    std::vector<float> texels;
    for (int k = 0; k < 9; ++k) texels.insert(texels.end(), {float(k), float(k), float(k), 1.0f});
    const Image image = Image::hdr(3, 3, texels);
    const double nan = std::nan("");
    for (Registration r : {Registration::cell, Registration::node})
        for (Filter f : {Filter::nearest, Filter::bilinear}) {
            CAPTURE(int(r));
            CHECK(sample(image, sampler(f, Wrap::border, r), nan, 0.5).x == 9.0f);  // sampler()'s border colour
            CHECK(sample(image, sampler(f, Wrap::border, r), 0.5, nan).x == 9.0f);
            CHECK(sample(image, sampler(f, Wrap::clamp, r), nan, 0.5).x == 3.0f);
        }
}

namespace {

// The Mitchell-Netravali kernel as the 1988 paper writes it (piecewise cubic in |x|).
double kernel(double x, double b, double c) {
    x = std::fabs(x);
    if (x < 1.0) return ((12.0 - 9.0 * b - 6.0 * c) * x * x * x + (-18.0 + 12.0 * b + 6.0 * c) * x * x + (6.0 - 2.0 * b)) / 6.0;
    if (x < 2.0) return ((-b - 6.0 * c) * x * x * x + (6.0 * b + 30.0 * c) * x * x + (-12.0 * b - 48.0 * c) * x + (8.0 * b + 24.0 * c)) / 6.0;
    return 0.0;
}

// Bicubic by definition: the 4x4 texels around the lattice position, each through the wrap
// rules on texel indices (wrap_index, checked against OpenGL's in this file), the border
// colour for an index beyond the image; node registration with border wrap first applies
// the slide's test, and inside [0, 1] reads the texture alone (taps beyond the edge nodes
// read the edge, as clamp); the overshoot clamp to the range of the 2x2 texels around the
// position.
Color4 bicubic_by_definition(const Image& image, const Sampler& s, double u, double v) {
    const bool node = s.registration == Registration::node;
    const auto outside = [&](Wrap wrap, double t) { return node && wrap == Wrap::border && !(t >= 0.0 && t <= 1.0); };
    if (outside(s.wrap_u, u) || outside(s.wrap_v, v)) return s.border;
    // Node registration with repeat reads each period like [0, 1) (the slide's t = u - floor(u)),
    // so the seam node is texel n - 1 of a period, and taps beyond it wrap from there.
    if (node && s.wrap_u == Wrap::repeat) u -= std::floor(u);
    if (node && s.wrap_v == Wrap::repeat) v -= std::floor(v);
    const int w = image.width(), h = image.height();
    const double x = node ? u * (w - 1) : u * w - 0.5, y = node ? v * (h - 1) : v * h - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y);
    const Wrap tap_u = node && s.wrap_u == Wrap::border ? Wrap::clamp : s.wrap_u;
    const Wrap tap_v = node && s.wrap_v == Wrap::border ? Wrap::clamp : s.wrap_v;
    const auto texel = [&](double i, double j) {
        const int column = wrap_index(tap_u, int(i), w, node), row = wrap_index(tap_v, int(j), h, node);
        return column < 0 || row < 0 ? s.border : image.texel(column, row);
    };
    Color4 sum(0.0f);
    for (int b = -1; b <= 2; ++b)
        for (int a = -1; a <= 2; ++a)
            sum += float(kernel(x - (x0 + a), s.cubic_b, s.cubic_c) * kernel(y - (y0 + b), s.cubic_b, s.cubic_c)) * texel(x0 + a, y0 + b);
    if (s.clamp_overshoot) {
        Color4 low(1e30f), high(-1e30f);
        for (int b = 0; b <= 1; ++b)
            for (int a = 0; a <= 1; ++a) low = glm::min(low, texel(x0 + a, y0 + b)), high = glm::max(high, texel(x0 + a, y0 + b));
        sum = glm::clamp(sum, low, high);
    }
    return sum;
}

}  // namespace

TEST_CASE("bicubic matches its definition for every wrap pair, both registrations, several (B, C), with and without the clamp") {
    // A 5x3 image of random values (distinct per channel), coordinates from -3 to 4 and near
    // 1e7 (|x| within the int range of the reference's indices after wrapping).
    std::vector<float> rgba;
    std::uint64_t state = 12345;
    const auto next = [&] { return float((state = state * 6364136223846793005ULL + 1442695040888963407ULL) >> 40) / float(1 << 24); };
    for (int k = 0; k < 5 * 3; ++k) rgba.insert(rgba.end(), {next(), next(), next(), 1.0f});
    const Image image = Image::hdr(5, 3, rgba);
    const Wrap wraps[] = {Wrap::repeat, Wrap::mirror, Wrap::clamp, Wrap::border};
    const std::pair<float, float> cubics[] = {{0.0f, 0.5f}, {1.0f, 0.0f}, {1.0f / 3.0f, 1.0f / 3.0f}, {0.5f, 0.25f}};
    int checked = 0;
    for (Wrap wu : wraps)
        for (Wrap wv : wraps)
            for (Registration r : {Registration::cell, Registration::node})
                for (const auto& [b, c] : cubics)
                    for (bool clamp : {false, true}) {
                        Sampler s;
                        s.filter = Filter::bicubic;
                        s.wrap_u = wu, s.wrap_v = wv, s.registration = r;
                        s.cubic_b = b, s.cubic_c = c, s.clamp_overshoot = clamp;
                        s.border = {0.9f, -0.3f, 2.0f, 0.5f};
                        for (int k = 0; k < 40; ++k) {
                            const double u = -3.0 + 7.0 * next(), v = -3.0 + 7.0 * next();
                            // Far out along u for the periodic modes, by a whole number of
                            // periods (exact there: 1e7 + a fraction): the same texels.
                            const bool periodic = wu == Wrap::repeat || wu == Wrap::mirror;
                            const double far_u = periodic && k % 4 == 0 ? u + 1e7 : u;
                            const Color4 got = sample_bicubic(image, s, far_u, v), expected = bicubic_by_definition(image, s, u, v);
                            CAPTURE(int(wu));
                            CAPTURE(int(wv));
                            CAPTURE(int(r));
                            const float cubic_b = b;  // (CAPTURE's lambda cannot capture a structured binding)
                            CAPTURE(cubic_b);
                            CAPTURE(clamp);
                            CAPTURE(far_u);
                            CAPTURE(v);
                            for (int ch = 0; ch < 4; ++ch) CHECK(got[ch] == doctest::Approx(expected[ch]).epsilon(1e-4));
                            ++checked;
                        }
                    }
    CHECK(checked == 16 * 2 * 4 * 2 * 40);
}

TEST_CASE("node registration with border wrap: every filter reads the border colour outside [0, 1], the image at 0 and 1") {
    // The slide: if (u < 0 || u > 1 || v < 0 || v > 1) return backgroundColor. A 3x1 white
    // image (the review's case): nearest read the border at u = -0.01, bilinear 0.98 white and
    // bicubic 0.99 white.
    const Image white = grey_image(3, 1, {1.0f, 1.0f, 1.0f});
    for (Filter f : {Filter::nearest, Filter::bilinear, Filter::bicubic}) {
        CAPTURE(std::string(filter_name(f)));
        Sampler s = sampler(f, Wrap::border, Registration::node);
        s.border = {0.0f, 0.0f, 0.0f, 1.0f};
        const auto at = [&](double u, double v) {
            return f == Filter::bicubic ? sample_bicubic(white, s, u, v) : sample(white, s, u, v);
        };
        for (double u : {-0.01, -1e-12, 1.0 + 1e-12, 1.2, -5.0})
            CHECK(at(u, 0.5) == s.border);
        CHECK(at(0.5, -0.01) == s.border);
        // Inside [0, 1] the image alone: at the nodes, and between them, where bicubic's taps
        // reach beyond the edge nodes (they read the edge: a review found the B-spline at
        // 0.833 at u = 0 and Catmull-Rom at 1.05 at u = 0.02 when they read the border).
        for (double u : {0.0, 0.02, 0.25, 0.5, 0.98, 1.0}) CHECK(grey(at(u, 0.5)) == doctest::Approx(1.0));
        if (f == Filter::bicubic) {
            s.cubic_b = 1.0f, s.cubic_c = 0.0f;  // the B-spline: no node weight is 1
            for (double u : {0.0, 0.02, 1.0}) CHECK(grey(at(u, 0.5)) == doctest::Approx(1.0));
            s.cubic_b = 0.0f, s.cubic_c = 0.5f;
        }
        // Along an axis that is not border, the test does not apply.
        s.wrap_v = Wrap::clamp;
        CHECK(grey(at(0.5, -0.5)) == doctest::Approx(1.0));
    }
}

TEST_CASE("the short path is taken only for repeat on both axes and power-of-two sides, and reads what the general path reads") {
    // 8-bit images: a 4x4 (short path with repeat on both axes) and a 4x3 (height not a power
    // of two: general path). Nearest and bilinear with repeat on u and clamp on v against the
    // same image as floats (always the general path), beyond [0, 1] on both axes.
    for (const std::pair<int, int>& size : {std::pair<int, int>{4, 4}, {4, 3}, {8, 2}}) {
        const int w = size.first, h = size.second;  // (CAPTURE: not a structured binding)
        std::vector<std::uint8_t> bytes;
        std::vector<float> floats;
        for (int k = 0; k < w * h; ++k) {
            const std::uint8_t value = std::uint8_t(17 * k + 3);
            bytes.insert(bytes.end(), {value, std::uint8_t(255 - value), std::uint8_t(value / 2), 255});
            floats.insert(floats.end(), {value / 255.0f, (255 - value) / 255.0f, (value / 2) / 255.0f, 1.0f});
        }
        const Image ldr = Image::ldr(w, h, ColorSpace::linear, bytes), hdr = Image::hdr(w, h, floats);
        for (Wrap wrap_v : {Wrap::repeat, Wrap::clamp, Wrap::mirror})
            for (Filter f : {Filter::nearest, Filter::bilinear}) {
                Sampler s = sampler(f, Wrap::repeat, Registration::cell);
                s.wrap_v = wrap_v;
                const bool power_of_two = (w & (w - 1)) == 0 && (h & (h - 1)) == 0;
                CHECK(takes_short_path(ldr, s) == (power_of_two && wrap_v == Wrap::repeat));
                for (double u : {-1.3, -0.2, 0.1, 0.6, 1.45})
                    for (double v : {-1.3, -0.2, 0.1, 0.6, 1.45}) {
                        CAPTURE(w);
                        CAPTURE(h);
                        CAPTURE(int(wrap_v));
                        CAPTURE(u);
                        CAPTURE(v);
                        const Color4 a = sample(ldr, s, u, v), b = sample(hdr, s, u, v);
                        for (int ch = 0; ch < 3; ++ch) CHECK(a[ch] == doctest::Approx(b[ch]).epsilon(1e-5));
                    }
            }
    }
}

// Boundaries that a mutation test of wrap.h and reconstruct.{h,cpp} found unchecked: each
// below fails when its comparison is loosened or tightened by one.
namespace {
Image hdr_row(const std::vector<float>& values) { return testing::hdr_image(int(values.size()), 1, values); }
}  // namespace

TEST_CASE("a lattice coordinate of whole periods wraps to texel 0, whichever way its quotient rounds") {
    // x = k n texels is k whole periods from texel 0: whole 0, fraction 0. The quotient
    // x (1/n) is worked out in double and may round one below k; the remainder must still
    // land in [0, n) (a reduced value equal to the period was kept: texel n, past the row).
    for (const int n : {3, 7, 49, 50, 97, 1000, 16383})
        for (long long k = -2000; k <= 2000; k += 7) {
            const LatticePoint p = split_lattice(Wrap::repeat, double(k * n), n);
            CAPTURE(n);
            CAPTURE(k);
            REQUIRE(p.whole == 0);
            REQUIRE(p.fraction == 0.0);
        }
    CHECK(split_lattice(Wrap::repeat, 49.0, 49).whole == 0);
    // Through the samplers: node registration, repeat, u = 1 is the node texel 49 shares with
    // the next period's texel 0, read as texel 0 (0); 50 texels whose values are their index.
    std::vector<float> ramp;
    for (int i = 0; i < 50; ++i) ramp.push_back(float(i));
    const Image image = hdr_row(ramp);
    Sampler node;
    node.registration = Registration::node;
    CHECK(sample_nearest(image, node, 1.0, 0.5).x == 0.0f);
    CHECK(sample_bilinear(image, node, 1.0, 0.5).x == 0.0f);
    // Cell registration, 49 texels: u = 1.02 is u = 0.02 a period on, x = 0.98 - 0.5 = 0.48,
    // between texels 0 and 1.
    ramp.pop_back();
    const Image odd = hdr_row(ramp);
    CHECK(sample_bilinear(odd, Sampler{}, 1.02, 0.5).x == doctest::Approx(0.48).epsilon(1e-6));
    CHECK(sample_bilinear(odd, Sampler{}, 0.02, 0.5).x == doctest::Approx(0.48).epsilon(1e-6));
}

TEST_CASE("repeat and mirror coordinates beyond 1e15 texels read texel 0, on the general and the short path") {
    // The documented rule (wrap.h): there a double holds no fraction of a texel any more. A
    // 4-texel row [0, 1, 2, 3] (HDR: the general path) at x = u 4 = 2e15 + 1 reads 0, not
    // texel 1; the 8-bit row [0, 85, 170, 255] (the short path of repeat on powers of two)
    // at x = -1e15 - 0.25 reads what the general path reads there: texel 0.
    const Image hdr = hdr_row({0.0f, 1.0f, 2.0f, 3.0f});
    CHECK(sample_nearest(hdr, Sampler{}, 500000000000000.25, 0.5).x == 0.0f);
    CHECK(sample_bilinear(hdr, Sampler{}, 500000000000000.25, 0.5).x == 0.0f);
    Sampler mirror;
    mirror.wrap_u = Wrap::mirror;  // (x = 2e15 + 1 is in an even period, 2e15 + 3 too: texels 1 and 3 without the rule)
    CHECK(sample_nearest(hdr, mirror, 500000000000000.25, 0.5).x == 0.0f);
    CHECK(sample_nearest(hdr, mirror, 500000000000000.75, 0.5).x == 0.0f);
    const std::vector<std::uint8_t> bytes = {0, 0, 0, 255, 85, 85, 85, 255, 170, 170, 170, 255, 255, 255, 255, 255};
    const Image ldr = Image::ldr(4, 1, ColorSpace::linear, bytes);
    const double u = -249999999999999.9375;  // u 4 = -(1e15 - 0.25); bilinear's x = u 4 - 1/2
    CHECK(sample_bilinear(ldr, Sampler{}, u, 0.5).x == 0.0f);
    CHECK(reconstruct_detail::sample_bilinear_general(ldr, Sampler{}, u, 0.5).x == 0.0f);
}

TEST_CASE("the bicubic kernel is 0 from two texels on, so a texel two away adds nothing, however large") {
    // k(x) = 0 for |x| >= 2 by definition; in floats the second piece's polynomial at x = 2
    // is not exactly 0 (1.6e-7 for B = C = 1/3), so x = 2 must take the outer branch.
    for (const std::pair<float, float>& bc : {std::pair{0.0f, 0.5f}, {1.0f, 0.0f}, {1.0f / 3.0f, 1.0f / 3.0f}, {0.3f, 0.7f}}) {
        CAPTURE(bc.first);
        CAPTURE(bc.second);
        CHECK(mitchell_netravali(2.0f, bc.first, bc.second) == 0.0f);
        CHECK(mitchell_netravali(-2.0f, bc.first, bc.second) == 0.0f);
        CHECK(mitchell_netravali(2.5f, bc.first, bc.second) == 0.0f);
    }
    // At texel 2's centre of [1, 1, 1, 1, 3e38] the taps are texels 1..4 at distances 1, 0,
    // 1, 2: the weights at 1, 0, 1 sum to 1 (k(0) + 2 k(1) = 1), the one at 2 is 0: exactly 1.
    const Image image = hdr_row({1.0f, 1.0f, 1.0f, 1.0f, 3e38f});
    Sampler s;
    s.filter = Filter::bicubic, s.wrap_u = s.wrap_v = Wrap::clamp, s.cubic_b = s.cubic_c = 1.0f / 3.0f;
    CHECK(sample_bicubic(image, s, 0.5, 0.5).x == doctest::Approx(1.0f));
}

TEST_CASE("bilinear between HDR texels more than the float maximum apart stays between them") {
    // -3.4e38 beside 3.4e38: their difference overflows a float (to inf, and 0 x inf is NaN),
    // while the blend of two finite values is finite. At a texel's centre the blend is that
    // texel; halfway it is their mean, 0.
    std::vector<float> rgba;
    for (const float t : {-3.4e38f, 3.4e38f, 3.4e38f, 3.4e38f})
        for (int c = 0; c < 4; ++c) rgba.push_back(t);
    const Image image = Image::hdr(2, 2, rgba);
    Sampler s;
    s.wrap_u = s.wrap_v = Wrap::clamp;
    CHECK(sample_bilinear(image, s, 0.25, 0.25).x == -3.4e38f);
    CHECK(sample_bilinear(image, s, 0.5, 0.25).x == doctest::Approx(0.0).epsilon(1e-6));  // (mean of -3.4e38 and 3.4e38)
    CHECK(sample_bilinear(image, s, 0.75, 0.75).x == 3.4e38f);
    const Color4 quarter = sample_bilinear(image, s, 0.375, 0.25);  // x = 0.25: 0.75 (-3.4e38) + 0.25 (3.4e38)
    CHECK(std::isfinite(quarter.x));
    CHECK(quarter.x == doctest::Approx(-1.7e38).epsilon(1e-6));
}
