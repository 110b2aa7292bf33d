// Colour encodings. Shading and filtering happen on linear values; images on disk and on
// screen are sRGB. The transfer function is the piecewise sRGB curve (IEC 61966-2-1):
//   linear = c / 12.92                    for c <= 0.04045
//   linear = ((c + 0.055) / 1.055)^2.4     otherwise
#pragma once
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace texr {

using Color = glm::vec3;   // linear RGB
using Color4 = glm::vec4;  // linear RGBA (alpha is coverage, never encoded)

// Whether every channel is finite. A filter's float sum of HDR texels near the float maximum
// (3.4e38) can overflow to inf (and inf - inf to NaN); the filters that sum many texels or
// probes check their sums with this and sum again in double.
// (x - x is 0 for a finite x and NaN for an infinite or NaN one: a few instructions, no branch
// per channel.)
inline bool all_finite(const Color4& c) {
    const float zero = (c.x - c.x) + (c.y - c.y) + (c.z - c.z) + (c.w - c.w);
    return zero == zero;
}

float srgb_to_linear(float encoded);
float linear_to_srgb(float linear);

// Decoding table for 8-bit sRGB texels: srgb8_to_linear_table()[byte] is the linear value.
const float* srgb8_to_linear_table();

// Linear [0, 1] to an 8-bit sRGB byte, rounded to nearest; values outside [0, 1] clamp.
// Through a table of 2^16 linear steps (see color.cpp); a loop over many values takes
// the table once and calls the inline form.
std::uint8_t linear_to_srgb8(float linear);
const std::uint8_t* linear_to_srgb8_table();
inline std::uint8_t linear_to_srgb8(float linear, const std::uint8_t* table) {
    if (!(linear > 0.0f)) return 0;  // also maps NaN to black
    if (linear >= 1.0f) return 255;
    return table[std::size_t(linear * 65535.0f + 0.5f)];
}

}  // namespace texr
