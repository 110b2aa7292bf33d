// stb_image compiled with texr's allocation functions (see stb_decode.h). Debian's libstb-dev
// ships the implementation in stb_image.h; STB_IMAGE_STATIC keeps it private to this file,
// apart from libstb's own copy, which the tests link (to write their test images).
#include "stb_decode.h"

#include <cstdlib>
#include <cstring>

namespace {

thread_local unsigned char fill_byte = 0;  // set by decode() for the call it makes on this thread

void* filled_malloc(std::size_t size) {
    void* p = std::malloc(size);
    if (p) std::memset(p, fill_byte, size);
    return p;
}

void* filled_realloc(void* p, std::size_t old_size, std::size_t size) {
    void* q = std::realloc(p, size);
    if (q && size > old_size) std::memset(static_cast<unsigned char*>(q) + old_size, fill_byte, size - old_size);
    return q;
}

// Sets the stack below the caller's frame, where stb_image's frames will lie (its palettes
// are arrays there), to fill_byte. Not inlined, so that its array is below the caller's frame.
[[gnu::noinline]] void fill_stack_below() {
    unsigned char area[64 * 1024];
    std::memset(area, fill_byte, sizeof area);
    asm volatile("" : : "r"(area) : "memory");  // the writes are kept
}

}  // namespace

#define STBI_MALLOC(size) filled_malloc(size)
#define STBI_REALLOC_SIZED(p, old_size, size) filled_realloc(p, old_size, size)
#define STBI_REALLOC(p, size) std::realloc(p, size)  // (stb_image uses the sized form when given)
#define STBI_FREE(p) std::free(p)
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb_image.h>
#pragma GCC diagnostic pop

namespace texr::stb_decode {

bool is_hdr(const unsigned char* bytes, int length) { return stbi_is_hdr_from_memory(bytes, length) != 0; }

bool is_16_bit(const unsigned char* bytes, int length) { return stbi_is_16_bit_from_memory(bytes, length) != 0; }

bool header_size(const unsigned char* bytes, int length, int& width, int& height) {
    int channels = 0;
    return stbi_info_from_memory(bytes, length, &width, &height, &channels) != 0;
}

Pixels decode(const unsigned char* bytes, int length, bool hdr, unsigned char fill) {
    fill_byte = fill;
    Pixels p;
    p.data = std::unique_ptr<void, void (*)(void*)>(nullptr, [](void* q) { stbi_image_free(q); });
    p.hdr = hdr;
    int channels = 0;
    fill_stack_below();
    p.data.reset(p.hdr ? static_cast<void*>(stbi_loadf_from_memory(bytes, length, &p.width, &p.height, &channels, 4))
                       : static_cast<void*>(stbi_load_from_memory(bytes, length, &p.width, &p.height, &channels, 4)));
    if (!p.data) {
        const char* reason = stbi_failure_reason();
        p.failure = reason ? reason : "";
    }
    fill_byte = 0;
    return p;
}

}  // namespace texr::stb_decode
