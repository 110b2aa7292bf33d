// The frame being rendered: linear RGB colour and a depth buffer, row 0 at the top.
#pragma once
#include <vector>

#include "texr/core/color.h"

namespace texr {

struct Framebuffer {
    int width = 0, height = 0;
    std::vector<Color> color;  // linear RGB
    std::vector<float> depth;  // window depth in [0, 1]; 1 is the far plane

    Framebuffer(int w, int h, Color background)
        : width(w), height(h), color(std::size_t(w) * std::size_t(h), background),
          depth(std::size_t(w) * std::size_t(h), 1.0f) {}

    std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(width) + std::size_t(x); }
};

}  // namespace texr
