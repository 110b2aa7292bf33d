// The texel store: the only layer that touches texels (DESIGN.md, "Layering").
// Texel (i, j) is column i from the left and row j from the *bottom* of the image file,
// so that v = 0 is the bottom row (OBJ / OpenGL convention). Every image is kept as RGBA:
// LDR images as 8 bits per channel (sRGB-encoded colour, or linear data), HDR as float.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "texr/core/color.h"

namespace texr {

enum class ColorSpace { srgb, linear };

class Image {
public:
    Image() = default;
    static Image ldr(int width, int height, ColorSpace space, std::vector<std::uint8_t> rgba);
    static Image hdr(int width, int height, std::vector<float> rgba);

    int width() const { return width_; }
    int height() const { return height_; }
    double inv_width() const { return inv_width_; }
    double inv_height() const { return inv_height_; }
    bool is_hdr() const { return hdr_; }
    ColorSpace color_space() const { return space_; }
    std::size_t bytes() const { return texels_8_.size() + texels_f_.size() * sizeof(float); }

    // Linear RGBA of texel (i, j); i in [0, width), j in [0, height).
    [[gnu::always_inline]] Color4 texel(int i, int j) const {
        const std::size_t k = (std::size_t(j) * std::size_t(width_) + std::size_t(i)) * 4;
        if (hdr_) return {texels_f_[k], texels_f_[k + 1], texels_f_[k + 2], texels_f_[k + 3]};
        const std::uint8_t* t = &texels_8_[k];
        return {decode_[t[0]], decode_[t[1]], decode_[t[2]], t[3] * (1.0f / 255.0f)};
    }

private:
    int width_ = 0, height_ = 0;
    double inv_width_ = 0.0, inv_height_ = 0.0;
    ColorSpace space_ = ColorSpace::srgb;
    bool hdr_ = false;
    std::vector<std::uint8_t> texels_8_;
    std::vector<float> texels_f_;
    const float* decode_ = nullptr;  // byte -> linear value: the sRGB table, or k / 255
};

// The table that reads 8-bit data texels as k / 255.
const float* unorm8_to_float_table();

// Loads PNG, JPEG, TGA, BMP (8-bit) or Radiance HDR (float) with stb_image.
// `space` says how 8-bit texels are to be read: srgb for colour, linear for data.
// Throws InputError naming the file when it cannot be read.
Image load_image(const std::string& path, ColorSpace space);

}  // namespace texr
