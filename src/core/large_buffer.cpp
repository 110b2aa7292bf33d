// Large buffers in 2 MiB pages (see large_buffer.h).
#include "texr/core/large_buffer.h"

#include <sys/mman.h>

#include <cstdint>

namespace texr {
namespace {

std::size_t whole_huge_pages(std::size_t bytes) { return (bytes + huge_page_bytes - 1) / huge_page_bytes * huge_page_bytes; }

}  // namespace

bool maps_large(std::size_t bytes) {
#ifdef TEXR_ADDRESS_SANITIZER
    (void)bytes;
    return false;
#else
    return bytes >= large_buffer_bytes;
#endif
}

std::size_t large_buffer_footprint(std::size_t bytes) { return maps_large(bytes) ? whole_huge_pages(bytes) : bytes; }

void* allocate_large(std::size_t bytes) {
    if (!maps_large(bytes)) return ::operator new(bytes);
    if (bytes > std::size_t(-1) - 2 * huge_page_bytes) throw std::bad_alloc();
    // Map one huge page more than needed, then unmap the ends: what is left starts on a
    // 2 MiB boundary, so the system can back it with whole 2 MiB pages.
    const std::size_t size = whole_huge_pages(bytes), mapped = size + huge_page_bytes;
    void* p = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    const std::uintptr_t start = reinterpret_cast<std::uintptr_t>(p);
    const std::uintptr_t aligned = (start + huge_page_bytes - 1) / huge_page_bytes * huge_page_bytes;
    const std::size_t head = aligned - start, tail = mapped - head - size;
    if (head) munmap(p, head);
    if (tail) munmap(reinterpret_cast<void*>(aligned + size), tail);
    madvise(reinterpret_cast<void*>(aligned), size, MADV_HUGEPAGE);  // a request: refusal is fine
    return reinterpret_cast<void*>(aligned);
}

void free_large(void* p, std::size_t bytes) noexcept {
    if (!p) return;
    if (!maps_large(bytes)) return ::operator delete(p);
    munmap(p, whole_huge_pages(bytes));
}

}  // namespace texr
