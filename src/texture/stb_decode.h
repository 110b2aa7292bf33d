// stb_image's decoders, compiled into texr (src/texture/stb_decode.cpp) so that the memory
// they allocate, and the stack below them, hold a byte texr chooses: image.cpp decodes a file
// whose format can leave texels unset twice, under two such bytes, and refuses it when the
// two results differ. Internal to src/texture/image.cpp.
#pragma once
#include <memory>
#include <string>

namespace texr::stb_decode {

// Decoded RGBA rows, top row first: 8-bit, or float for Radiance HDR.
struct Pixels {
    std::unique_ptr<void, void (*)(void*)> data{nullptr, nullptr};
    int width = 0, height = 0;
    bool hdr = false;
    std::string failure;  // stb_image's reason when data is null
};

bool is_hdr(const unsigned char* bytes, int length);
// Whether stb_image reads 16 bits a channel from the image (a PNG, Photoshop file or PPM/PGM).
bool is_16_bit(const unsigned char* bytes, int length);

// The image's size as its header gives it, without decoding (false if stb_image cannot
// read the header). For a GIF, the size of its logical screen.
bool header_size(const unsigned char* bytes, int length, int& width, int& height);

// Decodes with every byte stb_image allocates, and the stack it runs on, first set to `fill`:
// as float texels when `hdr` (is_hdr's answer for these bytes), else as 8-bit ones.
Pixels decode(const unsigned char* bytes, int length, bool hdr, unsigned char fill);

}  // namespace texr::stb_decode
