// stb_image_write compiled with zlib as its compressor (see png_encode.h). Debian's
// libstb-dev ships the implementation in stb_image_write.h; STB_IMAGE_WRITE_STATIC keeps
// this copy private to this file, apart from libstb's own, which the tests still link.
//
// Why zlib: the frame's bytes are deflated once per render, and stb_image_write's deflate
// (level 5, the lowest it honours) took about 60 ms of a 1024x768 frame. zlib at level 2
// takes about 25 ms there and makes a smaller file (README, "Rendering"). Every row gets
// the Sub filter (each byte minus the one a pixel to its left): trying all five filters per
// row, stb_image_write's default, took twice as long for a file 6% smaller.
#include "png_encode.h"

#include <zlib.h>

#include <cstdlib>

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

namespace {

void append_bytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<std::uint8_t>*>(context);
    const auto* bytes = static_cast<const std::uint8_t*>(data);
    out->insert(out->end(), bytes, bytes + size);
}

}  // namespace

std::vector<std::uint8_t> encode_rgb8(const std::uint8_t* rgb, int width, int height) {
    stbi_write_force_png_filter = 1;  // Sub
    std::vector<std::uint8_t> out;
    if (!stbi_write_png_to_func(append_bytes, &out, width, height, 3, rgb, width * 3)) out.clear();
    return out;
}

}  // namespace texr::png
