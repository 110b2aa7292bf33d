// sRGB transfer functions (see include/texr/core/color.h for the formula).
#include "texr/core/color.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace texr {

float srgb_to_linear(float encoded) {
    if (encoded <= 0.04045f) return encoded / 12.92f;
    return std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float linear) {
    if (linear <= 0.0031308f) return linear * 12.92f;
    return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

const float* srgb8_to_linear_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[i] = srgb_to_linear(float(i) / 255.0f);
        return t;
    }();
    return table.data();
}

// Encoding goes through a table with 2^16 linear steps: the sRGB curve's steepest slope
// (12.92 near 0) moves the output by 12.92 * 255 / 65535 = 0.05 of a byte per step, and a
// value is read at its nearest step, at most half a step away, so the table gives the
// correctly rounded byte except within about 0.025 of a rounding boundary (tested at 0.03).
const std::uint8_t* linear_to_srgb8_table() {
    static const std::array<std::uint8_t, 65536> table = [] {
        std::array<std::uint8_t, 65536> t{};
        for (int i = 0; i < 65536; ++i)
            t[i] = std::uint8_t(std::lround(linear_to_srgb(float(i) / 65535.0f) * 255.0f));
        return t;
    }();
    return table.data();
}

std::uint8_t linear_to_srgb8(float linear) { return linear_to_srgb8(linear, linear_to_srgb8_table()); }

}  // namespace texr
