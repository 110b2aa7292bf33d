// The texel store: the only layer that touches texels (docs/design.md, "Layering").
// Texel (i, j) is column i from the left and row j from the *bottom* of the image file,
// so that v = 0 is the bottom row (OBJ / OpenGL convention). Every image is kept as RGBA:
// LDR images as 8 bits per channel (sRGB-encoded colour, or linear data), HDR as float.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "texr/core/color.h"
#include "texr/core/large_buffer.h"

namespace texr {

enum class ColorSpace { srgb, linear };

// An 8-bit image (or mip level) as the short texture paths and EWA read it: the values they
// need per lookup, loaded once per triangle (or footprint) instead of through the Image.
// The masks mean something only for power-of-two sides (the short paths' images).
struct LdrLevel {
    const std::uint8_t* texels = nullptr;  // RGBA rows, bottom row first
    const float* decode = nullptr;         // byte -> linear value
    // The same texels decoded (Image::decoded_texels), 4 floats each at 4 times the byte
    // offset; or null. Filters that blend texels read one texel in one load from it instead
    // of four byte loads and three table loads, for the same values.
    const float* decoded = nullptr;
    double width = 0.0, height = 0.0;      // for u * width
    std::int64_t mask_u = 0, mask_v = 0;   // width - 1, height - 1
    std::size_t row_bytes = 0;
    int row_shift = 0;                     // log2(row_bytes): rows are addressed by it on the short
                                           // paths, whose widths are powers of two
};

// Linear RGBA of the 8-bit texel at t: colour through the decode table, alpha as k / 255.
[[gnu::always_inline]] inline Color4 decode_ldr_texel(const std::uint8_t* t, const float* decode) {
    return {decode[t[0]], decode[t[1]], decode[t[2]], t[3] * (1.0f / 255.0f)};
}

// Bilinear blend of four 8-bit texels: columns c0 | c1 (byte offsets) of rows r0 | r1,
// by successive linear interpolations along v, then u, on decoded linear values.
[[gnu::always_inline]] inline Color4 blend_ldr_texels(const std::uint8_t* r0, const std::uint8_t* r1, std::size_t c0,
                                                      std::size_t c1, const float* decode, float fu, float fv) {
    float rgb[3];  // (not Color4's operator[], which switches on the index)
    for (int c = 0; c < 3; ++c) {
        const float column0 = decode[r0[c0 + c]] + fv * (decode[r1[c0 + c]] - decode[r0[c0 + c]]);
        const float column1 = decode[r0[c1 + c]] + fv * (decode[r1[c1 + c]] - decode[r0[c1 + c]]);
        rgb[c] = column0 + fu * (column1 - column0);
    }
    // Alpha is stored linearly: k / 255, blended like the general path does it.
    const float a00 = r0[c0 + 3] * (1.0f / 255.0f), a01 = r1[c0 + 3] * (1.0f / 255.0f);
    const float a10 = r0[c1 + 3] * (1.0f / 255.0f), a11 = r1[c1 + 3] * (1.0f / 255.0f);
    const float a0 = a00 + fv * (a01 - a00), a1 = a10 + fv * (a11 - a10);
    return {rgb[0], rgb[1], rgb[2], a0 + fu * (a1 - a0)};
}

#if defined(__SSE__)
// The four channels in the four lanes of one register: a + t (b - a) on each.
[[gnu::always_inline]] inline __m128 lerp_lanes(__m128 a, __m128 b, float t) {
    return _mm_add_ps(a, _mm_mul_ps(_mm_set1_ps(t), _mm_sub_ps(b, a)));
}
[[gnu::always_inline]] inline Color4 color_of_lanes(__m128 c) {
    alignas(16) float out[4];
    _mm_store_ps(out, c);
    return {out[0], out[1], out[2], out[3]};
}
// blend_decoded_texels in lanes (below).
[[gnu::always_inline]] inline __m128 blend_decoded_lanes(const float* r0, const float* r1, std::size_t c0, std::size_t c1,
                                                         float fu, float fv) {
    const __m128 column0 = lerp_lanes(_mm_loadu_ps(r0 + c0), _mm_loadu_ps(r1 + c0), fv);
    const __m128 column1 = lerp_lanes(_mm_loadu_ps(r0 + c1), _mm_loadu_ps(r1 + c1), fv);
    return lerp_lanes(column0, column1, fu);
}
#endif

// The same blend on decoded texels (LdrLevel::decoded): rows r0 | r1, columns c0 | c1 as
// float offsets. The same operations on the same values: the same result to the bit.
[[gnu::always_inline]] inline Color4 blend_decoded_texels(const float* r0, const float* r1, std::size_t c0, std::size_t c1,
                                                          float fu, float fv) {
#if defined(__SSE__)  // (written out rather than through blend_decoded_lanes: anisotropic
                      // filtering, which sums these, took 15% more instructions that way)
    const __m128 t00 = _mm_loadu_ps(r0 + c0), t01 = _mm_loadu_ps(r1 + c0);
    const __m128 t10 = _mm_loadu_ps(r0 + c1), t11 = _mm_loadu_ps(r1 + c1);
    const __m128 v = _mm_set1_ps(fv);
    const __m128 column0 = _mm_add_ps(t00, _mm_mul_ps(v, _mm_sub_ps(t01, t00)));
    const __m128 column1 = _mm_add_ps(t10, _mm_mul_ps(v, _mm_sub_ps(t11, t10)));
    const __m128 blend = _mm_add_ps(column0, _mm_mul_ps(_mm_set1_ps(fu), _mm_sub_ps(column1, column0)));
    alignas(16) float out[4];
    _mm_store_ps(out, blend);
    return {out[0], out[1], out[2], out[3]};
#else
    float out[4];
    for (int c = 0; c < 4; ++c) {
        const float column0 = r0[c0 + c] + fv * (r1[c0 + c] - r0[c0 + c]);
        const float column1 = r0[c1 + c] + fv * (r1[c1 + c] - r0[c1 + c]);
        out[c] = column0 + fu * (column1 - column0);
    }
    return {out[0], out[1], out[2], out[3]};
#endif
}

class Image {
public:
    Image() = default;
    // RGBA texels, bottom row first. (Texels in another kind of vector are copied.)
    static Image ldr(int width, int height, ColorSpace space, LargeVector<std::uint8_t> rgba);
    static Image hdr(int width, int height, LargeVector<float> rgba);
    template <typename Allocator>
    static Image ldr(int width, int height, ColorSpace space, const std::vector<std::uint8_t, Allocator>& rgba) {
        return ldr(width, height, space, LargeVector<std::uint8_t>(rgba.begin(), rgba.end()));
    }
    template <typename Allocator>
    static Image hdr(int width, int height, const std::vector<float, Allocator>& rgba) {
        return hdr(width, height, LargeVector<float>(rgba.begin(), rgba.end()));
    }

    int width() const { return width_; }
    int height() const { return height_; }
    double inv_width() const { return inv_width_; }
    double inv_height() const { return inv_height_; }
    bool is_hdr() const { return hdr_; }
    // 8-bit texels and a power-of-two width and height: repeat wraps by a bit mask.
    bool is_ldr_pow2() const { return ldr_pow2_; }
    ColorSpace color_space() const { return space_; }
    std::size_t bytes() const { return texels_8_.size() + texels_f_.size() * sizeof(float); }

    // Linear RGBA of texel (i, j); i in [0, width), j in [0, height).
    [[gnu::always_inline]] Color4 texel(int i, int j) const {
        const std::size_t k = (std::size_t(j) * std::size_t(width_) + std::size_t(i)) * 4;
        if (hdr_) return {texels_f_[k], texels_f_[k + 1], texels_f_[k + 2], texels_f_[k + 3]};
        return decode_ldr_texel(&texels_8_[k], decode_);
    }

    // Bilinear blend of the four LDR texels (i0|i1, j0|j1), all inside the image:
    // successive linear interpolations along v, then u, on decoded linear values. The row
    // addresses are computed once for the four texels (the hot path of bilinear filtering).
    [[gnu::always_inline]] Color4 blend_ldr(int i0, int i1, int j0, int j1, float fu, float fv) const {
        const std::size_t row = std::size_t(width_) * 4;
        return blend_ldr_texels(texels_8_.data() + std::size_t(j0) * row, texels_8_.data() + std::size_t(j1) * row,
                                std::size_t(i0) * 4, std::size_t(i1) * 4, decode_, fu, fv);
    }

    // The view of an 8-bit image (see LdrLevel); with_decoded: with its decoded copy, if it
    // may have one (decoded_texels).
    LdrLevel ldr_level(bool with_decoded = false) const {
        return {texels_8_.data(), decode_, with_decoded ? decoded_texels() : nullptr, double(width_), double(height_),
                std::int64_t(width_) - 1, std::int64_t(height_) - 1, std::size_t(width_) * 4, row_shift_};
    }

    // An 8-bit image's texels decoded to linear float RGBA, as texel() reads them, for the
    // short paths that blend texels (src/render/scanline.h: bilinear on the spans where it
    // pays, the mip filters), anisotropic filtering and EWA; made on the first call
    // (thread-safe), so an image no such lookup reads has none. Null for HDR images, for
    // images of more than max_decoded_texels texels, once the process's copies would pass
    // decoded_budget_bytes (counted as the memory they take: whole 2 MiB pages from 1 MiB
    // up), and if the memory cannot be had. A copy is 4 times the image's 8-bit texels, and
    // it pays only while it stays in cache. (Measured on the receding plane, 1 thread,
    // random-noise textures, bilinear read from the copy everywhere: 3.85 -> 2.55 ms at
    // 512^2, 3.85 -> 2.68 ms at 1024^2, 3.99 -> 3.61 ms at 2048^2, 4.37 -> 5.09 ms at 4096^2.)
    static constexpr std::size_t max_decoded_texels = std::size_t(1) << 20;      // 1024 x 1024: a 16 MiB copy
    static constexpr std::size_t decoded_budget_bytes = std::size_t(256) << 20;  // all images' copies
    const float* decoded_texels() const;
    // Whether decoded_texels may give a copy (8-bit, at most max_decoded_texels; the budget
    // is not checked).
    bool may_be_decoded() const {
        return !hdr_ && !texels_8_.empty() && std::size_t(width_) * std::size_t(height_) <= max_decoded_texels;
    }
    std::size_t decoded_bytes() const;  // of the decoded copy, if made (else 0)

private:
    int width_ = 0, height_ = 0;
    double inv_width_ = 0.0, inv_height_ = 0.0;
    ColorSpace space_ = ColorSpace::srgb;
    bool hdr_ = false;
    bool ldr_pow2_ = false;
    int row_shift_ = 0;  // floor(log2(4 * width)): the row stride's shift when the width is a power of two
    LargeVector<std::uint8_t> texels_8_;  // (in 2 MiB pages: see large_buffer.h)
    LargeVector<float> texels_f_;
    const float* decode_ = nullptr;  // byte -> linear value: the sRGB table, or k / 255
    // The decoded copy, decided once (made, or refused by the budget or by a failed
    // allocation); shared by copies of the image, whose texels are the same. Only images
    // that may_be_decoded have one.
    struct Decoded {
        std::once_flag once;
        std::atomic<bool> decided{false};  // (read first: no call_once once decided)
        const float* texels = nullptr;     // the copy's texels, or null; set before `decided`
        LargeVector<float> storage;
        std::size_t reserved = 0;  // budget bytes held
        ~Decoded();                // returns them
    };
    std::shared_ptr<Decoded> decoded_;
};

// The table that reads 8-bit data texels as k / 255.
const float* unorm8_to_float_table();

// The largest image side load_image reads: 16384 (the usual GL_MAX_TEXTURE_SIZE), so an
// 8-bit image is at most 1 GiB of texels.
constexpr int max_texture_side = 16384;

// Loads what stb_image reads: PNG, JPEG, TGA, BMP, GIF, PSD, PIC, PPM/PGM (8-bit) or
// Radiance HDR (float).
// `space` says how 8-bit texels are to be read: srgb for colour, linear for data.
// Throws InputError naming the file when it cannot be read.
Image load_image(const std::string& path, ColorSpace space);

// Whether the image file holds 16 bits a channel (a PNG or Photoshop file: load_image reads
// such a file's high bytes; it refuses a 16-bit PPM/PGM). Throws InputError as load_image.
bool image_file_is_16_bit(const std::string& path);

}  // namespace texr
