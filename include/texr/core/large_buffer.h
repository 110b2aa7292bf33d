// Memory for texr's large buffers that live across frames: texels, mip levels and the frame
// buffers. (Not for buffers made anew every frame: each would be faulted in afresh.)
// A texture read across a receding plane touches a different 4 KiB page for nearly every
// pixel near the horizon, and each new page costs a TLB miss (a walk of the page tables).
// Backed by 2 MiB pages, a 1024x1024 RGBA texture is two TLB entries. So buffers of at
// least large_buffer_bytes are mapped 2 MiB-aligned, their size rounded up to whole 2 MiB,
// and the system is asked to back them with 2 MiB pages (madvise MADV_HUGEPAGE). It may
// decline (transparent huge pages set to "never", or no free 2 MiB page): the memory then
// behaves as any other. Smaller buffers come from operator new.
// Under AddressSanitizer every buffer comes from operator new, so overruns are still caught.
#pragma once
#include <cstddef>
#include <new>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)  // g++
#define TEXR_ADDRESS_SANITIZER 1
#elif defined(__has_feature)  // clang
#if __has_feature(address_sanitizer)
#define TEXR_ADDRESS_SANITIZER 1
#endif
#endif

namespace texr {

constexpr std::size_t huge_page_bytes = std::size_t(2) << 20;
constexpr std::size_t large_buffer_bytes = std::size_t(1) << 20;  // rounding wastes at most half

// `bytes` of memory (throws std::bad_alloc), and its release: free_large takes the same size.
void* allocate_large(std::size_t bytes);
void free_large(void* p, std::size_t bytes) noexcept;

// Whether allocate_large maps buffers of this size itself (false under AddressSanitizer).
bool maps_large(std::size_t bytes);
// The memory a buffer of `bytes` takes: mapped buffers are whole 2 MiB pages.
std::size_t large_buffer_footprint(std::size_t bytes);

// An allocator whose large allocations come from allocate_large (a minimal one, written
// out rather than derived from std::allocator, so that no inherited member can allocate
// memory that deallocate would then release the wrong way).
template <typename T>
struct LargeAllocator {
    static_assert(alignof(T) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__, "operator new serves the small buffers");
    using value_type = T;
    LargeAllocator() = default;
    template <typename U>
    LargeAllocator(const LargeAllocator<U>&) {}
    T* allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_alloc();
        return static_cast<T*>(allocate_large(n * sizeof(T)));
    }
    void deallocate(T* p, std::size_t n) noexcept { free_large(p, n * sizeof(T)); }
    template <typename U>
    bool operator==(const LargeAllocator<U>&) const { return true; }
    template <typename U>
    bool operator!=(const LargeAllocator<U>&) const { return false; }
};

template <typename T>
using LargeVector = std::vector<T, LargeAllocator<T>>;

}  // namespace texr
