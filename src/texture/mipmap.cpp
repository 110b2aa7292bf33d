// Mipmap construction by exact box downsampling (see include/texr/texture/mipmap.h).
#include "texr/texture/mipmap.h"

#include <algorithm>
#include <array>
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

namespace {

// Streams one level from `source`, a row at a time: each output row is the weighted sum of
// the (two or three) source rows under its footprint, each of those first reduced along x.
// Only a few rows are held in float, so building the pyramid of an 8192^2 texture needs
// no more memory than the levels themselves.
class RowReducer {
public:
    RowReducer(const Image& source, const std::vector<Footprint>& fx) : source_(source), fx_(fx) {}

    // Source row r reduced along x (cached: neighbouring output rows share source rows).
    const std::vector<Color4>& row(int r) {
        for (Cached& c : cache_)
            if (c.index == r) return c.texels;
        Cached& slot = cache_[next_++ % cache_.size()];
        slot.index = r;
        slot.texels.assign(fx_.size(), Color4(0.0f));
        for (std::size_t i = 0; i < fx_.size(); ++i) {
            const Footprint& f = fx_[i];
            for (std::size_t k = 0; k < f.weights.size(); ++k) slot.texels[i] += f.weights[k] * source_.texel(f.first + int(k), r);
        }
        return slot.texels;
    }

private:
    struct Cached {
        int index = -1;
        std::vector<Color4> texels;
    };
    const Image& source_;
    const std::vector<Footprint>& fx_;
    std::array<Cached, 4> cache_;
    std::size_t next_ = 0;
};

std::uint8_t to_unorm8(float linear) { return std::uint8_t(std::lround(std::clamp(linear, 0.0f, 1.0f) * 255.0f)); }

}  // namespace

Image downsample(const Image& source) {
    const int w = source.width(), h = source.height();
    const int mw = std::max(1, w / 2), mh = std::max(1, h / 2);
    const auto fx = footprints(w, mw), fy = footprints(h, mh);
    RowReducer reducer(source, fx);
    const std::size_t count = std::size_t(mw) * std::size_t(mh);
    std::vector<float> hdr(source.is_hdr() ? count * 4 : 0);
    std::vector<std::uint8_t> ldr(source.is_hdr() ? 0 : count * 4);
    const bool srgb = source.color_space() == ColorSpace::srgb;
    std::vector<Color4> out_row(static_cast<std::size_t>(mw));
    for (int j = 0; j < mh; ++j) {
        std::fill(out_row.begin(), out_row.end(), Color4(0.0f));
        const Footprint& f = fy[std::size_t(j)];
        for (std::size_t k = 0; k < f.weights.size(); ++k) {
            const std::vector<Color4>& r = reducer.row(f.first + int(k));
            for (int i = 0; i < mw; ++i) out_row[std::size_t(i)] += f.weights[k] * r[std::size_t(i)];
        }
        for (int i = 0; i < mw; ++i) {
            const std::size_t p = 4 * (std::size_t(j) * std::size_t(mw) + std::size_t(i));
            const Color4& c = out_row[std::size_t(i)];
            if (source.is_hdr()) {
                for (int ch = 0; ch < 4; ++ch) hdr[p + std::size_t(ch)] = c[ch];
                continue;
            }
            for (int ch = 0; ch < 3; ++ch) ldr[p + std::size_t(ch)] = srgb ? linear_to_srgb8(c[ch]) : to_unorm8(c[ch]);
            ldr[p + 3] = to_unorm8(c[3]);  // alpha is linear
        }
    }
    if (source.is_hdr()) return Image::hdr(mw, mh, std::move(hdr));
    return Image::ldr(mw, mh, source.color_space(), std::move(ldr));
}

int MipMap::count_levels(const Image& base) {
    int levels = 1;
    for (int w = base.width(), h = base.height(); w > 1 || h > 1; w = std::max(1, w / 2), h = std::max(1, h / 2))
        ++levels;
    return levels;
}

void MipMap::build() const {
    std::call_once(once_, [this] {
        const auto start = std::chrono::steady_clock::now();
        const int count = level_count();
        // Built aside and moved in whole: if a level fails (out of memory), nothing partial
        // stays behind for the next attempt.
        std::vector<Image> levels;
        levels.reserve(std::size_t(count - 1));
        for (int l = 1; l < count; ++l) levels.push_back(downsample(l == 1 ? *base_ : levels.back()));
        std::vector<LdrLevel> views;
        if (base_->is_ldr_pow2()) {
            views.push_back(base_->ldr_level());
            for (const Image& level : levels) views.push_back(level.ldr_level());  // (moving keeps the texel storage)
        }
        levels_ = std::move(levels);
        ldr_levels_ = std::move(views);
        build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        built_flag_.store(true, std::memory_order_release);
    });
}

std::size_t MipMap::bytes() const {
    std::size_t total = 0;
    for (const Image& l : levels_) total += l.bytes();
    return total;
}

}  // namespace texr
