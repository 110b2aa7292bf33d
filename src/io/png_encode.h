// PNG encoding: stb_image_write's PNG writer (row filters, chunks, CRCs) with zlib's deflate
// in place of stb_image_write's own compressor (src/io/png_encode.cpp). Internal to
// src/io/frame_writer.cpp.
#pragma once
#include <cstdint>
#include <vector>

namespace texr::png {

// The PNG file of `height` rows of `width` 8-bit RGB pixels, top row first; empty when the
// encoder fails (out of memory).
std::vector<std::uint8_t> encode_rgb8(const std::uint8_t* rgb, int width, int height);

}  // namespace texr::png
