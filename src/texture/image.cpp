// Image loading with stb_image; rows are flipped so that row 0 is the bottom (v = 0).
#include "texr/texture/image.h"

#include <stb_image.h>

#include <array>
#include <cctype>
#include <cstring>
#include <fstream>

#include "texr/core/error.h"

namespace texr {

Image Image::ldr(int width, int height, ColorSpace space, std::vector<std::uint8_t> rgba) {
    Image image;
    image.width_ = width;
    image.height_ = height;
    image.space_ = space;
    image.texels_8_ = std::move(rgba);
    image.inv_width_ = 1.0 / width, image.inv_height_ = 1.0 / height;
    image.decode_ = space == ColorSpace::srgb ? srgb8_to_linear_table() : unorm8_to_float_table();
    image.ldr_pow2_ = width > 0 && height > 0 && (width & (width - 1)) == 0 && (height & (height - 1)) == 0;
    return image;
}

Image Image::hdr(int width, int height, std::vector<float> rgba) {
    Image image;
    image.width_ = width;
    image.height_ = height;
    image.space_ = ColorSpace::linear;  // Radiance files hold linear radiance
    image.texels_f_ = std::move(rgba);
    image.hdr_ = true;
    image.inv_width_ = 1.0 / width, image.inv_height_ = 1.0 / height;
    return image;
}

const float* unorm8_to_float_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[std::size_t(i)] = float(i) / 255.0f;
        return t;
    }();
    return table.data();
}

namespace {

template <typename T>
std::vector<T> flipped_rows(const T* top_down, int width, int height) {
    const std::size_t row = std::size_t(width) * 4;
    std::vector<T> out(row * std::size_t(height));
    for (int j = 0; j < height; ++j)  // file row j (from the top) becomes row height-1-j
        std::memcpy(&out[row * std::size_t(height - 1 - j)], top_down + row * std::size_t(j),
                    row * sizeof(T));
    return out;
}

}  // namespace

namespace {

// stb_image's reason for a failure, in words a user can act on (its own are terse codes,
// and for a file cut short inside a PNG chunk, bytes past its end).
std::string unreadable(const char* reason) {
    std::string r = reason ? reason : "";
    for (const char ch : r)
        if (!std::isprint(static_cast<unsigned char>(ch))) r.clear();
    std::string why;
    if (r == "unknown image type") why = "not a format stb_image reads (PNG, JPEG, TGA, BMP, GIF, PSD, PIC, PPM/PGM or Radiance HDR)";
    else if (r == "outofmem") why = "out of memory";
    else if (r == "too large") why = "the image is too large to read";
    else why = "the file is cut short or damaged" + (r.empty() ? std::string() : " (stb_image: " + r + ")");
    return "not a readable image: " + why;
}

}  // namespace

Image load_image(const std::string& path, ColorSpace space) {
    require_file(path, "an image file");
    if (!std::ifstream(path)) throw InputError(path, 0, "cannot open image file");
    int width = 0, height = 0, channels = 0;
    if (stbi_is_hdr(path.c_str())) {
        float* data = stbi_loadf(path.c_str(), &width, &height, &channels, 4);
        if (!data) throw InputError(path, 0, unreadable(stbi_failure_reason()));
        Image image = Image::hdr(width, height, flipped_rows(data, width, height));
        stbi_image_free(data);
        return image;
    }
    unsigned char* data = stbi_load(path.c_str(), &width, &height, &channels, 4);
    if (!data) throw InputError(path, 0, unreadable(stbi_failure_reason()));
    Image image = Image::ldr(width, height, space, flipped_rows(data, width, height));
    stbi_image_free(data);
    return image;
}

}  // namespace texr
