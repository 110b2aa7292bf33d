// The frame being rendered: linear RGB colour and a depth buffer, row 0 at the top.
#pragma once
#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "texr/core/color.h"
#include "texr/core/large_buffer.h"

namespace texr {

// An allocator (over `Base`) whose containers leave new elements uninitialised, so that a
// frame's buffers can be cleared in parallel, each worker its own rows, instead of once
// serially, and buffers that are written whole are not cleared first.
template <typename T, typename Base = std::allocator<T>>
struct UninitializedAllocator : Base {
    template <typename U>
    struct rebind {
        using other = UninitializedAllocator<U, typename std::allocator_traits<Base>::template rebind_alloc<U>>;
    };
    UninitializedAllocator() = default;
    template <typename U, typename B>
    UninitializedAllocator(const UninitializedAllocator<U, B>&) {}
    template <typename U>
    void construct(U*) noexcept {}  // default-construct: leave it
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

// A frame's buffers: uninitialised, and large buffers (large_buffer.h). A 1024x768 frame's
// 12 MB in 4 KiB pages took 12 ms to clear the first time, most of it in the system's page
// faults; in 2 MiB pages, 3 ms. (The renderer keeps its frame across frames.)
template <typename T>
using FrameVector = std::vector<T, UninitializedAllocator<T, LargeAllocator<T>>>;

// Uninitialised buffers from operator new, for buffers made anew every frame: glibc then
// reuses the same memory frame after frame, where fresh mappings would be faulted in (and
// zeroed by the system) each time.
template <typename T>
using ScratchVector = std::vector<T, UninitializedAllocator<T>>;

struct Framebuffer {
    int width = 0, height = 0;
    FrameVector<Color> color;  // linear RGB
    // Window depth in [0, 1] (1 is the far plane), cleared to "nothing here" (+infinity):
    // a surface at the far plane itself, or one whose depth rounds to 1 when near/far is
    // extreme, is still drawn.
    FrameVector<float> depth;
    static constexpr float empty_depth = std::numeric_limits<float>::infinity();
    // Test instrumentation, empty unless sized by the caller: how many triangles covered
    // each pixel (counted before the depth test).
    std::vector<std::uint16_t> coverage;
    // Benchmark instrumentation, empty unless sized by the caller: the (u, v) each visible
    // pixel was textured with.
    std::vector<glm::dvec2> uv;
    // The same for the world position a solid procedural texture read.
    std::vector<glm::dvec3> world_read;
    // texr explain: the story of one pixel, when asked for (render/explain.h).
    std::shared_ptr<struct PixelExplanation> explanation;

    Framebuffer(int w, int h, Color background)
        : width(w), height(h), color(std::size_t(w) * std::size_t(h), background),
          depth(std::size_t(w) * std::size_t(h), empty_depth) {}

    // Buffers sized but not cleared: the caller clears every row (clear_rows) before use.
    struct Uncleared {};
    Framebuffer(int w, int h, Uncleared)
        : width(w), height(h), color(std::size_t(w) * std::size_t(h)), depth(std::size_t(w) * std::size_t(h)) {}
    // The same for a frame that already exists: resized, not cleared, keeping its memory when
    // it is large enough (a renderer drawing frame after frame then asks the system for no new
    // pages, which it would zero first, at some 12 MB per 1024x768 frame).
    void resize_uncleared(int w, int h) {
        width = w, height = h;
        color.resize(std::size_t(w) * std::size_t(h));
        depth.resize(std::size_t(w) * std::size_t(h));
    }

    void clear_rows(int first, int last, Color background);  // rows [first, last)

    bool drawn(std::size_t i) const { return depth[i] != empty_depth; }
    std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(width) + std::size_t(x); }
};

}  // namespace texr
