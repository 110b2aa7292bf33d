// The benchmark's error metrics against hand-worked values.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "texr/bench/metrics.h"
#include "texr/bench/targets.h"

using namespace texr;

namespace {
FrameBytes noise(int w, int h, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    FrameBytes f{w, h, std::vector<std::uint8_t>(std::size_t(w) * std::size_t(h) * 3)};
    for (auto& b : f.rgb) b = std::uint8_t(20 + rng() % 200);
    return f;
}
}  // namespace

TEST_CASE("PSNR: identical is infinite, and an error of one level everywhere is 10 log10(255^2) dB") {
    const FrameBytes a = noise(16, 8, 1);
    const std::vector<bool> all(16 * 8, true);
    CHECK(std::isinf(psnr(a, a, all)));
    FrameBytes b = a;
    for (auto& v : b.rgb) v = std::uint8_t(v + 1);
    CHECK(psnr(a, b, all) == doctest::Approx(10.0 * std::log10(255.0 * 255.0)));  // 48.13 dB
    // Only masked pixels count: a wrong pixel outside the mask changes nothing.
    FrameBytes c = a;
    c.rgb[0] = std::uint8_t(c.rgb[0] + 100);
    std::vector<bool> mask = all;
    mask[0] = false;
    CHECK(std::isinf(psnr(a, c, mask)));
    // No pixel masked: nothing compared, no score (it read +infinity, and SSIM 1).
    const std::vector<bool> none(16 * 8, false);
    CHECK(std::isnan(psnr(a, b, none)));
    CHECK(std::isnan(ssim(a, b, none)));
}

TEST_CASE("SSIM: 1 for identical frames, lower for noise, symmetric") {
    const FrameBytes a = noise(24, 20, 2), b = noise(24, 20, 3);
    const std::vector<bool> all(24 * 20, true);
    CHECK(ssim(a, a, all) == doctest::Approx(1.0));
    const double s = ssim(a, b, all);
    CHECK(s < 0.2);  // independent noise: no structure in common
    CHECK(s == doctest::Approx(ssim(b, a, all)));
}

TEST_CASE("bench targets: met at the threshold, missed past it or on NaN, counted in the table") {
    using namespace texr::bench;
    CHECK(at_least("filters", "g", "c", 120.0, 120.0, "Mpx/s", 1).met);
    CHECK_FALSE(at_least("filters", "g", "c", 119.95, 120.0, "Mpx/s", 1).met);
    CHECK(at_most("filters", "g", "c", 8.0, 8.0, "x", 2).met);
    CHECK_FALSE(at_most("filters", "g", "c", 8.01, 8.0, "x", 2).met);
    CHECK_FALSE(at_least("filters", "g", "c", std::nan(""), 1.0, "", 1).met);
    CHECK_FALSE(at_most("filters", "g", "c", std::nan(""), 1.0, "", 1).met);
    // the measured text: decimals or significant digits, and the unit
    CHECK(at_least("filters", "g", "c", 59.84, 120.0, "Mpx/s", 1).measured == "59.8 Mpx/s");
    CHECK(at_most("filters", "g", "c", 7.954, 8.0, "x (150 / 20 ms)", 2).measured == "7.95x (150 / 20 ms)");
    CHECK(at_most("spans", "g", "c", 5.5e-11, 1.0 / 64, "texel", -3).measured == "5.5e-11 texel");
    const std::string md = targets_markdown({at_least("a", "first", "c1", 2.0, 1.0, "", 0), at_most("b", "second", "c2", 2.0, 1.0, "", 0)});
    CHECK(md.find("| a | first | 2 | c1 | yes |") != std::string::npos);
    CHECK(md.find("| b | second | 2 | c2 | no |") != std::string::npos);
    CHECK(md.find("1 of 2 targets met") != std::string::npos);
    // Not measured as the target asks: neither met nor missed, whatever the value.
    Target small = at_least("scale", "third", "c3", 20.0, 10.0, "", 0);
    measured_as_asked(small, false, "the target is for 1M triangles");
    CHECK_FALSE(small.met);
    CHECK(std::string(target_status(small)) == "n/a");
    Target asked = at_least("scale", "fourth", "c4", 20.0, 10.0, "", 0);
    measured_as_asked(asked, true, "unused");
    CHECK(std::string(target_status(asked)) == "met");
    const std::string md2 = targets_markdown({small, asked});
    CHECK(md2.find("| scale | third | 20 | c3 | not measured: the target is for 1M triangles |") != std::string::npos);
    CHECK(md2.find("1 of 2 targets met (1 not measured as the issues ask)") != std::string::npos);
}
