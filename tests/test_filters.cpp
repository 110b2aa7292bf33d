// Bicubic, mipmaps, level of detail and the footprint filters, each checked against a
// property worked out by hand: interpolation, no overshoot, preserved means, constants.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "helpers.h"
#include "texr/scene/scene.h"
#include "texr/texture/ewa.h"
#include "texr/texture/lod_avx2.h"
#include "texr/texture/lookup.h"
#include "texr/texture/minify.h"
#include "texr/texture/mipmap.h"
#include "texr/texture/reconstruct.h"
#include "texr/texture/wrap.h"

using namespace texr;

namespace {

Image random_hdr(int w, int h, std::uint64_t seed, float lo = 0.0f, float hi = 1.0f) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> value(lo, hi);
    std::vector<float> rgba;
    for (int i = 0; i < w * h; ++i) {
        const float v = value(rng);
        rgba.insert(rgba.end(), {v, 1.0f - v, 0.5f * v, 1.0f});
    }
    return Image::hdr(w, h, rgba);
}

Image constant_ldr(int w, int h, std::uint8_t value) {
    std::vector<std::uint8_t> rgba(std::size_t(w) * std::size_t(h) * 4, value);
    return Image::ldr(w, h, ColorSpace::srgb, rgba);
}

Color4 mean_of(const Image& image) {
    Color4 sum(0.0f);
    for (int j = 0; j < image.height(); ++j)
        for (int i = 0; i < image.width(); ++i) sum += image.texel(i, j);
    return sum / float(image.width() * image.height());
}

Sampler cubic(float b, float c, bool clamp = false) {
    Sampler s;
    s.filter = Filter::bicubic;
    s.cubic_b = b, s.cubic_c = c, s.clamp_overshoot = clamp;
    return s;
}

UVDerivatives rotated(double texels_per_pixel, double degrees, int size) {
    const double a = degrees * M_PI / 180.0, k = texels_per_pixel / size;
    return {k * std::cos(a), k * std::sin(a), -k * std::sin(a), k * std::cos(a)};
}

}  // namespace

TEST_CASE("the Mitchell-Netravali weights sum to one for every fraction and (B, C)") {
    for (float b : {0.0f, 1.0f / 3.0f, 1.0f})
        for (float c : {0.0f, 1.0f / 3.0f, 0.5f})
            for (float f = 0.0f; f < 1.0f; f += 0.0625f) {
                const float sum = mitchell_netravali(1 + f, b, c) + mitchell_netravali(f, b, c) +
                                  mitchell_netravali(1 - f, b, c) + mitchell_netravali(2 - f, b, c);
                CHECK(sum == doctest::Approx(1.0f).epsilon(1e-5));
            }
}

TEST_CASE("Catmull-Rom passes through the samples") {
    const Image img = random_hdr(7, 5, 11);
    const Sampler s = cubic(0.0f, 0.5f);
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 7; ++i) {
            const Color4 got = sample_bicubic(img, s, (i + 0.5) / 7.0, (j + 0.5) / 5.0);  // texel centres
            const Color4 want = img.texel(i, j);
            for (int c = 0; c < 3; ++c) CHECK(got[c] == doctest::Approx(want[c]).epsilon(1e-5));
        }
}

TEST_CASE("the cubic B-spline never overshoots, and clamping removes Catmull-Rom's overshoot") {
    // A hard step: 0 0 0 1 1 1 along u. Catmull-Rom rings next to it, below 0 and above 1.
    std::vector<float> rgba;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 6; ++i) {
            const float v = i < 3 ? 0.0f : 1.0f;
            rgba.insert(rgba.end(), {v, v, v, 1.0f});
        }
    const Image step = Image::hdr(6, 4, rgba);
    float catmull_min = 1.0f, catmull_max = 0.0f;
    for (double u = 0.0; u <= 1.0; u += 1.0 / 256.0) {
        const float bspline = sample_bicubic(step, cubic(1.0f, 0.0f), u, 0.5).x;
        CHECK(bspline >= -1e-6f);
        CHECK(bspline <= 1.0f + 1e-6f);
        const float catmull = sample_bicubic(step, cubic(0.0f, 0.5f), u, 0.5).x;
        catmull_min = std::min(catmull_min, catmull), catmull_max = std::max(catmull_max, catmull);
        const float clamped = sample_bicubic(step, cubic(0.0f, 0.5f, true), u, 0.5).x;
        CHECK(clamped >= 0.0f);
        CHECK(clamped <= 1.0f);
    }
    CHECK(catmull_min < -0.01f);  // the overshoot exists without the clamp
    CHECK(catmull_max > 1.01f);
    // The B-spline on random data stays within the data's range.
    const Image noise = random_hdr(9, 9, 5);
    std::mt19937_64 rng(6);
    std::uniform_real_distribution<double> t(-1.0, 2.0);
    for (int k = 0; k < 2000; ++k) {
        const float v = sample_bicubic(noise, cubic(1.0f, 0.0f), t(rng), t(rng)).x;
        CHECK(v >= -1e-6f);
        CHECK(v <= 1.0f + 1e-6f);
    }
}

TEST_CASE("bicubic of HDR texels near the float maximum with B and C far from [0, 1] is their value, not inf - inf") {
    // The weights sum to 1 for any (B, C), so a constant image reads as its value; with
    // B = C = 10 single weights reach about 10, and 1.3e38 x 10 overflows a float. A ramp of
    // such values: between two texels the cubic of a linear ramp stays on it only for
    // B + 2C = 1, so there only the constant is checked exactly, the ramp for being finite.
    Sampler s;
    s.filter = Filter::bicubic;
    s.cubic_b = 10.0f, s.cubic_c = 10.0f;
    const float big = 1.3e38f;
    std::vector<float> flat(5 * 5 * 4, big), ramp(5 * 5 * 4, 1.0f);
    for (int k = 0; k < 25; ++k)
        for (int c = 0; c < 3; ++c) ramp[std::size_t(k) * 4 + std::size_t(c)] = big * (float(k % 5 + 1) / 5.0f);
    const Image constant = Image::hdr(5, 5, flat), rising = Image::hdr(5, 5, ramp);
    for (const double u : {0.13, 0.31, 0.5, 0.77}) {
        CAPTURE(u);
        const Color4 a = sample_bicubic(constant, s, u, 0.42);
        // (The float weights themselves sum to 1 within about 1e-5 at B = C = 10: 0.999993 at f = 0.15.)
        for (int c = 0; c < 4; ++c) CHECK(double(a[c]) == doctest::Approx(double(big)).epsilon(1e-4));
        const Color4 b = sample_bicubic(rising, s, u, 0.42);
        for (int c = 0; c < 3; ++c) CHECK(std::isfinite(b[c]));
    }
}

TEST_CASE("mip levels of a constant image are constant, for any size") {
    for (auto [w, h] : {std::pair{64, 64}, std::pair{37, 23}, std::pair{1, 9}, std::pair{100, 3}}) {
        const MipMap mip(std::make_shared<Image>(constant_ldr(w, h, 173)));
        const Color4 expected = mip.base().texel(0, 0);
        int levels = 0;
        for (int l = 0; l < mip.level_count(); ++l, ++levels) {
            const Image& level = mip.level(l);
            for (int j = 0; j < level.height(); ++j)
                for (int i = 0; i < level.width(); ++i) REQUIRE(level.texel(i, j) == expected);
        }
        const Image& top = mip.level(mip.level_count() - 1);
        CHECK(top.width() == 1);
        CHECK(top.height() == 1);
        CHECK(levels == 1 + int(std::floor(std::log2(std::max(w, h)))));
    }
}

TEST_CASE("each mip level keeps the base image's mean") {
    SUBCASE("float levels: exact up to float rounding, odd sizes included") {
        for (auto [w, h] : {std::pair{37, 23}, std::pair{64, 48}, std::pair{15, 1}}) {
            const MipMap mip(std::make_shared<Image>(random_hdr(w, h, 3)));
            const Color4 base = mean_of(mip.base());
            for (int l = 1; l < mip.level_count(); ++l) {
                const Color4 m = mean_of(mip.level(l));
                for (int c = 0; c < 4; ++c) CHECK(m[c] == doctest::Approx(base[c]).epsilon(1e-5));
            }
        }
    }
    SUBCASE("8-bit linear levels: within half a step of rounding per level") {
        std::mt19937_64 rng(9);
        std::vector<std::uint8_t> rgba(41 * 29 * 4);
        for (auto& b : rgba) b = std::uint8_t(rng() % 256);
        const MipMap mip(std::make_shared<Image>(Image::ldr(41, 29, ColorSpace::linear, rgba)));
        const Color4 base = mean_of(mip.base());
        for (int l = 1; l < mip.level_count(); ++l) {
            const Color4 m = mean_of(mip.level(l));
            for (int c = 0; c < 4; ++c) CHECK(std::fabs(m[c] - base[c]) <= float(l) * 0.5f / 255.0f + 1e-6f);
        }
    }
}

TEST_CASE("node-registered mip levels: every other node filtered 1/4, 1/2, 1/4, the ends read through the wrap mode") {
    // 9 x 5 nodes (2^3 + 1 by 2^2 + 1): level 1 is 5 x 3, node (i, j) at source node (2i, 2j).
    const Image base = random_hdr(9, 5, 21);
    const Color4 border(0.25f, 0.5f, 0.75f, 1.0f);
    // The source node k of n along an axis, as each wrap mode reads it (worked out from the
    // modes' definitions: repeat every n - 1 nodes, mirror about the end nodes).
    const auto wrapped = [](Wrap mode, int k, int n) {
        if (k >= 0 && k < n) return k;
        switch (mode) {
            case Wrap::repeat: return k < 0 ? k + (n - 1) : k - (n - 1);
            case Wrap::mirror: return k < 0 ? -k : 2 * (n - 1) - k;
            case Wrap::clamp: return k < 0 ? 0 : n - 1;
            case Wrap::border: return -1;
        }
        return 0;
    };
    const float tap[3] = {0.25f, 0.5f, 0.25f};
    for (Wrap mode : {Wrap::repeat, Wrap::mirror, Wrap::clamp, Wrap::border}) {
        CAPTURE(int(mode));
        Sampler s;
        s.registration = Registration::node;
        s.wrap_u = s.wrap_v = mode;
        s.border = border;
        const MipMap mip(std::make_shared<Image>(base), s);
        CHECK(mip.node_levels());
        REQUIRE(mip.level_count() == 5);  // 9x5, 5x3, 3x2, 2x1, 1x1
        const Image& level = mip.level(1);
        REQUIRE(level.width() == 5);
        REQUIRE(level.height() == 3);
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 5; ++i) {
                Color4 want(0.0f);
                for (int b = -1; b <= 1; ++b)
                    for (int a = -1; a <= 1; ++a) {
                        const int x = wrapped(mode, 2 * i + a, 9), y = wrapped(mode, 2 * j + b, 5);
                        want += tap[a + 1] * tap[b + 1] * ((x < 0 || y < 0) ? border : base.texel(x, y));
                    }
                for (int c = 0; c < 4; ++c) CHECK(level.texel(i, j)[c] == doctest::Approx(want[c]).epsilon(1e-5));
            }
        // The last level holds the mean over the whole image, [0, 8] x [0, 4], of the linear
        // interpolation between nodes: the trapezoid rule, end nodes at half weight.
        Color4 mean(0.0f);
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 9; ++i)
                mean += ((i == 0 || i == 8) ? 0.5f : 1.0f) * ((j == 0 || j == 4) ? 0.5f : 1.0f) * base.texel(i, j);
        mean = mean / 32.0f;
        const Image& top = mip.level(4);
        REQUIRE(top.width() == 1);
        REQUIRE(top.height() == 1);
        // (The levels between are filtered with the wrap mode too, which moves the mean a
        // little except for repeat, where every level keeps the period's mean.)
        if (mode == Wrap::repeat)
            for (int c = 0; c < 4; ++c) CHECK(top.texel(0, 0)[c] == doctest::Approx(mean[c]).epsilon(1e-5));
    }
    // Cell registration keeps the box levels: 9 -> 4 -> 2 -> 1.
    Sampler cell;
    const MipMap boxes(std::make_shared<Image>(base), cell);
    CHECK_FALSE(boxes.node_levels());
    CHECK(boxes.level_count() == 4);
    CHECK(boxes.level(1).width() == 4);
}

TEST_CASE("node-registered mip levels of any size match the mean of the linear interpolation, integrated piece by piece") {
    // An independent reference along one axis: level m = floor(n/2) + 1 (1 from n <= 2) has
    // node i at x = i (n - 1) / (m - 1); its value is the mean of the linear interpolation L
    // of the wrapped source nodes over [x - r/2, x + r/2] ([0, n - 1] for m = 1), integrated
    // exactly by splitting the interval at whole nodes and taking each piece's trapezoid
    // (exact for a linear piece).
    const auto node_of = [](Wrap mode, int k, int n) {  // the node each mode reads, -1 for the border
        if (k >= 0 && k < n) return k;
        if (n == 1) return mode == Wrap::border ? -1 : 0;
        const int period = n - 1;
        switch (mode) {
            case Wrap::repeat: return ((k % period) + period) % period;
            case Wrap::mirror: {
                const int t = ((k % (2 * period)) + 2 * period) % (2 * period);
                return t <= period ? t : 2 * period - t;
            }
            case Wrap::clamp: return k < 0 ? 0 : n - 1;
            case Wrap::border: return -1;
        }
        return 0;
    };
    const double border = -0.75;
    const auto reference_level = [&](const std::vector<double>& p, Wrap mode) {
        const int n = int(p.size()), m = n <= 2 ? 1 : n / 2 + 1;
        const auto value = [&](int k) {
            const int j = node_of(mode, k, n);
            return j < 0 ? border : p[std::size_t(j)];
        };
        const auto L = [&](double t) {
            const double k = std::floor(t), f = t - k;
            return (1.0 - f) * value(int(k)) + f * value(int(k) + 1);
        };
        std::vector<double> out;
        for (int i = 0; i < m; ++i) {
            const double r = m > 1 ? double(n - 1) / double(m - 1) : 0.0;
            const double lo = m > 1 ? (i - 0.5) * r : 0.0, hi = m > 1 ? (i + 0.5) * r : double(n - 1);
            if (hi == lo) {  // a single node
                out.push_back(value(0));
                continue;
            }
            double integral = 0.0;
            for (double a = lo; a < hi;) {
                const double b = std::min(hi, std::floor(a) + 1.0);
                integral += (b - a) * 0.5 * (L(a) + L(b));  // (L is continuous at whole nodes)
                a = b;
            }
            out.push_back(integral / (hi - lo));
        }
        return out;
    };
    std::mt19937_64 rng(77);
    std::uniform_real_distribution<double> value(-1.0, 2.0);
    for (int n : {2, 3, 4, 5, 6, 7, 10, 12, 16, 21, 33, 64}) {
        std::vector<double> base(static_cast<std::size_t>(n));
        for (double& b : base) b = value(rng);
        std::vector<float> rgba;
        for (double b : base) rgba.insert(rgba.end(), {float(b), 0.0f, 0.0f, 1.0f});
        const auto image = std::make_shared<Image>(Image::hdr(n, 1, rgba));
        for (Wrap mode : {Wrap::repeat, Wrap::mirror, Wrap::clamp, Wrap::border}) {
            CAPTURE(n);
            CAPTURE(int(mode));
            Sampler s;
            s.registration = Registration::node;
            s.wrap_u = s.wrap_v = mode;
            s.border = Color4(float(border), 0.0f, 0.0f, 1.0f);
            const MipMap mip(image, s);
            std::vector<double> expected(base.begin(), base.end());
            for (int l = 1; l < mip.level_count(); ++l) {
                // (The image is one node high: along v every level reads that node alone.)
                for (double& e : expected) e = float(e);  // each level is stored as float
                expected = reference_level(expected, mode);
                const Image& level = mip.level(l);
                REQUIRE(level.width() == int(expected.size()));
                REQUIRE(level.height() == 1);
                for (int i = 0; i < level.width(); ++i) CHECK(level.texel(i, 0).x == doctest::Approx(expected[std::size_t(i)]).epsilon(1e-5));
            }
            CHECK(mip.level(mip.level_count() - 1).width() == 1);
        }
    }
}

TEST_CASE("node registration's mip filters read a linear ramp where it is, on every level") {
    // R = u and G = v at the nodes (u = i / (n - 1)): every node level holds the same ramp,
    // and bilinear lookups of a ramp are exact, so trilinear returns (u, v) at any level of
    // detail, away from the ends (where clamp flattens the ramp). Box levels read on the node
    // lattice would be up to half a level's texel off: on level 1 of 16 texels, texel i
    // averages nodes 2i and 2i + 1, (2i + 1/2) / 15, where the node lattice puts i / 7.
    for (const std::pair<int, int>& size : {std::pair{16, 12}, std::pair{17, 9}, std::pair{33, 20}}) {
        // (named, not a structured binding: doctest's CAPTURE is a lambda, which cannot capture
        // one in C++17; clang refuses it)
        const int w = size.first, h = size.second;  // (CAPTURE: not a structured binding)
        CAPTURE(w);
        std::vector<float> rgba;
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) rgba.insert(rgba.end(), {float(i) / float(w - 1), float(j) / float(h - 1), 0.5f, 1.0f});
        Sampler s;
        s.registration = Registration::node;
        s.wrap_u = s.wrap_v = Wrap::clamp;
        const MipMap mip(std::make_shared<Image>(Image::hdr(w, h, rgba)), s);
        for (double lambda : {0.0, 0.5, 1.0, 1.7, 2.0, 2.5}) {
            CAPTURE(lambda);
            // Level l's end nodes see the clamp within about 2^(l+1) base nodes of the ends.
            const double margin_u = std::ldexp(2.0, int(lambda) + 2) / (w - 1), margin_v = std::ldexp(2.0, int(lambda) + 2) / (h - 1);
            if (margin_u >= 0.45 || margin_v >= 0.45) continue;
            for (double fu = 0.0; fu <= 1.0; fu += 0.125)
                for (double fv = 0.0; fv <= 1.0; fv += 0.25) {
                    const double u = margin_u + fu * (1.0 - 2.0 * margin_u), v = margin_v + fv * (1.0 - 2.0 * margin_v);
                    const Color4 got = sample_trilinear(mip, s, u, v, lambda);
                    CHECK(got.x == doctest::Approx(u).epsilon(1e-5));
                    CHECK(got.y == doctest::Approx(v).epsilon(1e-5));
                    const Color4 nearest_level = sample_mip_nearest(mip, s, u, v, lambda, true);
                    CHECK(nearest_level.x == doctest::Approx(u).epsilon(1e-5));
                }
        }
    }
}

TEST_CASE("level of detail is 0 at one texel per pixel and 1 at two, whatever the rotation") {
    for (double degrees : {0.0, 30.0, 45.0, 77.0}) {
        CAPTURE(degrees);
        CHECK(level_of_detail(rotated(1.0, degrees, 256), 256, 256) == doctest::Approx(0.0).scale(1.0));
        CHECK(level_of_detail(rotated(2.0, degrees, 256), 256, 256) == doctest::Approx(1.0));
        CHECK(level_of_detail(rotated(8.0, degrees, 256), 256, 256) == doctest::Approx(3.0));
    }
    // Non-square texture: lengths are measured in texels of each axis.
    CHECK(level_of_detail({2.0 / 512, 0.0, 0.0, 2.0 / 128}, 512, 128) == doctest::Approx(1.0));
    // The longer derivative vector decides.
    CHECK(level_of_detail({1.0 / 256, 0.0, 0.0, 4.0 / 256}, 256, 256) == doctest::Approx(2.0));
}

TEST_CASE("the level of detail's log2 is within 1e-13 of std::log2 and exact at powers of two") {
    using minify_detail::log2_positive;
    // Powers of two, with every exponent a footprint can have (subnormals included).
    for (int e = -1074; e <= 1023; ++e) CHECK(log2_positive(std::ldexp(1.0, e)) == double(e));
    // The mantissa across [1, 2), densely, at several exponents, and both sides of every
    // boundary 1 + i/128 where the table entry switches.
    double worst = 0.0;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> mantissa(1.0, 2.0);
    for (int i = 0; i < 200000; ++i) {
        const double r = std::ldexp(mantissa(rng), int(i % 120) - 60);
        worst = std::max(worst, std::fabs(log2_positive(r) - std::log2(r)));
    }
    for (int i = 1; i <= 128; ++i)
        for (int e : {-40, 0, 3}) {
            const double c = std::ldexp(1.0 + i / 128.0, e);
            for (double r : {c, std::nextafter(c, 0.0), std::nextafter(c, 1e300)})
                worst = std::max(worst, std::fabs(log2_positive(r) - std::log2(r)));
        }
    for (double r : {std::sqrt(2.0), std::nextafter(1.0, 0.0), std::nextafter(1.0, 2.0), 1e-300, 1e300})
        worst = std::max(worst, std::fabs(log2_positive(r) - std::log2(r)));
    CHECK(worst < 1e-13);
    MESSAGE("largest difference from std::log2: " << worst);
    // Outside the normal range it is std::log2 itself.
    CHECK(log2_positive(std::numeric_limits<double>::infinity()) == std::numeric_limits<double>::infinity());
    CHECK(std::isnan(log2_positive(std::nan(""))));
    CHECK(log2_positive(5e-324) == -1074.0);
}

#if defined(__SSE2__)
TEST_CASE("level_of_detail_lanes gives level_of_detail's bits in each lane, special values included") {
    // The lanes are worked out by the scalar function, one footprint at a time: each lane of
    // every pair must be the same double, bit for bit (the span walk relies on it for
    // frames that are the same bytes either way).
    const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
    const std::vector<double> specials = {0.0, -0.0, nan, inf, -inf, 5e-324, -4e-310, 1e-160, 1e160, 1e300, 1.0, -0.5};
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> exponent(-40.0, 40.0), unit(0.0, 1.0);
    const auto random_component = [&] {
        if (unit(rng) < 0.05) return specials[std::size_t(unit(rng) * double(specials.size())) % specials.size()];
        return (unit(rng) < 0.5 ? -1.0 : 1.0) * std::pow(2.0, exponent(rng));
    };
    const auto bits = [](double x) {
        std::uint64_t b;
        std::memcpy(&b, &x, sizeof b);
        return b;
    };
    int differing = 0, pairs = 0, special_lanes = 0;
    for (int i = 0; i < 400000; ++i) {
        UVDerivatives d[2];
        for (UVDerivatives& e : d) e = {random_component(), random_component(), random_component(), random_component()};
        const int width = i % 3 == 0 ? 1024 : 1 << (i % 12), height = i % 5 == 0 ? 768 : 1 << (i % 9);
        alignas(16) double lanes[2];
        _mm_store_pd(lanes, level_of_detail_lanes(_mm_set_pd(d[1].dudx, d[0].dudx), _mm_set_pd(d[1].dvdx, d[0].dvdx),
                                                  _mm_set_pd(d[1].dudy, d[0].dudy), _mm_set_pd(d[1].dvdy, d[0].dvdy),
                                                  width, height));
        for (int k = 0; k < 2; ++k) {
            const double scalar = level_of_detail(d[k], width, height);
            differing += bits(lanes[k]) != bits(scalar);
            special_lanes += !(std::fabs(scalar) < 1e9) || scalar < -1000.0;
        }
        ++pairs;
    }
    CHECK(differing == 0);
    CHECK(special_lanes > 1000);  // zero, infinite and subnormal footprints were among them
    MESSAGE(pairs << " pairs, " << special_lanes << " lanes at a point, infinite or subnormal footprint");
}
#endif

#if defined(__SSE2__)
TEST_CASE("trilinear_levels_lanes gives trilinear's level int(lambda) and fraction float(lambda - l0), -1 at the ends") {
    const double inf = std::numeric_limits<double>::infinity();
    const int last = 10;
    std::vector<double> values = {0.0, -0.0, 5e-324, 1e-300, 0.5, 1.0, std::nextafter(1.0, 0.0), 9.0, std::nextafter(10.0, 0.0),
                                  10.0, 10.5, -0.5, -1e9, 1e300, inf, -inf, std::nan("")};
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> any(-1.0, 11.0);
    for (int i = 0; i < 2000; ++i) values.push_back(any(rng));
    int checked = 0, inside = 0;
    for (int n = 0; n <= 32; ++n)
        for (std::size_t start = 0; start + std::size_t(n) <= values.size(); start += 37) {
            int l0s[32];
            float fractions[32];
            trilinear_levels_lanes(values.data() + start, n, last, l0s, fractions);
            for (int k = 0; k < n; ++k) {
                const double lambda = values[start + std::size_t(k)];
                CAPTURE(lambda);
                if (lambda > 0.0 && lambda < last) {
                    const float fraction = float(lambda - int(lambda));
                    REQUIRE(l0s[k] == int(lambda));
                    REQUIRE(std::memcmp(&fractions[k], &fraction, sizeof fraction) == 0);
                    ++inside;
                } else {
                    REQUIRE(l0s[k] == -1);
                }
                ++checked;
            }
        }
    CHECK(inside > checked / 2);
    MESSAGE(checked << " levels of detail, " << inside << " between the ends");
}
#endif

TEST_CASE("levels_of_detail_avx2 gives the scalar 1/q, (u, v) and level of detail, four pixels at a time, to the bit") {
    if (!avx2_lanes_available()) {
        MESSAGE("this CPU has no AVX2 (or TEXR_NO_AVX2 is set): the batched walk uses SSE2's lanes, tested above");
        return;
    }
    const auto bits = [](double x) {
        std::uint64_t b;
        std::memcpy(&b, &x, sizeof b);
        return b;
    };
    const double inf = std::numeric_limits<double>::infinity();
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-30.0, 30.0);
    const auto value = [&] { return unit(rng) * std::pow(2.0, exponent(rng)); };
    int differing = 0, pixels = 0, special = 0;
    for (int round = 0; round < 20000; ++round) {
        // A homography whose derivative rows are random, some of them 0 (point footprints) or
        // huge (infinite ones); q of 0, infinity or NaN now and then.
        TextureHomography h;
        for (Plane* p : {&h.u_prime, &h.v_prime, &h.q}) {
            p->dx = round % 7 == 0 ? 0.0 : value(), p->dy = round % 11 == 0 ? 0.0 : value(), p->c = value();
            if (round % 13 == 0) p->dx *= 1e300;
        }
        const int n = round % 38, width = 1 << (round % 13), height = round % 3 == 0 ? 768 : 1 << (round % 10);
        const bool stepped = round % 2 == 0;
        double q[40], u[40], v[40], lambda[40];
        for (int k = 0; k < n; ++k) {
            q[k] = value(), u[k] = value(), v[k] = value();
            if (round % 17 == 0 && k % 5 == 0) q[k] = k % 3 == 0 ? 0.0 : k % 3 == 1 ? inf : std::nan("");
        }
        double want_q[40], want_u[40], want_v[40];
        for (int k = 0; k < n; ++k) want_q[k] = q[k], want_u[k] = u[k], want_v[k] = v[k];
        const int done = levels_of_detail_avx2(h, width, height, stepped, n, q, u, v, lambda);
        REQUIRE(done == n / 4 * 4);
        for (int k = 0; k < done; ++k) {
            const double inv_q = 1.0 / want_q[k];
            if (stepped) want_u[k] *= inv_q, want_v[k] *= inv_q;
            const UVDerivatives d = uv_derivatives_from_inverse_q(h, want_u[k], want_v[k], inv_q);
            const double want_lambda = level_of_detail(d, width, height);
            differing += bits(q[k]) != bits(inv_q) || bits(u[k]) != bits(want_u[k]) || bits(v[k]) != bits(want_v[k]) ||
                         bits(lambda[k]) != bits(want_lambda);
            special += !(std::fabs(want_lambda) < 1e9);
            ++pixels;
        }
    }
    CHECK(differing == 0);
    CHECK(special > 1000);  // point, infinite and NaN footprints were among them
    MESSAGE(pixels << " pixels, " << special << " with a point, infinite or NaN footprint");
}

TEST_CASE("anisotropic and EWA filtering of a constant texture return the constant") {
    const MipMap mip(std::make_shared<Image>(constant_ldr(50, 70, 200)));
    const Color4 expected = mip.base().texel(0, 0);
    Sampler s;
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> coordinate(-3.0, 3.0), scale(-6.0, 1.0);
    for (int k = 0; k < 500; ++k) {
        const double big = std::pow(10.0, scale(rng)), small = big * std::pow(10.0, scale(rng) / 2.0);
        const UVDerivatives d{big * coordinate(rng), big * coordinate(rng), small * coordinate(rng), small * coordinate(rng)};
        const double u = coordinate(rng), v = coordinate(rng);
        int probes = 0, texels = 0;
        const Color4 a = sample_anisotropic(mip, s, u, v, d, probes);
        const Color4 e = sample_ewa(mip, s, u, v, d, texels);
        for (int c = 0; c < 4; ++c) {
            REQUIRE(a[c] == doctest::Approx(expected[c]).epsilon(1e-5));
            REQUIRE(e[c] == doctest::Approx(expected[c]).epsilon(1e-5));
        }
        CHECK(probes <= 16);
    }
}

TEST_CASE("at strong minification of white noise every mipmapped filter approaches its mean") {
    std::mt19937_64 rng(21);
    std::vector<std::uint8_t> rgba(256 * 256 * 4);
    for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = (i % 4 == 3) ? 255 : std::uint8_t(rng() % 256);
    const MipMap mip(std::make_shared<Image>(Image::ldr(256, 256, ColorSpace::linear, rgba)));
    const Color4 mean = mean_of(mip.base());
    Sampler s;
    std::uniform_real_distribution<double> coordinate(0.0, 1.0);
    for (double texels_per_pixel : {300.0, 1000.0}) {
        for (double degrees : {0.0, 35.0}) {
            // An anisotropic footprint: 300+ texels long, a quarter of that wide.
            UVDerivatives d = rotated(texels_per_pixel, degrees, 256);
            d.dudy *= 0.25, d.dvdy *= 0.25;
            const double u = coordinate(rng), v = coordinate(rng);
            const double lambda = level_of_detail(d, 256, 256);
            int n = 0;
            const Color4 results[] = {sample_mip_nearest(mip, s, u, v, lambda, false), sample_mip_nearest(mip, s, u, v, lambda, true),
                                      sample_trilinear(mip, s, u, v, lambda), sample_anisotropic(mip, s, u, v, d, n),
                                      sample_ewa(mip, s, u, v, d, n)};
            for (const Color4& r : results)
                for (int c = 0; c < 3; ++c) CHECK(r[c] == doctest::Approx(mean[c]).epsilon(0.03));
        }
    }
}

TEST_CASE("at moderate minification of white noise the mip filters average it") {
    // 20 texels per pixel on a 256^2 noise image: lambda = log2(20) = 4.3, so the filters read
    // levels 4 and 5 (16^2 and 8^2), each texel the mean of 256 or more base texels; their
    // standard deviation is under 73.6 / 16 = 4.6 levels of 255 around the mean (~128).
    std::mt19937_64 rng(23);
    std::vector<std::uint8_t> rgba(256 * 256 * 4);
    for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = (i % 4 == 3) ? 255 : std::uint8_t(rng() % 256);
    const MipMap mip(std::make_shared<Image>(Image::ldr(256, 256, ColorSpace::linear, rgba)));
    const Color4 mean = mean_of(mip.base());
    Sampler s;
    const UVDerivatives d = rotated(20.0, 30.0, 256);
    const double lambda = level_of_detail(d, 256, 256);
    CHECK(lambda == doctest::Approx(std::log2(20.0)));
    std::uniform_real_distribution<double> coordinate(0.0, 1.0);
    int bilinear_outliers = 0;
    for (int k = 0; k < 20; ++k) {
        const double u = coordinate(rng), v = coordinate(rng);
        for (const Color4& r : {sample_mip_nearest(mip, s, u, v, lambda, true), sample_trilinear(mip, s, u, v, lambda)})
            for (int c = 0; c < 3; ++c) CHECK(std::fabs(r[c] - mean[c]) < 5.0f * 4.6f / 255.0f);  // 5 sigma
        // The base level alone is far noisier: the same bound fails for plain bilinear.
        bilinear_outliers += std::fabs(sample_bilinear(mip.base(), s, u, v).x - mean.x) >= 5.0f * 4.6f / 255.0f;
    }
    CHECK(bilinear_outliers > 5);
}

TEST_CASE("mip filters at one texel per pixel read the base level like bilinear") {
    const MipMap mip(std::make_shared<Image>(random_hdr(32, 32, 8)));
    Sampler s;
    const UVDerivatives d = rotated(1.0, 0.0, 32);
    for (double u = 0.01; u < 1.0; u += 0.097) {
        const Color4 want = sample_bilinear(mip.base(), s, u, 0.37);
        const Color4 got = sample_trilinear(mip, s, u, 0.37, level_of_detail(d, 32, 32));
        int probes = 0;
        const Color4 aniso = sample_anisotropic(mip, s, u, 0.37, d, probes);
        CHECK(probes == 1);
        for (int c = 0; c < 3; ++c) {
            CHECK(got[c] == doctest::Approx(want[c]).epsilon(1e-5));
            CHECK(aniso[c] == doctest::Approx(want[c]).epsilon(1e-5));
        }
    }
}

TEST_CASE("EWA is exact for |u| up to 1e7: periodic for repeat and mirror, edges for clamp") {
    const MipMap mip(std::make_shared<Image>(random_hdr(300, 40, 17)));
    const UVDerivatives d = {3.0 / 300, 0.5 / 40, -0.4 / 300, 1.2 / 40};  // a small rotated footprint
    for (Registration r : {Registration::cell, Registration::node})
        for (Wrap w : {Wrap::repeat, Wrap::mirror}) {
            Sampler s;
            s.wrap_u = s.wrap_v = w, s.registration = r;
            for (double u : {0.1, 0.5, 0.93}) {
                int n = 0;
                const Color4 near_zero = sample_ewa(mip, s, u, 0.3, d, n);
                const Color4 far = sample_ewa(mip, s, u + 1e7, 0.3, d, n);
                for (int c = 0; c < 3; ++c) CHECK(far[c] == doctest::Approx(near_zero[c]).epsilon(1e-4));
            }
        }
    // Clamp: far right reads like just right of the image, far left like just left of it.
    Sampler s;
    s.wrap_u = s.wrap_v = Wrap::clamp;
    int n = 0;
    const Color4 right = sample_ewa(mip, s, 1e7, 0.3, d, n), just_right = sample_ewa(mip, s, 1.5, 0.3, d, n);
    const Color4 left = sample_ewa(mip, s, -1e7, 0.3, d, n), just_left = sample_ewa(mip, s, -0.5, 0.3, d, n);
    for (int c = 0; c < 3; ++c) {
        CHECK(right[c] == doctest::Approx(just_right[c]).epsilon(1e-5));
        CHECK(left[c] == doctest::Approx(just_left[c]).epsilon(1e-5));
    }
}

TEST_CASE("footprint filters stay bounded and finite for huge, infinite and NaN footprints") {
    const MipMap mip(std::make_shared<Image>(random_hdr(64, 64, 19)));
    const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
    Sampler s;
    for (const UVDerivatives& d : {UVDerivatives{1e5, 0.0, 0.0, 1e5}, UVDerivatives{1e5, 3e4, -2e4, 7e4},
                                   UVDerivatives{inf, 0.0, 0.0, 1.0}, UVDerivatives{nan, nan, nan, nan},
                                   UVDerivatives{1e300, 1e300, 1e300, 1e300}, UVDerivatives{inf, 0.0, 0.0, inf},
                                   UVDerivatives{1e200, 1e200, 0.0, 0.0}, UVDerivatives{1e160, 0.0, 0.0, 1e160}}) {
        int texels = 0, probes = 0;
        const Color4 e = sample_ewa(mip, s, 0.3, 0.6, d, texels);
        CHECK(texels <= 4);  // wider than the coarsest level: that level's average
        if (!std::isnan(d.dudx))  // (all NaN: no footprint at all, read as a point)
            for (int c = 0; c < 4; ++c) CHECK(e[c] == doctest::Approx(mip.level(mip.level_count() - 1).texel(0, 0)[c]));
        const Color4 a = sample_anisotropic(mip, s, 0.3, 0.6, d, probes);
        const double lambda = level_of_detail(d, 64, 64);
        const Color4 t = sample_trilinear(mip, s, 0.3, 0.6, lambda);
        const Color4 m = sample_mip_nearest(mip, s, 0.3, 0.6, lambda, true);
        for (int c = 0; c < 4; ++c) {
            CHECK(std::isfinite(e[c]));
            CHECK(std::isfinite(a[c]));
            CHECK(std::isfinite(t[c]));
            CHECK(std::isfinite(m[c]));
        }
    }
}

TEST_CASE("every footprint filter takes a derivative vector with a NaN as no extent: the other one is the footprint") {
    const MipMap mip(std::make_shared<Image>(random_hdr(64, 64, 19)));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    Sampler s;
    // Each case with its NaN vector replaced by (0, 0): the answers must be the same.
    const std::pair<UVDerivatives, UVDerivatives> cases[] = {
        {{0.05, 0.01, nan, 0.0}, {0.05, 0.01, 0.0, 0.0}},   {{nan, 0.0, 0.02, 0.01}, {0.0, 0.0, 0.02, 0.01}},
        {{0.2, 0.1, 0.0, nan}, {0.2, 0.1, 0.0, 0.0}},       {{0.0, nan, 0.3, 0.05}, {0.0, 0.0, 0.3, 0.05}},
        {{0.004, 0.002, nan, nan}, {0.004, 0.002, 0.0, 0.0}}};
    for (const auto& nan_and_zero : cases) {
        const UVDerivatives &with_nan = nan_and_zero.first, &with_zero = nan_and_zero.second;
        CAPTURE(with_zero.dudx);
        CAPTURE(with_zero.dudy);
        const double lambda = level_of_detail(with_nan, 64, 64);
        CHECK(lambda == level_of_detail(with_zero, 64, 64));
        CHECK(lambda > -1e8);  // a footprint, not a point
        int texels = 0, zero_texels = 0, probes = 0, zero_probes = 0;
        const Color4 e = sample_ewa(mip, s, 0.3, 0.6, with_nan, texels), ez = sample_ewa(mip, s, 0.3, 0.6, with_zero, zero_texels);
        const Color4 a = sample_anisotropic(mip, s, 0.3, 0.6, with_nan, probes),
                     az = sample_anisotropic(mip, s, 0.3, 0.6, with_zero, zero_probes);
        CHECK(texels == zero_texels);
        CHECK(probes == zero_probes);
        CHECK(probes == 16);  // a degenerate footprint: the most eccentric, max_anisotropy probes
        for (int c = 0; c < 4; ++c) {
            CHECK(e[c] == ez[c]);
            CHECK(a[c] == az[c]);
            CHECK(std::isfinite(e[c]));
        }
    }
    // The first two: the finite vector is the major axis (3.3 or 1.4 texels) and the minor one
    // is stretched to a sixteenth of it: an ellipse of a few texels, on the base level.
    int texels = 0;
    sample_ewa(mip, s, 0.3, 0.6, cases[0].first, texels);
    CHECK(texels > 4);
    CHECK(texels <= 20);
}

TEST_CASE("EWA at a NaN coordinate returns a finite colour for every wrap mode") {
    const MipMap mip(std::make_shared<Image>(random_hdr(64, 64, 19)));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (Wrap wrap : {Wrap::repeat, Wrap::mirror, Wrap::clamp, Wrap::border}) {
        Sampler s;
        s.wrap_u = s.wrap_v = wrap;
        int texels = 0;
        const Color4 e = sample_ewa(mip, s, nan, 0.4, {0.05, 0.01, -0.002, 0.01}, texels);
        for (int c = 0; c < 4; ++c) CHECK(std::isfinite(e[c]));
    }
}

TEST_CASE("EWA at coordinates from 1e15 texels to infinity with clamp and border reads the edge or the border") {
    // A white 4x4 texture. Far outside on u, a small footprint covers only what lies beyond
    // the left or right edge: the border colour (0) with border, the edge texels (1) with
    // clamp, whatever the magnitude, up to infinity (where no centre is left to move).
    const MipMap mip(std::make_shared<Image>(Image::hdr(4, 4, std::vector<float>(64, 1.0f))));
    const double inf = std::numeric_limits<double>::infinity();
    for (const double u : {-1e16, 1e16, -1e20, 1e300, -inf, inf}) {
        CAPTURE(u);
        Sampler border, clamp;
        border.wrap_u = border.wrap_v = Wrap::border, border.border = Color4(0.0f);
        clamp.wrap_u = clamp.wrap_v = Wrap::clamp;
        int texels = 0;
        const UVDerivatives d = {0.1, 0.0, 0.0, 0.1};  // 0.4 texels: the base level
        CHECK(sample_ewa(mip, border, u, 0.5, d, texels).x == 0.0f);
        CHECK(sample_ewa(mip, clamp, u, 0.5, d, texels).x == doctest::Approx(1.0));
    }
}

TEST_CASE("nearest-mip level selection follows OpenGL: lambda <= 1/2 is level 0, else ceil(lambda + 1/2) - 1") {
    const MipMap mip(std::make_shared<Image>(random_hdr(16, 16, 31)));
    Sampler s;
    // (lambda, level) worked out from the rule by hand.
    const std::pair<double, int> cases[] = {{-3.0, 0}, {0.5, 0}, {0.51, 1}, {1.5, 1}, {1.51, 2}, {2.0, 2}, {2.49, 2}, {3.5, 3}, {99.0, 4}};
    for (const auto& lambda_and_level : cases) {
        const double lambda = lambda_and_level.first;  // (CAPTURE: not a structured binding)
        const int level = lambda_and_level.second;
        CAPTURE(lambda);
        for (double u : {0.13, 0.61})
            CHECK(sample_mip_nearest(mip, s, u, 0.37, lambda, false).x == sample_nearest(mip.level(level), s, u, 0.37).x);
    }
}

namespace {

// The principal semi-axes of the footprint ellipse {d1 cos t + d2 sin t} as vectors: its
// longest radius, by a scan of t in [0, pi) and a golden-section search around the best
// sample, and the radius a quarter turn of t away (the squared radius is
// a + b cos 2(t - t0), so that one is the shortest). (The filters use a closed form.)
std::pair<glm::dvec2, glm::dvec2> principal_axes_by_search(double d1u, double d1v, double d2u, double d2v) {
    const auto at = [&](double t) { return glm::dvec2(d1u * std::cos(t) + d2u * std::sin(t), d1v * std::cos(t) + d2v * std::sin(t)); };
    const auto radius2 = [&](double t) { return glm::dot(at(t), at(t)); };
    double best = 0.0;
    for (int k = 1; k < 3600; ++k)
        if (radius2(M_PI * k / 3600) > radius2(best)) best = M_PI * k / 3600;
    double lo = best - M_PI / 3600, hi = best + M_PI / 3600;
    for (int k = 0; k < 100; ++k) {
        const double m1 = hi - (hi - lo) * 0.618033988749895, m2 = lo + (hi - lo) * 0.618033988749895;
        if (radius2(m1) < radius2(m2)) lo = m1;
        else hi = m2;
    }
    const double t_major = 0.5 * (lo + hi);
    return {at(t_major), at(t_major + M_PI / 2)};
}

}  // namespace

TEST_CASE("anisotropic filtering is the mean of its trilinear probes along the major axis") {
    // The probes, from the definition: n = ceil(min(major / minor, max anisotropy)) trilinear
    // lookups at offsets (k + 1/2) / n - 1/2 of the footprint's major axis (principal, in
    // base texels), at level log2(major / n). Worked out here on the public trilinear lookup,
    // against the filter's own loop (which reads the level views directly for these
    // power-of-two 8-bit textures, one square and one 64x16, so that texels are not square in
    // (u, v)). The last three footprints are sheared: their major axis is neither derivative
    // vector, and about 10, 20 and 40 times their minor axis (11, 16 and 16 probes), while the
    // two derivative vectors' lengths differ by 2% or less (the GL extension's rule, which
    // takes those lengths for the axes, would make two probes).
    std::mt19937_64 rng(23);
    for (const int height : {64, 16}) {
        std::vector<std::uint8_t> rgba(64 * std::size_t(height) * 4);
        for (auto& b : rgba) b = std::uint8_t(rng() % 256);
        const auto image = std::make_shared<Image>(Image::ldr(64, height, ColorSpace::srgb, rgba));
        const double w = 64, h = height;
        Sampler s;
        s.filter = Filter::anisotropic;
        s.max_anisotropy = 16;
        REQUIRE(takes_short_path(*image, s));
        {  // magnified: only the base level is read, and no level is built
            const MipMap mip(image);
            int probes = 0;
            sample_anisotropic(mip, s, 0.3, 0.6, {0.2 / w, 0.0, 0.0, 0.05 / h}, probes);
            CHECK(probes == 4);
            CHECK_FALSE(mip.built());
        }
        const MipMap mip(image);
        struct Texels {
            double d1u, d1v, d2u, d2v;  // the derivative vectors in base texels
        };
        for (const Texels& f : {Texels{6.0, 1.0, -0.5, 1.5}, Texels{0.3, 0.0, 0.0, 9.0}, Texels{40.0, 0.0, 0.0, 1.0},
                                Texels{0.2, 0.0, 0.0, 0.05}, Texels{2000.0, 0.0, 0.0, 300.0} /* beyond the 1x1 level */,
                                Texels{6.0, 0.0, 6.0, 1.2}, Texels{5.0, 0.0, 5.0, 0.5}, Texels{2.0, 2.0, 2.1, 1.9}}) {
            const UVDerivatives d = {f.d1u / w, f.d1v / h, f.d2u / w, f.d2v / h};
            const auto [a1, a2] = principal_axes_by_search(f.d1u, f.d1v, f.d2u, f.d2v);
            const double major = glm::length(a1), minor = glm::length(a2);
            const int n = int(std::ceil(std::min(major / minor, 16.0) - 1e-9));
            const double au = a1.x / w, av = a1.y / h;
            for (double u : {0.3, -2.71, 1e6 + 0.1, 2e13 /* beyond 1e15 texels: the general path */}) {
                CAPTURE(height);
                CAPTURE(u);
                CAPTURE(n);
                Color4 expected(0.0f);
                for (int k = 0; k < n; ++k) {
                    const double t = (k + 0.5) / n - 0.5;
                    expected += sample_trilinear(mip, s, u + t * au, 0.6 + t * av, std::log2(major / n));
                }
                expected *= 1.0f / float(n);
                int probes = 0;
                const Color4 got = sample_anisotropic(mip, s, u, 0.6, d, probes);
                CHECK(probes == n);
                for (int c = 0; c < 3; ++c) CHECK(got[c] == doctest::Approx(expected[c]).epsilon(1e-6));
            }
        }
    }
}

TEST_CASE("footprint_axes: the principal axes of sheared, huge and tiny footprints") {
    // Against the search of the ellipse's radii, for footprints of ordinary size; and, as
    // scaling both vectors by k scales the axes by k, the same footprints scaled by 2^200 and
    // 2^-200 (where squaring without rescaling would overflow or underflow) give the same
    // axes times k.
    for (const std::array<double, 4>& f : {std::array<double, 4>{6.0, 1.0, -0.5, 1.5}, {6.0, 0.0, 6.0, 1.2}, {2.0, 2.0, 2.1, 1.9},
                                              {0.0, 3.0, 2.0, 0.0}, {1.0, 2.0, 2.0, 4.0} /* parallel */}) {
        const double d1u = f[0], d1v = f[1], d2u = f[2], d2v = f[3];  // (CAPTURE: not a structured binding)
        const auto [a1, a2] = principal_axes_by_search(d1u, d1v, d2u, d2v);
        for (const int e : {0, 200, -200, 1000, -1000}) {
            CAPTURE(d1u);
            CAPTURE(e);
            const double k = std::ldexp(1.0, e);
            const FootprintAxes axes = footprint_axes(d1u * k, d1v * k, d2u * k, d2v * k);
            CHECK(axes.major / k == doctest::Approx(glm::length(a1)).epsilon(1e-9));
            CHECK(axes.minor / k == doctest::Approx(glm::length(a2)).epsilon(1e-6));  // (a search near a flat minimum)
            CHECK(std::fabs(axes.major_u * a1.x + axes.major_v * a1.y) == doctest::Approx(glm::length(a1)).epsilon(1e-9));
        }
    }
    const double inf = std::numeric_limits<double>::infinity();
    CHECK(std::isinf(footprint_axes(inf, 0.0, 0.0, 1.0).major));
    CHECK(std::isnan(footprint_axes(std::nan(""), 0.0, 0.0, 1.0).major));
    CHECK(footprint_axes(0.0, 0.0, 0.0, 0.0).major == 0.0);
}

namespace {

// EWA at one level, from the definition in ewa.h, summed over every texel near the centre
// (not a bounding box), with Q evaluated at each texel rather than stepped. Texel indices
// go through wrap_index (checked against hand-worked values in test_wrap_and_reconstruct);
// -1 is the border colour. d1, d2: the derivative vectors in this level's texels, scaled.
// `near_edge` is set when a texel's Q lies within 1e-9 of a step of the weight table (or of
// the ellipse's edge), where the filter's stepped Q may round to the other side.
Color4 ewa_level_by_definition(const Image& level, const Sampler& s, double u, double v, double d1u, double d1v, double d2u,
                               double d2v, bool& near_edge, int reach_s = 200, int reach_t = 200, int* inside = nullptr) {
    const double a = d1v * d1v + d2v * d2v + 1.0, b = -2.0 * (d1u * d1v + d2u * d2v), c = d1u * d1u + d2u * d2u + 1.0;
    const double f = a * c - b * b / 4.0;
    const bool node = s.registration == Registration::node;
    const int w = level.width(), h = level.height();
    const double cs = node ? u * (w - 1) : u * w - 0.5, ct = node ? v * (h - 1) : v * h - 0.5;
    Color4 sum(0.0f);
    double weight_sum = 0.0;
    // (reach: beyond any ellipse the tests below make)
    for (int j = int(ct) - reach_t; j <= int(ct) + reach_t; ++j)
        for (int i = int(cs) - reach_s; i <= int(cs) + reach_s; ++i) {
            const double x = i - cs, y = j - ct;
            const double r2 = (a * x * x + b * x * y + c * y * y) / f;
            const double steps = r2 * 127.0;
            if (r2 < 1.0 + 1e-9 && std::fabs(steps - std::round(steps)) < 1e-9 * 127.0) near_edge = true;
            if (!(r2 < 1.0)) continue;
            if (inside) ++*inside;
            // The filter tabulates its weights at r^2 = k / 127 and reads the entry at or below
            // r^2 (a documented quantisation: the exact exp would differ by up to 2%, more than
            // a wrong texel would show); so does this reference.
            const double tabulated_r2 = std::floor(std::max(r2, 0.0) * 127.0) / 127.0;
            const double weight = std::exp(-2.0 * tabulated_r2) - std::exp(-2.0);
            const int column = wrap_index(s.wrap_u, i, w, node), row = wrap_index(s.wrap_v, j, h, node);
            sum += float(weight) * (column < 0 || row < 0 ? s.border : level.texel(column, row));
            weight_sum += weight;
        }
    return sum / float(weight_sum);
}

// The weight of a row at r = (its distance from the centre)^2 / A on a level one texel across
// the rows (ewa.h): what a long row's cells add up to in the cell sum, each weight read at the
// table entry at or below its Q (w_j = exp(-2 j / 127) - exp(-2) for Q in [j, j + 1) / 127).
// Along the row Q = r + y^2 (y: the distance from the chord's middle times sqrt(a)), so Q
// passes j / 127 at y = +-sqrt(j / 127 - r), and the row covers, in y,
//   W(r) = sum over j of w_j (its length with Q in [j, j + 1) / 127)
//        = sum over j >= floor(127 r) of w_j 2 (sqrt((j + 1) / 127 - r) - sqrt(max(j / 127 - r, 0))),
// worked out here term by term. 0 from r = 1 on.
double row_weight_by_definition(double r) {
    if (!(r < 1.0)) return 0.0;
    const auto w = [](int j) { return std::exp(-2.0 * j / 127.0) - std::exp(-2.0); };
    double sum = 0.0;
    for (int j = int(std::floor(r * 127.0)); j < 127; ++j)
        sum += w(j) * 2.0 * (std::sqrt((j + 1) / 127.0 - r) - std::sqrt(std::max(j / 127.0 - r, 0.0)));
    return sum;
}

// The ellipse's sum by definition on a level one texel across u (rows = true: rows j along v,
// each reading its texel in column 0) or across v (columns along u): each line k within the
// ellipse's reach of `centre` weighted by W((k - centre)^2 / spread), its texel read through
// the wrap modes (-1: the border colour). `lines` grows by the lines inside (W > 0).
Color4 lines_by_definition(const Image& level, const Sampler& s, bool rows, double centre, double spread, int& lines) {
    const bool node = s.registration == Registration::node;
    const double reach = std::sqrt(spread) + 1.0;
    glm::dvec4 sum(0.0);
    double weight_sum = 0.0;
    for (int k = int(std::floor(centre - reach)); k <= int(std::ceil(centre + reach)); ++k) {
        const double r = (k - centre) * (k - centre) / spread;
        if (!(r < 1.0)) continue;
        ++lines;
        const double weight = row_weight_by_definition(r);
        const int i = rows ? 0 : wrap_index(s.wrap_u, k, level.width(), node);
        const int j = rows ? wrap_index(s.wrap_v, k, level.height(), node) : 0;
        sum += weight * glm::dvec4(i < 0 || j < 0 ? s.border : level.texel(i, j));
        weight_sum += weight;
    }
    return Color4(sum / weight_sum);
}

}  // namespace

TEST_CASE("EWA is the Gaussian-weighted mean over its ellipse, blended between two levels") {
    // Worked out from the definition (ewa.h): the derivative vectors in base texels span the
    // footprint ellipse {d1 cos t + d2 sin t}; its principal semi-axes are its longest and
    // shortest radii, found here by searching t (the filter uses a closed form); the minor
    // axis stretched to major / max anisotropy, lambda = log2(minor), the axes scaled by 0.7
    // and taken to each level's texels, the two levels blended by lambda's fraction. Two
    // footprints are strongly sheared (d1 and d2 nearly parallel): their minor axis is much
    // shorter than either derivative vector.
    // Three textures: 8-bit power-of-two and 8-bit 48x40 (read through row addresses) and
    // float (read through Image::texel); every wrap mode, both registrations, coordinates
    // beyond [0, 1]. The footprint of 240 texels, at max anisotropy 64, is wider than the 128
    // columns the filter once kept on the stack; the last one, at max anisotropy 64 across the
    // diagonal, has a box of more cells than the filter's list holds (about 72 x 72 on level 2
    // against 2^12), which it sums and empties as it fills.
    std::mt19937_64 rng(29);
    std::vector<std::uint8_t> bytes(64 * 64 * 4), odd_bytes(48 * 40 * 4);
    for (auto& byte : bytes) byte = std::uint8_t(rng() % 256);
    for (auto& byte : odd_bytes) byte = std::uint8_t(rng() % 256);
    const MipMap textures[] = {MipMap(std::make_shared<Image>(Image::ldr(64, 64, ColorSpace::srgb, bytes))),
                               MipMap(std::make_shared<Image>(Image::ldr(48, 40, ColorSpace::srgb, odd_bytes))),
                               MipMap(std::make_shared<Image>(random_hdr(64, 64, 31)))};
    struct Footprint {
        double d1u, d1v, d2u, d2v;  // base texels
        float max_anisotropy;
    };
    const Footprint footprints[] = {{0.6, 0.2, -0.1, 0.5, 16}, {5.0, 2.0, -0.3, 1.1, 16}, {1.5, 9.0, 2.1, -0.2, 16},
                                    {30.0, 0.0, 0.0, 0.2, 16}, {0.0, 3.2, 2.3, 0.0, 16},  {240.0, 12.0, 0.0, 1.0, 64},
                                    {10.0, 0.0, 10.0, 0.1, 16}, {8.0, 6.0, 7.0, 5.5, 16},  {200.0, 200.0, 3.1, -3.1, 64}};
    const std::pair<Wrap, Wrap> wraps[] = {{Wrap::repeat, Wrap::repeat}, {Wrap::mirror, Wrap::clamp}, {Wrap::border, Wrap::mirror},
                                           {Wrap::clamp, Wrap::border}};
    int cases_exact = 0, cases_near_edge = 0;
    for (const Footprint& fp : footprints)
        for (const MipMap& mip : textures)
            for (const auto& [wrap_u, wrap_v] : wraps)
                for (Registration registration : {Registration::cell, Registration::node}) {
                    // Footprints are in the base level's lattice texels: cells, or for node
                    // registration the n - 1 spacings between its nodes (and likewise on every level).
                    const auto lattice = [&](int n) { return registration == Registration::node ? double(n - 1) : double(n); };
                    const double w = lattice(mip.base().width()), h = lattice(mip.base().height());
                    Sampler s;
                    s.max_anisotropy = fp.max_anisotropy;
                    s.wrap_u = wrap_u, s.wrap_v = wrap_v, s.registration = registration;
                    s.border = Color4(0.9f, 0.1f, 0.4f, 1.0f);
                    const auto [axis1, axis2] = principal_axes_by_search(fp.d1u, fp.d1v, fp.d2u, fp.d2v);
                    double d1u = axis1.x, d1v = axis1.y, d2u = axis2.x, d2v = axis2.y;
                    const double major = std::hypot(d1u, d1v);
                    double minor = std::hypot(d2u, d2v);
                    if (minor * fp.max_anisotropy < major) {
                        const double stretch = major / fp.max_anisotropy / minor;
                        d2u *= stretch, d2v *= stretch, minor *= stretch;
                    }
                    const double lambda = std::max(0.0, std::log2(minor));
                    const int l0 = int(lambda);
                    bool near_edge = false;
                    int inside = 0;  // the texels inside the ellipses read
                    const auto at = [&](int l, double u, double v) {
                        const Image& level = mip.level(l);
                        const double kx = 0.7 * lattice(level.width()) / w, ky = 0.7 * lattice(level.height()) / h;
                        return ewa_level_by_definition(level, s, u, v, d1u * kx, d1v * ky, d2u * kx, d2v * ky, near_edge, 200, 200,
                                                       &inside);
                    };
                    for (int k = 0; k < 2; ++k) {
                        // Coordinates in [-0.5, 1.5); in [0, 1) for node registration with repeat,
                        // whose seam node is texel n - 1 of one period and texel 0 of the next:
                        // the filter reads it as the former in every period (it removes whole
                        // periods first), this reference only in the first.
                        const bool seam = registration == Registration::node && (wrap_u == Wrap::repeat || wrap_v == Wrap::repeat);
                        const double span = seam ? 1.0 : 2.0, offset = seam ? 0.0 : -0.5;
                        const double u = double(rng() % 1000) / 1000.0 * span + offset, v = double(rng() % 1000) / 1000.0 * span + offset;
                        CAPTURE(u);
                        CAPTURE(v);
                        CAPTURE(lambda);
                        const int wrap_u_mode = int(wrap_u), wrap_v_mode = int(wrap_v);  // (CAPTURE: not a binding)
                        CAPTURE(wrap_u_mode);
                        CAPTURE(wrap_v_mode);
                        CAPTURE(int(registration));
                        CAPTURE(w);
                        near_edge = false;
                        inside = 0;
                        const Color4 a = at(l0, u, v), b = at(l0 + 1, u, v);
                        const Color4 expected = a + float(lambda - l0) * (b - a);
                        int texels = 0;
                        const Color4 got = sample_ewa(mip, s, u, v, {fp.d1u / w, fp.d1v / h, fp.d2u / w, fp.d2v / h}, texels);
                        // Float sums over up to a few thousand texels: 1e-5. A texel on a step
                        // of the table may read the neighbouring entry (up to 2% of its weight).
                        const double tolerance = near_edge ? 2e-3 : 1e-5;
                        ++(near_edge ? cases_near_edge : cases_exact);
                        for (int c = 0; c < 4; ++c) CHECK(got[c] == doctest::Approx(expected[c]).epsilon(tolerance));
                        // Every texel inside either ellipse, and no other, is read (at a whole
                        // lambda, l0's alone).
                        if (!near_edge && float(lambda - l0) != 0.0f) CHECK(texels == inside);
                    }
                }
    // Most cases are held to the tight tolerance (a texel exactly on a step is rare).
    CHECK(cases_exact > 9 * cases_near_edge);
    MESSAGE("EWA cases compared within 1e-5: ", cases_exact, ", within 2e-3: ", cases_near_edge);
}

TEST_CASE("EWA on a thin image: summed row by row across its 1-texel side, in closed form where it repeats, mirrors or clamps, as the texel beside the border where it wraps to the border") {
    // A 1x1024 image: its levels stay 1 texel wide, so a footprint thousands of texels long
    // along u is thousands of image widths long on every level. Axis-aligned footprints, so
    // their principal axes are d1 and d2 themselves; max anisotropy 64 sets the level from
    // major / 64.
    // - Border on u: every column but 0 reads the border colour. The ellipse is thousands of
    //   cells across u, and ewa.h sums each row as the border weighted by the row's weight
    //   W(r) (less column 0's cell) plus column 0's cell by its Gaussian weight: the
    //   cell-by-cell sum (the definition) within 1e-4 here, with one read a row.
    // - Repeat, mirror or clamp on u: every cell of a row reads the row's texel in column 0,
    //   and ewa.h weighs each row by W(r) (row_weight_by_definition), r = (j - ct)^2 / A on
    //   row j, A = d1v^2 + d2v^2 + 1 (here 0 + (0.7 minor)^2 + 1 in the level's texels): what
    //   a long row's cells add up to, which the last check compares with the cells' sum.
    std::mt19937_64 rng(53);
    std::vector<std::uint8_t> bytes(1024 * 4);
    for (auto& byte : bytes) byte = std::uint8_t(rng() % 256);
    const MipMap mip(std::make_shared<Image>(Image::ldr(1, 1024, ColorSpace::srgb, bytes)));
    struct Footprint {
        double major, minor;  // base texels, along u and v
        int reach;            // of the reference, along u
    };
    // The same texels in a 1024x1 image: its rows are the other's columns.
    const MipMap transposed(std::make_shared<Image>(Image::ldr(1024, 1, ColorSpace::srgb, bytes)));
    // The last footprint reads levels 9 (1x2) and 10 (1x1, the image's mean, in every row; with
    // border on v, the rows beyond it read the border).
    const Footprint footprints[] = {{2000.0, 32.0, 1500}, {6000.0, 94.0, 4300}, {12500.0, 196.0, 8900}, {20000.0, 700.0, 15000}};
    const std::pair<Wrap, Wrap> wraps[] = {{Wrap::border, Wrap::repeat}, {Wrap::repeat, Wrap::repeat}, {Wrap::clamp, Wrap::mirror},
                                           {Wrap::mirror, Wrap::border}};
    double largest_gap = 0.0;  // between the rows' sum and the cell-by-cell sum
    for (const Footprint& fp : footprints)
        for (const auto& [wrap_u, wrap_v] : wraps)
            for (const double v : {0.61, 0.004}) {
                Sampler s;
                s.max_anisotropy = 64.0f;
                s.wrap_u = wrap_u, s.wrap_v = wrap_v;
                s.border = Color4(0.9f, 0.1f, 0.4f, 1.0f);
                const double minor = std::max(fp.minor, fp.major / 64.0);  // (stretched)
                const double lambda = std::log2(minor);
                const int l0 = int(lambda);
                const double u = 0.37;
                bool near_edge = false;
                // Cell by cell (the definition's sum over the whole ellipse).
                const auto cells = [&](int l) {
                    const Image& level = mip.level(l);
                    const double kx = 0.7 * level.width() / 1.0, ky = 0.7 * level.height() / 1024.0;
                    return ewa_level_by_definition(level, s, u, v, fp.major * kx, 0.0, 0.0, minor * ky, near_edge, fp.reach, 12);
                };
                // Row by row, weighted by W(r).
                int rows_inside = 0;
                const auto rows = [&](int l) {
                    const Image& level = mip.level(l);
                    const double d2v = 0.7 * minor * level.height() / 1024.0;
                    return lines_by_definition(level, s, true, v * level.height() - 0.5, d2v * d2v + 1.0, rows_inside);
                };
                const bool by_rows = wrap_u != Wrap::border;
                const Color4 a = by_rows ? rows(l0) : cells(l0), b = by_rows ? rows(l0 + 1) : cells(l0 + 1);
                const Color4 expected = a + float(lambda - l0) * (b - a);
                int texels = 0;
                const Color4 got = sample_ewa(mip, s, u, v, {fp.major / 1.0, 0.0, 0.0, fp.minor / 1024.0}, texels);
                CAPTURE(fp.major);
                CAPTURE(v);
                const int wrap_u_mode = int(wrap_u), wrap_v_mode = int(wrap_v);  // (CAPTURE: not a binding)
                CAPTURE(wrap_u_mode);
                CAPTURE(wrap_v_mode);
                CAPTURE(texels);
                // (The rows' sum in double; the border rows within 5e-4 of the cells' float sum.)
                const double tolerance = by_rows ? (near_edge ? 2e-3 : 1e-5) : 1e-3;
                for (int c = 0; c < 4; ++c) CHECK(got[c] == doctest::Approx(expected[c]).epsilon(tolerance));
                if (!by_rows) {
                    // One read a row (column 0's texel), on each of the two levels.
                    CHECK(texels < 2 * 8);
                    continue;
                }
                // One texel read a row inside either ellipse (at a whole lambda, l0's alone).
                if (!near_edge && float(lambda - l0) != 0.0f) CHECK(texels == rows_inside);
                CHECK(texels < 2 * 8);
                // The transposed image, with the footprint and the wrap modes transposed, sums
                // its columns the same way.
                Sampler st = s;
                st.wrap_u = wrap_v, st.wrap_v = wrap_u;
                int texels_transposed = 0;
                const Color4 got_transposed =
                    sample_ewa(transposed, st, v, u, {0.0, fp.major / 1.0, fp.minor / 1024.0, 0.0}, texels_transposed);
                CHECK(texels_transposed == texels);
                for (int c = 0; c < 4; ++c) CHECK(got_transposed[c] == doctest::Approx(got[c]).epsilon(1e-6));
                // The cell-by-cell sum over the ellipse, hundreds of image widths long, whose
                // rows' sums approach W(r) (up to a factor every row shares).
                const Color4 by_cells = cells(l0) + float(lambda - l0) * (cells(l0 + 1) - cells(l0));
                for (int c = 0; c < 3; ++c) largest_gap = std::max(largest_gap, double(std::fabs(by_cells[c] - got[c])));
            }
    MESSAGE("largest difference between the rows' and the cells' sums: ", largest_gap);
    CHECK(largest_gap < 2e-4);  // (measured: 4.9e-5)
}

TEST_CASE("EWA on levels one texel across: sheared ellipses, both registrations, against rows and against cells") {
    // Footprints given by their principal axes (perpendicular, at an angle to the lattice, so
    // that the ellipse on each level is sheared: B != 0), in base texels of the registration's
    // lattice; the minor axis stretched to major / max anisotropy where shorter. On each level
    // (ewa.h), the axes times 0.7 are taken to the level's lattice; then
    // - a level one texel across u whose box is 64 cells or more across u (and shorter across
    //   v, where the level is one texel across v too) and wrap_u not border: rows j, each
    //   weighted by W(r) (row_weight_by_definition), r = (j - ct)^2 / A, A = d1v^2 + d2v^2 + 1,
    //   each row's texel in column 0;
    // - across v: the same with columns and C = d1u^2 + d2u^2 + 1;
    // - otherwise, and beside the border (which the next test works out by hand), the
    //   cell-by-cell sum (ewa_level_by_definition).
    // Each result is also compared with the cell-by-cell sum over the whole ellipse, which the
    // rows' sum approaches (a long row's cells against W(r)).
    std::mt19937_64 rng(61);
    const auto image = [&](int w, int h) {
        std::vector<std::uint8_t> bytes(std::size_t(w) * std::size_t(h) * 4);
        for (auto& byte : bytes) byte = std::uint8_t(rng() % 256);
        return MipMap(std::make_shared<Image>(Image::ldr(w, h, ColorSpace::srgb, bytes)));
    };
    // A thin image each way, and one whose coarse levels are 4x1, 2x1 and 1x1 (cell).
    const MipMap textures[] = {image(1, 1024), image(1024, 1), image(256, 64)};
    struct Footprint {
        double major, minor, angle;  // base texels; the major axis's angle to u, in degrees
        float max_anisotropy;
    };
    // The last one, at max anisotropy 64, has on the 1024x1 image's level 4 (64x1) a box about
    // 90 cells along u and 22 across v: not one texel across u, so summed cell by cell.
    const Footprint footprints[] = {{3000.0, 40.0, 30.0, 16}, {900.0, 300.0, -55.0, 16}, {200.0, 90.0, 80.0, 16},
                                    {12000.0, 100.0, 12.0, 16}, {1024.0, 1.0, 3.0, 64}};
    const std::pair<Wrap, Wrap> wraps[] = {{Wrap::repeat, Wrap::repeat}, {Wrap::mirror, Wrap::clamp}, {Wrap::clamp, Wrap::border},
                                           {Wrap::border, Wrap::mirror}};
    int compared = 0, by_rows = 0;
    double largest_gap = 0.0;  // from the cell-by-cell sums
    for (const MipMap& mip : textures)
        for (const Footprint& fp : footprints)
            for (const auto& [wrap_u, wrap_v] : wraps)
                for (const Registration registration : {Registration::cell, Registration::node})
                    for (const int place : {0, 1}) {
                        const bool node = registration == Registration::node;
                        // Coordinates outside [0, 1) too, but not for node registration with
                        // repeat, whose seam node the filter reads as node n - 1 of every period
                        // (it removes whole periods first) and this reference only in the first.
                        const bool seam = node && (wrap_u == Wrap::repeat || wrap_v == Wrap::repeat);
                        const double u = place == 0 ? 0.37 : seam ? 0.004 : -0.004, v = place == 0 ? 0.61 : seam ? 0.93 : 1.3;
                        const auto lattice = [&](int n) { return node ? double(n > 1 ? n - 1 : 1) : double(n); };
                        const double w = lattice(mip.base().width()), h = lattice(mip.base().height());
                        Sampler s;
                        s.max_anisotropy = fp.max_anisotropy;
                        s.wrap_u = wrap_u, s.wrap_v = wrap_v, s.registration = registration;
                        s.border = Color4(0.9f, 0.1f, 0.4f, 1.0f);
                        const double angle = fp.angle * M_PI / 180.0;
                        const glm::dvec2 along(std::cos(angle), std::sin(angle)), across(-std::sin(angle), std::cos(angle));
                        const double minor = std::max(fp.minor, fp.major / fp.max_anisotropy);
                        const glm::dvec2 a1 = fp.major * along, a2 = minor * across;  // (a2 stretched)
                        const double lambda = std::max(0.0, std::log2(minor));
                        const int l0 = int(lambda), last = mip.level_count() - 1;
                        if (lambda >= last) continue;  // (bilinear on the coarsest level)
                        bool near_edge = false, beside_border = false;
                        int rows_read = 0, cells_inside = 0;
                        const auto rows_or_cells = [&](int l, bool cells_only) {
                            const Image& level = mip.level(l);
                            const int lw = level.width(), lh = level.height();
                            const double kx = 0.7 * lattice(lw) / w, ky = 0.7 * lattice(lh) / h;
                            const double d1u = a1.x * kx, d1v = a1.y * ky, d2u = a2.x * kx, d2v = a2.y * ky;
                            // The box's cells across each axis, as ellipse_at_level makes it (a far
                            // centre moved by whole texels keeps the count).
                            const auto count = [](double centre, double half) {
                                return int(std::floor(centre + half)) - int(std::ceil(centre - half)) + 1;
                            };
                            const double cs = node ? u * (lw - 1) : u * lw - 0.5, ct = node ? v * (lh - 1) : v * lh - 0.5;
                            const int across_s = count(cs, std::sqrt(d1u * d1u + d2u * d2u + 1.0));
                            const int across_t = count(ct, std::sqrt(d1v * d1v + d2v * d2v + 1.0));
                            // Along one axis where the level is one texel across the other and the
                            // ellipse's middle row (column) 64 cells or more long: 2 sqrt(F / A) cells
                            // (2 sqrt(F / C)), where Q / F = A s^2 / F at t = 0 reaches 1 (the shorter
                            // way, by the box, where both are).
                            const double A = d1v * d1v + d2v * d2v + 1.0, C = d1u * d1u + d2u * d2u + 1.0;
                            const double F = A * C - (d1u * d1v + d2u * d2v) * (d1u * d1v + d2u * d2v);
                            const bool by_rows = lw == 1 && 2.0 * std::sqrt(F / A) >= 64.0;
                            const bool by_columns = lh == 1 && 2.0 * std::sqrt(F / C) >= 64.0;
                            const bool rows = by_rows && (!by_columns || across_t <= across_s), columns = !rows && by_columns;
                            // Beside the border: the cells' sum is the reference, within 4e-4.
                            const bool beside = (rows && wrap_u == Wrap::border) || (columns && wrap_v == Wrap::border);
                            beside_border = beside_border || beside;
                            if (cells_only || beside || !(rows || columns)) {
                                // (reach: the ellipse's half-widths, sqrt(C) and sqrt(A), and a few texels)
                                const int reach_s = int(std::sqrt(d1u * d1u + d2u * d2u + 1.0)) + 3;
                                const int reach_t = int(std::sqrt(d1v * d1v + d2v * d2v + 1.0)) + 3;
                                return ewa_level_by_definition(level, s, u, v, d1u, d1v, d2u, d2v, near_edge, reach_s, reach_t,
                                                               cells_only ? nullptr : &cells_inside);
                            }
                            // Rows along v (one texel across u) or columns along u.
                            const int n = rows ? lh : lw;
                            const double spread = rows ? d1v * d1v + d2v * d2v + 1.0 : d1u * d1u + d2u * d2u + 1.0;
                            const double t = rows ? v : u;
                            return lines_by_definition(level, s, rows, node ? t * (n - 1) : t * n - 0.5, spread, rows_read);
                        };
                        const float f = float(lambda - l0);
                        const Color4 a = rows_or_cells(l0, false), b = rows_or_cells(l0 + 1, false);
                        const Color4 expected = a + f * (b - a);
                        int texels = 0;
                        const Color4 got = sample_ewa(mip, s, u, v, {a1.x / w, a1.y / h, a2.x / w, a2.y / h}, texels);
                        CAPTURE(mip.base().width());
                        CAPTURE(fp.major);
                        CAPTURE(fp.angle);
                        CAPTURE(u);
                        const int wrap_u_mode = int(wrap_u), wrap_v_mode = int(wrap_v), registration_mode = int(registration);
                        CAPTURE(wrap_u_mode);
                        CAPTURE(wrap_v_mode);
                        CAPTURE(registration_mode);
                        CAPTURE(lambda);
                        // (Float sums: of up to 10^5 cells on the levels summed cell by cell, with
                        // border on their 1-texel side, 1e-3; the axes' cos and sin a rounding
                        // from the filter's.)
                        const double tolerance = near_edge ? 2e-3 : cells_inside > 4096 || beside_border ? 1e-3 : 1e-4;
                        for (int c = 0; c < 4; ++c) CHECK(got[c] == doctest::Approx(expected[c]).epsilon(tolerance));
                        ++compared;
                        if (rows_read > 0) ++by_rows;
                        // The texels read tell the sums taken: one a row, or each cell inside (beside
                        // the border, whose reads are not the cells', aside).
                        if (!beside_border && !near_edge && f != 0.0f) CHECK(texels == rows_read + cells_inside);
                        const Color4 cells = rows_or_cells(l0, true) + f * (rows_or_cells(l0 + 1, true) - rows_or_cells(l0, true));
                        for (int c = 0; c < 3; ++c) largest_gap = std::max(largest_gap, double(std::fabs(cells[c] - got[c])));
                    }
    MESSAGE("lookups compared: ", compared, ", on levels summed by rows: ", by_rows, "; largest difference from the cells' sum: ",
            largest_gap);
    CHECK(by_rows > 80);
    // W(r) is what a long row's cells add up to: rows of 64 cells and more come close
    // (measured: 5.3e-5, where rows of texels meet rows of border of contrast 0.9).
    CHECK(largest_gap < 2e-4);
}

TEST_CASE("EWA on a 1x1 level whose box is 64 cells or more both ways sums along the shorter way") {
    // A 1x16384 image, a footprint 10^6 base texels long along v (in base texels:
    // u in image widths, v in texels), max anisotropy 64: the minor axis stretched to 15625,
    // lambda = log2(15625) = 13.93, levels 13 (1x2) and 14 (1x1). On level 14 the ellipse is
    // about 22000 cells across u and 85 across v, its middle row and column both 64 cells or
    // more: rows along v (the box's shorter side), one read a row (each row's texel: the
    // image's mean); on level 13, about 22000 by 170. So a few hundred reads (columns would be
    // tens of thousands), and on each level the rows weighted by W(r), r = (j - ct)^2 / A
    // (row_weight_by_definition).
    std::mt19937_64 rng(71);
    std::vector<std::uint8_t> bytes(16384 * 4);
    for (auto& byte : bytes) byte = std::uint8_t(rng() % 256);
    const MipMap mip(std::make_shared<Image>(Image::ldr(1, 16384, ColorSpace::srgb, bytes)));
    Sampler s;
    s.max_anisotropy = 64.0f;
    const double angle = 90.0 * M_PI / 180.0, major = 1e6, minor = major / 64.0;
    const glm::dvec2 a1 = major * glm::dvec2(std::cos(angle), std::sin(angle)), a2 = minor * glm::dvec2(-std::sin(angle), std::cos(angle));
    const double lambda = std::log2(minor), u = 0.3, v = 0.45;
    const int l0 = int(lambda);
    REQUIRE(l0 == 13);
    int rows_inside = 0;
    const auto rows = [&](int l) {
        const Image& level = mip.level(l);
        const double ky = 0.7 * level.height() / 16384.0, d1v = a1.y * ky, d2v = a2.y * ky;
        return lines_by_definition(level, s, true, v * level.height() - 0.5, d1v * d1v + d2v * d2v + 1.0, rows_inside);
    };
    const Color4 expected = rows(l0) + float(lambda - l0) * (rows(l0 + 1) - rows(l0));
    int texels = 0;
    const Color4 got = sample_ewa(mip, s, u, v, {a1.x, a1.y / 16384.0, a2.x, a2.y / 16384.0}, texels);
    CAPTURE(texels);
    for (int c = 0; c < 4; ++c) CHECK(got[c] == doctest::Approx(expected[c]).epsilon(1e-5));
    CHECK(texels < 400);
}

TEST_CASE("EWA with no footprint reads the base level bilinearly, with one beyond measure the coarsest level") {
    std::mt19937_64 rng(73);
    std::vector<std::uint8_t> bytes(16 * 8 * 4);
    for (auto& byte : bytes) byte = std::uint8_t(rng() % 256);
    const MipMap mip(std::make_shared<Image>(Image::ldr(16, 8, ColorSpace::srgb, bytes)));
    const double inf = std::numeric_limits<double>::infinity();
    Sampler s;
    for (const auto& [u, v] : {std::pair{0.31, 0.77}, std::pair{-1.2, 0.05}}) {
        int texels = 0;
        const Color4 none = sample_ewa(mip, s, u, v, {0.0, 0.0, 0.0, 0.0}, texels);
        CHECK(texels == 4);
        const Color4 base = sample_bilinear(mip.base(), s, u, v);
        const Color4 beyond = sample_ewa(mip, s, u, v, {inf, 0.0, 0.0, 1.0}, texels);
        const Color4 coarsest = sample_bilinear(mip.level(mip.level_count() - 1), s, u, v);
        for (int c = 0; c < 4; ++c) {
            CHECK(none[c] == base[c]);
            CHECK(beyond[c] == coarsest[c]);
        }
        CHECK(base != coarsest);  // (a texture that is not one colour: the two differ)
    }
}

TEST_CASE("EWA beside the border: a 1-texel side with border wrap under a wide ellipse, row by row and column by column, worked out by hand") {
    // ewa.h: on a level one texel across u with border wrap, under an ellipse whose middle row
    // is 64 cells or more long, each row j of the ellipse has one cell (s = 0) on the row's texel and the rest
    // on the border colour; the row's weights add up to W(r_j) / sqrt(a) cells (what a long
    // row's cells add up to: row_weight_by_definition; r_j = (j - ct)^2 / A, a = A / F), and
    // the cell's weight is the Gaussian's at its own Q. So the mean is
    //   border + sum_j w0_j (texel_j - border) / sum_j W(r_j) / sqrt(a),
    // worked out here from the footprint. A 1x64 image, lambda = 2 exactly (a minor axis of 4
    // base texels), level 2 (1x16); the ellipse sheared (its major axis at 3 degrees to u),
    // its middle row about 77 cells long. The same transposed: a 64x1 image with border on v, summed
    // column by column (C, c and the cell t = 0 in place of A, a and s = 0). The centres put
    // the texel's cell near the middle (a texel's share of a few per cent) and several cells
    // off it (where a wrong sign of the shear term would show).
    std::mt19937_64 rng(67);
    std::vector<std::uint8_t> bytes(64 * 4);
    for (auto& byte : bytes) byte = std::uint8_t(rng() % 256);
    const MipMap tall(std::make_shared<Image>(Image::ldr(1, 64, ColorSpace::srgb, bytes)));
    const MipMap wide(std::make_shared<Image>(Image::ldr(64, 1, ColorSpace::srgb, bytes)));
    int off_middle = 0;
    for (const bool transposed : {false, true})
        for (const Registration registration : {Registration::cell, Registration::node})
            for (const double across : {0.4, 0.9, -0.3, -2.3})  // u (transposed: v), on the 1-texel side
                for (const double along : {0.2, 0.77}) {
                    const bool node = registration == Registration::node;
                    const MipMap& mip = transposed ? wide : tall;
                    Sampler s;
                    s.wrap_u = transposed ? Wrap::repeat : Wrap::border, s.wrap_v = transposed ? Wrap::border : Wrap::repeat;
                    s.registration = registration;
                    s.border = Color4(0.9f, 0.1f, 0.4f, 1.0f);
                    const double n = node ? 63.0 : 64.0;  // the long side's base lattice (the other: 1 either way)
                    const double angle = 3.0 * M_PI / 180.0;
                    // (p, q): components across the 1-texel side and along the long one.
                    const glm::dvec2 p1 = 60.0 * glm::dvec2(std::cos(angle), std::sin(angle)), p2 = 4.0 * glm::dvec2(-std::sin(angle), std::cos(angle));
                    const Image& level = mip.level(2);
                    REQUIRE((transposed ? level.width() : level.height()) == 16);
                    const double k = 0.7 * (node ? 15.0 : 16.0) / n;
                    const double d1p = 0.7 * p1.x, d1q = k * p1.y, d2p = 0.7 * p2.x, d2q = k * p2.y;
                    // In (p, q) the form is that of (s, t) for the tall image: Q ~ P p^2 + R p q + S q^2,
                    // P = d1q^2 + d2q^2 + 1 (the coefficient of p^2), S = d1p^2 + d2p^2 + 1.
                    const double P = d1q * d1q + d2q * d2q + 1.0, R = -2.0 * (d1p * d1q + d2p * d2q), S = d1p * d1p + d2p * d2p + 1.0;
                    const double F = P * S - R * R / 4.0, pn = P / F, rn = R / F, sn = S / F;
                    REQUIRE(2.0 * std::sqrt(F / P) > 70.0);  // (the middle row, 2 / sqrt(pn) cells: 64 or more)
                    const double cp = node ? 0.0 : across - 0.5, cq = node ? along * 15.0 : along * 16.0 - 0.5;
                    glm::dvec4 share(0.0);
                    double row_sum = 0.0;
                    bool near_edge = false;
                    for (int j = int(std::ceil(cq - std::sqrt(P))); j <= int(std::floor(cq + std::sqrt(P))); ++j) {
                        const double x = j - cq, r = x * x / P, m = row_weight_by_definition(r);
                        if (!(r < 1.0)) continue;
                        row_sum += m / std::sqrt(pn);
                        const double q0 = pn * cp * cp - rn * cp * x + sn * x * x, steps = q0 * 127.0;
                        if (std::fabs(steps - std::round(steps)) < 1e-9 * 127.0) near_edge = true;
                        if (!(q0 < 1.0)) continue;
                        const double w0 = std::exp(-2.0 * std::floor(steps) / 127.0) - std::exp(-2.0);
                        const int texel = wrap_index(Wrap::repeat, j, 16, node);
                        share += w0 * (glm::dvec4(transposed ? level.texel(texel, 0) : level.texel(0, texel)) - glm::dvec4(s.border));
                    }
                    const glm::dvec4 expected = glm::dvec4(s.border) + share / row_sum;
                    const double u = transposed ? along : across, v = transposed ? across : along;
                    const UVDerivatives d = transposed ? UVDerivatives{p1.y / n, p1.x, p2.y / n, p2.x} : UVDerivatives{p1.x, p1.y / n, p2.x, p2.y / n};
                    int texels = 0;
                    const Color4 got = sample_ewa(mip, s, u, v, d, texels);
                    CAPTURE(transposed);
                    CAPTURE(across);
                    CAPTURE(along);
                    CAPTURE(int(registration));
                    CAPTURE(share.x / row_sum);
                    for (int c = 0; c < 3; ++c) CHECK(got[c] == doctest::Approx(expected[c]).epsilon(near_edge ? 1e-3 : 1e-6));
                    // The texel's share is a few per cent where its cell is inside the ellipse
                    // near its middle (0.4 in cell registration; node registration's one node at 0).
                    if (across == 0.4 || node) CHECK(std::fabs(share.x / row_sum) > 0.005);
                    if (across == -2.3 && !node && share != glm::dvec4(0.0)) ++off_middle;
                    CHECK(texels < 10);  // (one read a row; about 3 rows)
                }
    CHECK(off_middle >= 2);  // (the cell 2.8 off the middle is inside the ellipse somewhere)

    // At 10 degrees the ellipse is more sheared: its box is still about 83 cells across u, but
    // its middle row only 2 sqrt(F / A) = 46 long, so it is summed cell by cell.
    Sampler s;
    s.wrap_u = Wrap::border;
    s.border = Color4(0.9f, 0.1f, 0.4f, 1.0f);
    const double angle = 10.0 * M_PI / 180.0;
    const glm::dvec2 a1 = 60.0 * glm::dvec2(std::cos(angle), std::sin(angle)), a2 = 4.0 * glm::dvec2(-std::sin(angle), std::cos(angle));
    const double d1u = 0.7 * a1.x, d1v = 0.7 * 16.0 / 64.0 * a1.y, d2u = 0.7 * a2.x, d2v = 0.7 * 16.0 / 64.0 * a2.y;
    const double A = d1v * d1v + d2v * d2v + 1.0, C = d1u * d1u + d2u * d2u + 1.0;
    const double F = A * C - (d1u * d1v + d2u * d2v) * (d1u * d1v + d2u * d2v);
    REQUIRE(2.0 * std::sqrt(C) > 80.0);
    REQUIRE(2.0 * std::sqrt(F / A) < 50.0);
    bool near_edge = false;
    int inside = 0;
    const Color4 expected = ewa_level_by_definition(tall.level(2), s, 0.4, 0.2, d1u, d1v, d2u, d2v, near_edge, 60, 10, &inside);
    int texels = 0;
    const Color4 got = sample_ewa(tall, s, 0.4, 0.2, {a1.x, a1.y / 64.0, a2.x, a2.y / 64.0}, texels);
    for (int c = 0; c < 3; ++c) CHECK(got[c] == doctest::Approx(expected[c]).epsilon(near_edge ? 2e-3 : 1e-5));
    if (!near_edge) CHECK(texels == inside);
    CHECK(texels > 64);
}

TEST_CASE("EWA reads the same values from an 8-bit image's bytes as from its decoded copy") {
    // A 2048x2048 image has no decoded copy (more than Image::max_decoded_texels), a 1024x1024
    // one has: EWA reads the first level's texels from the bytes and the decode table, the
    // second's from the copy. The large image is the small one four times over (2 x 2), so
    // each of its mip levels is the small one's level four times over, and at (u/2, v/2),
    // with derivatives halved, it reads the same texels at the same lattice positions (the
    // halvings are exact) with the same weights: the two results must be the same bits.
    std::mt19937_64 rng(41);
    const int n = 1024;
    std::vector<std::uint8_t> small_bytes(std::size_t(n) * n * 4), large_bytes(std::size_t(4) * n * n * 4);
    for (auto& byte : small_bytes) byte = std::uint8_t(rng() % 256);
    for (int j = 0; j < 2 * n; ++j)
        for (int i = 0; i < 2 * n; ++i)
            std::memcpy(&large_bytes[(std::size_t(j) * 2 * n + std::size_t(i)) * 4],
                        &small_bytes[(std::size_t(j % n) * n + std::size_t(i % n)) * 4], 4);
    const auto small_image = std::make_shared<Image>(Image::ldr(n, n, ColorSpace::srgb, small_bytes));
    const auto large_image = std::make_shared<Image>(Image::ldr(2 * n, 2 * n, ColorSpace::srgb, large_bytes));
    REQUIRE(small_image->decoded_texels() != nullptr);
    REQUIRE(large_image->decoded_texels() == nullptr);
    const MipMap small(small_image), large(large_image);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int compared = 0, from_base = 0;
    for (float max_anisotropy : {4.0f, 16.0f, 64.0f}) {
        Sampler s;
        s.max_anisotropy = max_anisotropy;
        for (int k = 0; k < 600; ++k) {
            // Footprints from a third of a texel to 2^9 texels long, in any direction and shape.
            const double length = std::exp2(unit(rng) * 10.6 - 1.6), angle = unit(rng) * 6.283185307179586;
            const double ratio = std::exp2(-unit(rng) * 8.0), turn = (unit(rng) - 0.5) * 3.0;
            const double d1u = length * std::cos(angle) / n, d1v = length * std::sin(angle) / n;
            const double d2u = ratio * length * std::cos(angle + turn) / n, d2v = ratio * length * std::sin(angle + turn) / n;
            const double u = unit(rng) * 3.0 - 1.0, v = unit(rng) * 3.0 - 1.0;
            int small_texels = 0, large_texels = 0;
            const Color4 expected = sample_ewa(small, s, u, v, {d1u, d1v, d2u, d2v}, small_texels);
            const Color4 got = sample_ewa(large, s, u / 2.0, v / 2.0, {d1u / 2.0, d1v / 2.0, d2u / 2.0, d2v / 2.0}, large_texels);
            CAPTURE(u);
            CAPTURE(v);
            CAPTURE(length);
            CAPTURE(ratio);
            CHECK(std::memcmp(&got, &expected, sizeof got) == 0);
            CHECK(large_texels == small_texels);
            ++compared;
            // The base level is read when the ellipse's minor semi-axis (stretched to at least
            // major / max anisotropy) is under two texels: the singular values of [d1 d2].
            const double p = (d1u * d1u + d2u * d2u) * n * n, q = (d1v * d1v + d2v * d2v) * n * n;
            const double r = (d1u * d1v + d2u * d2v) * n * n;
            const double root = std::sqrt((p - q) * (p - q) / 4.0 + r * r);
            const double major = std::sqrt((p + q) / 2.0 + root), minor = std::sqrt(std::max((p + q) / 2.0 - root, 0.0));
            from_base += std::max(minor, major / max_anisotropy) < 2.0 ? 1 : 0;
        }
    }
    CHECK(from_base > compared / 10);  // enough of them read the large image's bytes
    MESSAGE("EWA lookups compared bit for bit: ", compared, ", reading the base level: ", from_base);
}

TEST_CASE("node registration measures footprints in spacings between nodes: one per pixel is level 0") {
    // A 3x3 float image, 1 at the centre node and 0 elsewhere; node registration puts the
    // nodes at u = 0, 1/2, 1, so derivatives of 1/2 per pixel are one node spacing: level of
    // detail 0 (log2(3 x 1/2) = 0.585 if measured in n texels, which reads level 1 (2x2) or
    // blends it in). Worked by hand at the centre node (u, v) = (1/2, 1/2):
    //  - nearest-mip-nearest, bilinear-mip-nearest, trilinear (level 0 alone) and anisotropic
    //    (a round footprint: one probe at lambda 0) read the centre node: 1;
    //  - EWA at lambda 0 reads level 0 alone: the ellipse 0.7 spacings round, plus the unit
    //    reconstruction term, gives Q = r^2 / 1.49; the centre (Q = 0, weight 1 - e^-2) and its
    //    four neighbours (Q = 1/1.49 = 0.67114, tabulated at 85/127: weight
    //    e^(-2 x 85/127) - e^-2 = 0.126882) are inside, the diagonals (Q = 1.342) are not:
    //    0.864665 / (0.864665 + 4 x 0.126882) = 0.630134, from 5 texels.
    std::vector<float> rgba(3 * 3 * 4, 0.0f);
    for (int k = 0; k < 9; ++k) rgba[std::size_t(k) * 4 + 3] = 1.0f;
    for (int c = 0; c < 3; ++c) rgba[4 * 4 + std::size_t(c)] = 1.0f;
    Texture t;
    t.image = std::make_shared<Image>(Image::hdr(3, 3, rgba));
    t.sampler.registration = Registration::node;
    t.sampler.wrap_u = t.sampler.wrap_v = Wrap::clamp;
    t.mipmap = std::make_shared<MipMap>(t.image, t.sampler);
    const UVDerivatives one_spacing{0.5, 0.0, 0.0, 0.5};
    for (Filter f : {Filter::nearest_mip_nearest, Filter::bilinear_mip_nearest, Filter::trilinear, Filter::anisotropic}) {
        CAPTURE(std::string(filter_name(f)));
        t.sampler.filter = f;
        std::uint64_t texels = 0;
        CHECK(lookup_footprint(t, 0.5, 0.5, one_spacing, texels).x == doctest::Approx(1.0).epsilon(1e-6));
    }
    t.sampler.filter = Filter::ewa;
    std::uint64_t texels = 0;
    CHECK(lookup_footprint(t, 0.5, 0.5, one_spacing, texels).x == doctest::Approx(0.630134).epsilon(1e-5));
    CHECK(texels == 5);
    CHECK(lattice_texels(Registration::node, 3) == 2);
    CHECK(lattice_texels(Registration::node, 1) == 1);
    CHECK(lattice_texels(Registration::cell, 3) == 3);
}

TEST_CASE("the texels counted for anisotropic filtering are those its probes read: 4 on one level, 8 on two") {
    // A 256 x 256 texture has levels 0 to 8. Footprints along u and v, in base texels:
    //  - 1 x 1/4: N = 4 probes at lambda = log2(1 / 4) = -2, bilinear on the base: 4 x 4 = 16;
    //  - 64 x 8: N = 8 probes at lambda = log2(64 / 8) = 3, between levels 0 and 8: 8 x 8 = 64;
    //  - 4096 x 2048: N = 2 probes at lambda = 11, beyond level 8, on the coarsest: 2 x 4 = 8;
    //  - 60 x 2 with max_anisotropy 16: N = 16 at lambda = log2(60 / 16) = 1.9: 16 x 8 = 128;
    //  - no footprint: one bilinear lookup on the base: 4.
    // (texr explain says how many texel reads its value came from; --stats sums them.)
    Texture t;
    t.image = std::make_shared<Image>(constant_ldr(256, 256, 90));
    t.sampler.filter = Filter::anisotropic;
    t.mipmap = std::make_shared<MipMap>(t.image);
    const double n = 256.0;
    const std::pair<UVDerivatives, std::uint64_t> cases[] = {
        {{1.0 / n, 0.0, 0.0, 0.25 / n}, 16}, {{64.0 / n, 0.0, 0.0, 8.0 / n}, 64}, {{4096.0 / n, 0.0, 0.0, 2048.0 / n}, 8},
        {{0.0, 60.0 / n, 2.0 / n, 0.0}, 128}, {{0.0, 0.0, 0.0, 0.0}, 4}};
    for (const auto& case_ : cases) {
        const UVDerivatives& d = case_.first;  // (CAPTURE: not a structured binding)
        const std::uint64_t expected = case_.second;
        CAPTURE(d.dudx * n);
        std::uint64_t texels = 0;
        lookup_footprint(t, 0.3, 0.6, d, texels);
        CHECK(texels == expected);
    }
}

// Boundaries that a mutation test of mipmap.cpp, minify.{h,cpp} and lookup.cpp found
// unchecked: each below fails when its comparison, constant or branch is changed.
namespace {
std::shared_ptr<const Image> hdr_image(int w, int h, const std::vector<float>& values) {
    return std::make_shared<const Image>(testing::hdr_image(w, h, values));
}
}  // namespace

TEST_CASE("a mip level of 8-bit data rounds each mean half up: bytes k and k + 1 give k + 1") {
    // A linear (data) 510 x 1 image of pairs (k, k + 1): level 1 is 255 x 1, texel k the mean
    // k + 1/2 of its pair, stored as a byte rounded half up (lround): k + 1.
    std::vector<std::uint8_t> bytes(510 * 4);
    for (int k = 0; k < 255; ++k)
        for (int c = 0; c < 4; ++c) bytes[std::size_t(2 * k) * 4 + c] = std::uint8_t(k), bytes[std::size_t(2 * k + 1) * 4 + c] = std::uint8_t(k + 1);
    const Image level1 = downsample(Image::ldr(510, 1, ColorSpace::linear, bytes));
    REQUIRE(level1.width() == 255);
    int wrong = 0;
    for (int k = 0; k < 255; ++k) wrong += std::lround(level1.texel(k, 0).w * 255.0f) != k + 1;
    CHECK(wrong == 0);
}

TEST_CASE("footprint axes of 1e308 texels keep their length") {
    // The vectors are scaled by a power of two before squaring; at 1e308 that power is 2^-1023,
    // which must not be taken as 0 (2^-1023 is a subnormal double, and the scale is clamped
    // to 2^-1022): both axes stay 1e308.
    const FootprintAxes a = footprint_axes(1e308, 0.0, 0.0, 1e308);
    CHECK(a.major == doctest::Approx(1e308));
    CHECK(a.minor == doctest::Approx(1e308));
    const FootprintAxes b = footprint_axes(1.7e308, 0.0, 0.0, 1e300);
    CHECK(b.major == doctest::Approx(1.7e308));
    CHECK(b.minor == doctest::Approx(1e300));
}

TEST_CASE("anisotropic filtering of an infinite footprint reads the 1x1 level, and a footprint of ratio 2 takes 2 probes") {
    // A 2 x 2 HDR texture [0, 1; 1, 1]: its 1 x 1 level is the mean, 0.75. A footprint
    // infinitely long is wider than the whole texture: that level, not the base's texel 0.
    const MipMap mip(hdr_image(2, 2, {0.0f, 1.0f, 1.0f, 1.0f}));
    Sampler s;
    s.filter = Filter::anisotropic;
    int probes = 0;
    const Color4 far = sample_anisotropic(mip, s, 0.25, 0.25, UVDerivatives{HUGE_VAL, 0.0, 0.0, 1e-3}, probes, nullptr);
    CHECK(far.x == doctest::Approx(0.75));
    // Axes 2 and 1 texels turned by small angles: ratio 2 up to rounding (2.0000000000000004
    // at 0.0008 rad), which is N = ceil(2) = 2 probes, not 3.
    int not_two = 0;
    for (int k = 0; k < 20000; ++k) {
        const double a = k * 1e-4, c = std::cos(a), sn = std::sin(a);
        const FootprintAxes ax = footprint_axes(2.0 * c, 2.0 * sn, -sn, c);
        not_two += anisotropic_probes(ax.major, ax.minor, 16.0f).count != 2;
    }
    CHECK(not_two == 0);
}

TEST_CASE("trilinear at the ends of the pyramid reads one level, exactly, and blends HDR levels far apart without overflow") {
    // A 4 x 1 HDR row [-3.4e38, 3.4e38, 3.4e38, 3.4e38] (repeat); level 1 is [0, 3.4e38].
    // At u = 1/8, level 0's bilinear x = 0 is texel 0, -3.4e38; level 1's x = -1/4 lies
    // between its texel 1 (a period back) and texel 0, 0.75 of the way to texel 0:
    // 0.25 (3.4e38) + 0.75 (0) = 8.5e37. Their difference, 4.25e38, overflows a float.
    // At lambda 0 trilinear is level 0 alone, exactly -3.4e38 (blending in level 1 with a
    // weight of 0 would make 0 x inf = NaN); at lambda 1/2 it is
    // -3.4e38 + (4.25e38) / 2 = -1.275e38 (the float blend gave inf).
    const MipMap mip(hdr_image(4, 1, {-3.4e38f, 3.4e38f, 3.4e38f, 3.4e38f}));
    Sampler s;
    s.filter = Filter::trilinear;
    CHECK(sample_trilinear(mip, s, 0.125, 0.5, 0.0).x == -3.4e38f);
    const Color4 mid = sample_trilinear(mip, s, 0.125, 0.5, 0.5);
    CHECK(std::isfinite(mid.x));
    CHECK(mid.x == doctest::Approx(-1.275e38).epsilon(1e-6));
#if defined(__SSE2__)
    // The lanes' choice of levels: a lambda at the last level (or beyond, or at 0) is an end
    // of the pyramid, l0 = -1, as trilinear_over reads it (one level alone).
    for (const double lambda : {3.0, 0.0, 3.5}) {
        int l0 = 7;
        float fraction = 0.0f;
        trilinear_levels_lanes(&lambda, 1, 3, &l0, &fraction);
        CAPTURE(lambda);
        CHECK(l0 == -1);
    }
    // Two at a time (SSE2's lanes): the ends in either lane.
    const double pairs[3][2] = {{3.0, 2.5}, {2.5, 0.0}, {0.0, 3.5}};
    const int expected[3][2] = {{-1, 2}, {2, -1}, {-1, -1}};
    for (int p = 0; p < 3; ++p) {
        int l0s[2] = {7, 7};
        float fractions[2];
        trilinear_levels_lanes(pairs[p], 2, 3, l0s, fractions);
        CAPTURE(p);
        CHECK(l0s[0] == expected[p][0]);
        CHECK(l0s[1] == expected[p][1]);
        for (int k = 0; k < 2; ++k)
            if (l0s[k] == 2) CHECK(fractions[k] == 0.5f);
    }
#endif
}

TEST_CASE("bicubic lookups count the 16 texels they read") {
    Texture t;
    t.image = std::make_shared<Image>(constant_ldr(8, 8, 90));
    t.sampler.filter = Filter::bicubic;
    t.mipmap = std::make_shared<MipMap>(t.image);
    std::uint64_t texels = 0;
    lookup_footprint(t, 0.3, 0.6, UVDerivatives{0.01, 0.0, 0.0, 0.01}, texels);
    CHECK(texels == 16);
}

TEST_CASE("anisotropic probes beyond 1e15 texels read texel 0 on the short path, as on the general path") {
    // An 8-bit 4 x 4 texture whose columns are [0, 85, 170, 255] (repeat, power-of-two sides:
    // the short path where the probes stay within its limit). Beyond 1e15 texels a
    // coordinate carries no fraction and reads texel 0 (wrap.h), on either path.
    std::vector<std::uint8_t> bytes;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            for (int c = 0; c < 4; ++c) bytes.push_back(c == 3 ? 255 : std::uint8_t(85 * i));
    const MipMap mip(std::make_shared<const Image>(Image::ldr(4, 4, ColorSpace::linear, bytes)));
    Sampler s;
    s.filter = Filter::anisotropic;
    int probes = 0;
    // One probe (a tiny footprint) at u 4 = -(1e15 - 0.25): its bilinear x = -1e15 - 0.25.
    const Color4 one = sample_anisotropic(mip, s, -249999999999999.9375, 0.375, UVDerivatives{1e-4, 0.0, 0.0, 1e-4}, probes, nullptr);
    CHECK(probes == 1);
    CHECK(one.x == 0.0f);
    // 16 probes along u over 16 texels (lambda 0) around u 4 = -(1e15 - 4): probe k lies at
    // u 4 = -(1e15 - 4) + 16 ((k + 1/2) / 16 - 1/2), its bilinear x = that - 1/2 =
    // -1e15 + k - 4. Probes k = 0..4 (x <= -1e15) read 0; k = 5..15 lie on whole texels
    // x = -1e15 + j, j = 1..11, which read texel j mod 4 (1e15 is a multiple of 4): 85, 170,
    // 255, 0 and so on, 3 x 510 = 1530 in all; 1530 / 16 / 255 = 0.375 (linear data).
    const Color4 sixteen = sample_anisotropic(mip, s, -249999999999999.0, 0.375, UVDerivatives{4.0, 0.0, 0.0, 0.25}, probes, nullptr);
    CHECK(probes == 16);
    CHECK(sixteen.x == doctest::Approx(0.375).epsilon(1e-6));
}

TEST_CASE("every filter of an HDR image with texels near the float maximum returns a finite value between the texels") {
    // Each filter's value is a weighted mean of texels (and the border colour) with weights
    // that are not negative (bicubic as the B-spline): finite, and between the smallest and
    // largest of them, whatever the float sums of such texels overflow to on the way
    // (-3.4e38 beside 3.4e38, or texels at the float maximum itself). Random 1..6 x 1..6
    // images of such texels, every wrap pair and registration, random footprints.
    std::mt19937_64 rng(31);
    const auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    const auto pick = [&](int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); };
    const Wrap wraps[4] = {Wrap::repeat, Wrap::mirror, Wrap::clamp, Wrap::border};
    int wrong[8] = {}, lookups = 0;
    for (int round = 0; round < 6000; ++round) {
        const float big = round % 2 == 0 ? 3.4e38f : std::numeric_limits<float>::max();
        const float values[5] = {-big, big, 0.0f, big / 2, -big / 2};
        Sampler s;
        s.registration = pick(0, 1) ? Registration::node : Registration::cell;
        const int w = std::max(pick(1, 6), s.registration == Registration::node ? 2 : 1);
        const int h = std::max(pick(1, 6), s.registration == Registration::node ? 2 : 1);
        s.wrap_u = wraps[pick(0, 3)], s.wrap_v = wraps[pick(0, 3)];
        const float border = values[pick(0, 4)];
        s.border = Color4(border, border, border, 1.0f);
        s.cubic_b = 1.0f, s.cubic_c = 0.0f;  // the B-spline: no negative weights
        std::vector<float> texels;
        float lo = border, hi = border;
        for (int k = 0; k < w * h; ++k) {
            const float t = pick(0, 4) == 0 ? values[pick(2, 4)] : values[pick(0, 1)];
            lo = std::min(lo, t), hi = std::max(hi, t);
            texels.push_back(t);
        }
        Texture tex;
        tex.image = hdr_image(w, h, texels);
        tex.mipmap = std::make_shared<MipMap>(tex.image, s);
        for (int f = 0; f < 8; ++f) {
            tex.sampler = s;
            tex.sampler.filter = Filter(f);
            tex.sampler.max_anisotropy = float(pick(1, 16));
            const double scale = std::pow(2.0, uniform(-4.0, 3.0)) / std::max(w, h);
            const UVDerivatives d{scale * uniform(-1, 1), scale * uniform(-1, 1), scale * uniform(-1, 1), scale * uniform(-1, 1)};
            std::uint64_t read = 0;
            const float x = lookup(tex, uniform(-0.5, 1.5), uniform(-0.5, 1.5), d, read).x;
            const float slack = 1e-6f;
            wrong[f] += !(std::isfinite(x) && x >= lo - slack * std::fabs(lo) && x <= hi + slack * std::fabs(hi));
            ++lookups;
        }
    }
    for (int f = 0; f < 8; ++f) {
        const std::string name = filter_name(Filter(f));
        CAPTURE(name);
        CHECK(wrong[f] == 0);
    }
    MESSAGE(lookups << " lookups");
}

TEST_CASE("EWA with clamp far outside the image reads the nearer edge, and a footprint as wide as the pyramid reads its top level") {
    // A 2 x 2 HDR texture whose left column is 0.25 and right column 0.75, clamped: a lookup
    // 1e15 texture widths to the right reads the right column, to the left the left one.
    const MipMap columns(hdr_image(2, 2, {0.25f, 0.75f, 0.25f, 0.75f}));
    Sampler clamp;
    clamp.filter = Filter::ewa, clamp.wrap_u = clamp.wrap_v = Wrap::clamp;
    int texels = 0;
    const UVDerivatives small{0.5, 0.0, 0.0, 0.5};
    CHECK(sample_ewa(columns, clamp, 1e15, 0.5, small, texels).x == doctest::Approx(0.75));
    CHECK(sample_ewa(columns, clamp, -1e15, 0.5, small, texels).x == doctest::Approx(0.25));
    // A 2 x 2 texture of 1s with a border of 0: a footprint of 2 texels (d = 1 texture width
    // a pixel) has lambda = log2(2) = 1, the last level, which is read as it is (bilinear at
    // its one texel's centre: 1), not averaged over an ellipse that takes in the border.
    const MipMap ones(hdr_image(2, 2, {1.0f, 1.0f, 1.0f, 1.0f}));
    Sampler border;
    border.filter = Filter::ewa, border.wrap_u = border.wrap_v = Wrap::border;
    CHECK(sample_ewa(ones, border, 0.5, 0.5, UVDerivatives{1.0, 0.0, 0.0, 1.0}, texels).x == 1.0f);
}
