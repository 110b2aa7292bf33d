// stb_image_write compiled with zlib as its compressor (see png_encode.h). Debian's
// libstb-dev ships the implementation in stb_image_write.h; STB_IMAGE_WRITE_STATIC keeps
// this copy private to this file, apart from libstb's own, which the tests still link.
//
// Why zlib: the frame's bytes are deflated once per render, and stb_image_write's deflate
// (level 5, the lowest it honours) made the write of the 1024x768 benchmark plane about 75
// ms; with zlib at level 2 it is about 37 ms, for a 7% smaller file (README, "Rendering").
// Every row gets the Sub filter (each byte minus the one a pixel to its left): trying all
// five filters per row, stb_image_write's default, took about twice as long, and with zlib
// the plane's file came out 6% larger (467,809 bytes against 440,410).
#include "png_encode.h"

#include <zlib.h>

#include <cstdlib>
#include <memory>

namespace {

constexpr int deflate_level = 2;

// The zlib stream (RFC 1950) of data, in memory from malloc, as stb_image_write expects (it
// frees it with free); null when zlib fails.
unsigned char* zlib_compress(unsigned char* data, int length, int* out_length, int /*stb's level: unused*/) {
    uLongf size = compressBound(uLong(length));
    auto* out = static_cast<unsigned char*>(std::malloc(size));
    if (!out) return nullptr;
    if (compress2(out, &size, data, uLong(length), deflate_level) != Z_OK) {
        std::free(out);
        return nullptr;
    }
    *out_length = int(size);
    return out;
}

}  // namespace

#define STBIW_ZLIB_COMPRESS zlib_compress
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

namespace texr::png {

std::vector<std::uint8_t> encode_rgb8(const std::uint8_t* rgb, int width, int height) {
    // Sub on every row: set once (a static's initialisation runs once, even across threads),
    // so that frames encoded on several threads at once never write the setting together.
    static const bool sub_filter = (stbi_write_force_png_filter = 1, true);
    (void)sub_filter;
    int length = 0;
    // The file in memory from malloc, held so that it is freed whatever happens next.
    const std::unique_ptr<unsigned char, void (*)(void*)> file(stbi_write_png_to_mem(rgb, width * 3, width, height, 3, &length), std::free);
    if (!file) return {};
    return std::vector<std::uint8_t>(file.get(), file.get() + length);
}

}  // namespace texr::png
