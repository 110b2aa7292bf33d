// Large buffers (core/large_buffer.h): mapped on 2 MiB boundaries from 1 MiB up, and
// memory like any other: every byte written reads back, and vectors of them behave.
#include <doctest/doctest.h>

#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <vector>

#include "texr/core/large_buffer.h"
#include "texr/texture/image.h"

using namespace texr;

namespace {

// Whether every page of [p, p + bytes) is mapped (mincore fails with ENOMEM when one is not).
bool mapped(const void* p, std::size_t bytes) {
    std::vector<unsigned char> resident((bytes + 4095) / 4096);
    return mincore(const_cast<void*>(p), bytes, resident.data()) == 0;
}

}  // namespace

TEST_CASE("buffers of 1 MiB and more start on a 2 MiB boundary, smaller ones come from operator new") {
    CHECK_FALSE(maps_large(1000));
    CHECK_FALSE(maps_large((std::size_t(1) << 20) - 1));
#ifdef TEXR_ADDRESS_SANITIZER
    CHECK_FALSE(maps_large(std::size_t(1) << 20));  // AddressSanitizer sees every buffer
#else
    CHECK(maps_large(std::size_t(1) << 20));
    CHECK(maps_large(std::size_t(1) << 30));
#endif
    for (const std::size_t bytes : {std::size_t(1) << 20, std::size_t(2) << 20, (std::size_t(3) << 20) + 1}) {
        CAPTURE(bytes);
        auto* p = static_cast<std::uint8_t*>(allocate_large(bytes));
        REQUIRE(p != nullptr);
        if (maps_large(bytes)) CHECK(reinterpret_cast<std::uintptr_t>(p) % huge_page_bytes == 0);
        // Every page, and the last byte, hold what was written (the size is not cut short).
        for (std::size_t i = 0; i < bytes; i += 4096) p[i] = std::uint8_t(i / 4096 * 7 + 1);
        bool same = true;
        for (std::size_t i = 0; i < bytes; i += 4096) same = same && p[i] == std::uint8_t(i / 4096 * 7 + 1);
        CHECK(same);
        p[bytes - 1] = 0xa5;
        CHECK(p[bytes - 1] == 0xa5);
        free_large(p, bytes);
        // A mapped buffer is given back whole: every one of its 2 MiB pages is unmapped.
        if (maps_large(bytes)) {
            bool any_left = false;
            for (std::size_t page = 0; page < bytes; page += huge_page_bytes) any_left = any_left || mapped(p + page, 4096);
            CHECK_FALSE(any_left);
        }
    }
    void* small = allocate_large(100);
    std::memset(small, 1, 100);
    free_large(small, 100);
    free_large(nullptr, std::size_t(4) << 20);  // nothing to release
}

TEST_CASE("a vector in large buffers grows, copies and keeps its elements across the 1 MiB line") {
    LargeVector<std::uint32_t> v;
    for (std::uint32_t i = 0; i < 600000; ++i) v.push_back(i * 2654435761u);  // 2.4 MB: crosses 1 MiB while growing
    const LargeVector<std::uint32_t> copy = v;
    bool same = copy.size() == 600000;
    for (std::uint32_t i = 0; i < 600000 && same; ++i) same = copy[i] == i * 2654435761u;
    CHECK(same);
    v.resize(10);  // shrinking keeps the first elements
    v.shrink_to_fit();
    CHECK(v[9] == 9u * 2654435761u);
}

TEST_CASE("an image in a large buffer reads its texels where they were put") {
    // 1024 x 512 RGBA = 2 MiB: texel (i, j) holds (i mod 256, j mod 256, (i + j) mod 256, 255).
    const int w = 1024, h = 512;
    LargeVector<std::uint8_t> rgba(std::size_t(w) * h * 4);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            std::uint8_t* t = &rgba[4 * (std::size_t(j) * w + i)];
            t[0] = std::uint8_t(i), t[1] = std::uint8_t(j), t[2] = std::uint8_t(i + j), t[3] = 255;
        }
    const Image image = Image::ldr(w, h, ColorSpace::linear, std::move(rgba));
    CHECK(image.bytes() == std::size_t(w) * h * 4);
    const Color4 t = image.texel(1000, 300);  // linear data: k / 255
    CHECK(t.x == doctest::Approx(1000 % 256 / 255.0));
    CHECK(t.y == doctest::Approx(300 % 256 / 255.0));
    CHECK(t.z == doctest::Approx(1300 % 256 / 255.0));
    CHECK(t.w == doctest::Approx(1.0));
}
