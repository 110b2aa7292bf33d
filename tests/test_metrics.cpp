// The benchmark's error metrics against hand-worked values.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "../src/bench/common.h"  // (median, fixed: the benchmarks' own helpers)
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

TEST_CASE("PSNR and SSIM against their definitions: a hand-worked PSNR, and SSIM by a slower two-pass sum") {
    // PSNR: channel errors 1, 2, 3, 4, 5, 6 over two pixels: MSE = 91 / 6.
    const FrameBytes a{2, 1, {10, 20, 30, 40, 50, 60}}, b{2, 1, {11, 22, 33, 44, 55, 66}};
    CHECK(psnr(a, b, {true, true}) == doctest::Approx(10.0 * std::log10(255.0 * 255.0 * 6.0 / 91.0)).epsilon(1e-12));  // 36.3219 dB
    CHECK(psnr(a, b, {false, true}) == doctest::Approx(10.0 * std::log10(255.0 * 255.0 * 3.0 / 77.0)).epsilon(1e-12));
    // SSIM (Wang et al. 2004) as metrics.h states it, written otherwise: each pixel's window
    // weights exp(-(dx^2 + dy^2) / (2 1.5^2)) for |dx|, |dy| <= 5 within the frame, the means
    // first, then the variances and covariance about them.
    const auto reference = [](const FrameBytes& f, const FrameBytes& g, const std::vector<bool>& mask) {
        const auto y = [](const FrameBytes& im, int x, int yy) {
            const std::size_t p = 3 * (std::size_t(yy) * std::size_t(im.width) + std::size_t(x));
            return 0.299 * im.rgb[p] + 0.587 * im.rgb[p + 1] + 0.114 * im.rgb[p + 2];
        };
        double total = 0.0;
        int count = 0;
        for (int py = 0; py < f.height; ++py)
            for (int px = 0; px < f.width; ++px) {
                if (!mask[std::size_t(py * f.width + px)]) continue;
                struct Sample {
                    double w, x, y;
                };
                std::vector<Sample> window;
                for (int qy = std::max(0, py - 5); qy <= std::min(f.height - 1, py + 5); ++qy)
                    for (int qx = std::max(0, px - 5); qx <= std::min(f.width - 1, px + 5); ++qx) {
                        const double d2 = double((qx - px) * (qx - px) + (qy - py) * (qy - py));
                        window.push_back({std::exp(-d2 / 4.5), y(f, qx, qy), y(g, qx, qy)});
                    }
                double w = 0, mx = 0, my = 0;
                for (const Sample& s : window) w += s.w, mx += s.w * s.x, my += s.w * s.y;
                mx /= w, my /= w;
                double vx = 0, vy = 0, cxy = 0;
                for (const Sample& s : window)
                    vx += s.w * (s.x - mx) * (s.x - mx), vy += s.w * (s.y - my) * (s.y - my), cxy += s.w * (s.x - mx) * (s.y - my);
                vx /= w, vy /= w, cxy /= w;
                const double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
                total += (2 * mx * my + c1) * (2 * cxy + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
                ++count;
            }
        return total / count;
    };
    // A colour ramp, and the ramp with noise, 20 x 16: the whole frame, and a mask of the
    // pixels near its edges and corners, where windows are clipped.
    FrameBytes ramp{20, 16, std::vector<std::uint8_t>(20 * 16 * 3)};
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 20; ++x) {
            const std::size_t p = 3 * std::size_t(y * 20 + x);
            ramp.rgb[p] = std::uint8_t(10 * x), ramp.rgb[p + 1] = std::uint8_t(12 * y), ramp.rgb[p + 2] = std::uint8_t(5 * (x + y));
        }
    FrameBytes noisy = ramp;
    std::mt19937_64 rng(7);
    for (std::uint8_t& v : noisy.rgb) v = std::uint8_t(std::min(255, int(v) + int(rng() % 40)));
    std::vector<bool> all(20 * 16, true), edges(20 * 16, false);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 20; ++x) edges[std::size_t(y * 20 + x)] = x < 3 || y < 2 || x > 17 || y > 14;
    for (const std::vector<bool>* mask : {&all, &edges}) {
        const double expected = reference(ramp, noisy, *mask);
        CHECK(expected < 0.99);
        CHECK(ssim(ramp, noisy, *mask) == doctest::Approx(expected).epsilon(1e-10));
    }
}

TEST_CASE("the benchmarks' median, fixed-point text and targets' text") {
    using texr::bench::median;
    CHECK(median({3, 1, 2}) == 2.0);
    CHECK(median({4, 1, 3, 2}) == 2.5);
    CHECK(median({5, 1}) == 3.0);
    CHECK(median({7}) == 7.0);
    CHECK(texr::bench::fixed(INFINITY, 2) == "inf");
    CHECK(texr::bench::fixed(-INFINITY, 2) == "-inf");
    using namespace texr::bench;
    // Significant digits: 3 of 0.0123456.
    CHECK(at_least("spans", "g", "c", 0.0123456, 1.0, "texel", -3).measured == "0.0123 texel");
    // A table of targets all measured says nothing of targets not measured.
    const std::string md = targets_markdown({at_least("filters", "g", "c", 2.0, 1.0, "", 1)});
    CHECK(md.find("1 of 1 targets met.") != std::string::npos);
    CHECK(md.find("not measured") == std::string::npos);
}
