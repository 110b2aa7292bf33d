// Mipmap construction by exact box downsampling (see include/texr/texture/mipmap.h).
#include "texr/texture/mipmap.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace texr {

namespace {

// Weights of the source texels under output texel i's footprint [i n/m, (i+1) n/m),
// normalised to sum to 1: (first source texel, weights...).
struct Footprint {
    int first;
    std::vector<float> weights;
};

std::vector<Footprint> footprints(int n, int m) {
    std::vector<Footprint> out(static_cast<std::size_t>(m));
    const double scale = double(n) / double(m);
    for (int i = 0; i < m; ++i) {
        const double lo = i * scale, hi = (i + 1) * scale;
        Footprint& f = out[std::size_t(i)];
        f.first = int(std::floor(lo));
        for (int k = f.first; k < n && k < hi; ++k) {
            const double overlap = std::min<double>(hi, k + 1) - std::max<double>(lo, k);
            if (overlap > 0.0) f.weights.push_back(float(overlap / scale));
            else f.weights.push_back(0.0f);
        }
    }
    return out;
}

}  // namespace

// A level kept in linear float while the pyramid is built, so rounding to 8 bits happens
// once per level and never accumulates down the chain.
struct LinearLevel {
    int width = 0, height = 0;
    std::vector<Color4> texels;
};

namespace {

LinearLevel to_linear(const Image& image) {
    LinearLevel l{image.width(), image.height(), {}};
    l.texels.reserve(std::size_t(l.width) * std::size_t(l.height));
    for (int j = 0; j < l.height; ++j)
        for (int i = 0; i < l.width; ++i) l.texels.push_back(image.texel(i, j));
    return l;
}

LinearLevel downsample_linear(const LinearLevel& source) {
    const int w = source.width, h = source.height;
    const int mw = std::max(1, w / 2), mh = std::max(1, h / 2);
    const auto fx = footprints(w, mw), fy = footprints(h, mh);
    // Separable: rows first (w -> mw), then columns (h -> mh).
    std::vector<Color4> rows(std::size_t(mw) * std::size_t(h));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < mw; ++i) {
            Color4 sum(0.0f);
            const Footprint& f = fx[std::size_t(i)];
            for (std::size_t k = 0; k < f.weights.size(); ++k)
                sum += f.weights[k] * source.texels[std::size_t(j) * std::size_t(w) + std::size_t(f.first) + k];
            rows[std::size_t(j) * std::size_t(mw) + std::size_t(i)] = sum;
        }
    LinearLevel out{mw, mh, std::vector<Color4>(std::size_t(mw) * std::size_t(mh))};
    for (int j = 0; j < mh; ++j)
        for (int i = 0; i < mw; ++i) {
            Color4 sum(0.0f);
            const Footprint& f = fy[std::size_t(j)];
            for (std::size_t k = 0; k < f.weights.size(); ++k)
                sum += f.weights[k] * rows[(std::size_t(f.first) + k) * std::size_t(mw) + std::size_t(i)];
            out.texels[std::size_t(j) * std::size_t(mw) + std::size_t(i)] = sum;
        }
    return out;
}

// Stores a level like `like`: float for HDR, else 8-bit (sRGB-encoded for colour images).
Image encode_like(const LinearLevel& level, const Image& like) {
    if (like.is_hdr()) {
        std::vector<float> texels(level.texels.size() * 4);
        for (std::size_t p = 0; p < level.texels.size(); ++p)
            for (int c = 0; c < 4; ++c) texels[4 * p + std::size_t(c)] = level.texels[p][c];
        return Image::hdr(level.width, level.height, std::move(texels));
    }
    const auto to_byte = [](float linear) { return std::uint8_t(std::lround(std::clamp(linear, 0.0f, 1.0f) * 255.0f)); };
    std::vector<std::uint8_t> texels(level.texels.size() * 4);
    const bool srgb = like.color_space() == ColorSpace::srgb;
    for (std::size_t p = 0; p < level.texels.size(); ++p) {
        for (int c = 0; c < 3; ++c)
            texels[4 * p + std::size_t(c)] = srgb ? linear_to_srgb8(level.texels[p][c]) : to_byte(level.texels[p][c]);
        texels[4 * p + 3] = to_byte(level.texels[p][3]);  // alpha is linear
    }
    return Image::ldr(level.width, level.height, like.color_space(), std::move(texels));
}

}  // namespace

Image downsample(const Image& source) { return encode_like(downsample_linear(to_linear(source)), source); }

int MipMap::level_count() const {
    int levels = 1;
    for (int w = base_->width(), h = base_->height(); w > 1 || h > 1; w = std::max(1, w / 2), h = std::max(1, h / 2))
        ++levels;
    return levels;
}

void MipMap::build() const {
    std::call_once(once_, [this] {
        const auto start = std::chrono::steady_clock::now();
        const int count = level_count();
        levels_.reserve(std::size_t(count - 1));
        LinearLevel level = to_linear(*base_);
        for (int l = 1; l < count; ++l) {
            level = downsample_linear(level);
            levels_.push_back(encode_like(level, *base_));
        }
        build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        built_flag_.store(true);
    });
}

std::size_t MipMap::bytes() const {
    std::size_t total = 0;
    for (const Image& l : levels_) total += l.bytes();
    return total;
}

}  // namespace texr
