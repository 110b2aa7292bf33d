// Mipmap construction: exact box downsampling for cell registration, the mean of the linear
// interpolation for node registration (see include/texr/texture/mipmap.h).
#include "texr/texture/mipmap.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

namespace texr {

namespace {

// The source texels under output texel i's footprint [i n/m, (i+1) n/m): texels first[i] to
// first[i] + count[i] - 1, with weights (the overlap of each, over n/m: they sum to 1)
// weight[i * max_count + k]. Two texels of weight 1/2 each for even n; two or three for odd.
// Node levels (node_footprints) list each tap's source index instead, in `index` (with the
// same stride as `weight`; -1 for the border colour), as wrapping makes them non-consecutive.
struct Footprints {
    std::vector<int> first, count;
    std::vector<float> weight;
    std::vector<int> index;
    int max_count = 0;
};

Footprints footprints(int n, int m) {
    const double scale = double(n) / double(m);
    Footprints f;
    f.max_count = int(std::ceil(scale)) + 1;
    f.first.resize(std::size_t(m)), f.count.resize(std::size_t(m));
    f.weight.assign(std::size_t(m) * std::size_t(f.max_count), 0.0f);
    for (int i = 0; i < m; ++i) {
        const double lo = i * scale, hi = (i + 1) * scale;
        const int first = int(std::floor(lo));
        int k = 0;
        for (int t = first; t < n && t < hi; ++t, ++k) {
            const double overlap = std::min<double>(hi, t + 1) - std::max<double>(lo, t);
            f.weight[std::size_t(i) * std::size_t(f.max_count) + std::size_t(k)] = overlap > 0.0 ? float(overlap / scale) : 0.0f;
        }
        f.first[std::size_t(i)] = first, f.count[std::size_t(i)] = k;
    }
    return f;
}

// The integral of the hat function max(0, 1 - |t|) from -infinity to t.
double hat_integral(double t) {
    if (t <= -1.0) return 0.0;
    if (t <= 0.0) return 0.5 * (t + 1.0) * (t + 1.0);
    if (t < 1.0) return 1.0 - 0.5 * (1.0 - t) * (1.0 - t);
    return 1.0;
}

// Node level of m nodes from n (mipmap.h): node i is the mean of the linear interpolation of
// the source nodes over [lo, hi] = [i r - r/2, i r + r/2] (over [0, n - 1] when m = 1), so
// source node j weighs (H(hi - j) - H(lo - j)) / (hi - lo), H = hat_integral; indices
// beyond the ends go through the wrap mode.
Footprints node_footprints(int n, int m, Wrap wrap) {
    Footprints f;
    const double r = m > 1 ? double(n - 1) / double(m - 1) : 0.0;
    f.max_count = (m > 1 ? int(std::ceil(r)) : n) + 3;
    f.first.assign(std::size_t(m), 0), f.count.resize(std::size_t(m));
    f.weight.assign(std::size_t(m) * std::size_t(f.max_count), 0.0f);
    f.index.assign(f.weight.size(), 0);
    for (int i = 0; i < m; ++i) {
        const double lo = m > 1 ? (i - 0.5) * r : 0.0, hi = m > 1 ? (i + 0.5) * r : double(n - 1);
        const std::size_t at = std::size_t(i) * std::size_t(f.max_count);
        int k = 0;
        if (n == 1) {
            f.weight[at] = 1.0f, k = 1;
        } else {
            // Node j's hat covers (j - 1, j + 1): the taps that touch [lo, hi].
            for (int j = int(std::floor(lo)); j <= int(std::ceil(hi)); ++j) {
                const double weight = (hat_integral(hi - j) - hat_integral(lo - j)) / (hi - lo);
                if (weight <= 0.0) continue;
                f.weight[at + std::size_t(k)] = float(weight);
                f.index[at + std::size_t(k)] = wrap_index(wrap, j, n, true);
                ++k;
            }
        }
        f.count[std::size_t(i)] = k;
    }
    return f;
}

// Streams one level from `source`, a row at a time: each output row is the weighted sum of
// the source rows under its footprint (two or three for box levels, up to four for node
// levels), each of those first decoded to linear RGBA floats and reduced along x. Only a few
// rows are held in float, so building the pyramid of an 8192^2 texture needs no more memory
// than the levels themselves.
class RowReducer {
public:
    RowReducer(const Image& source, const Footprints& fx, const Color4& border)
        : source_(source), fx_(fx), border_{border.x, border.y, border.z, border.w}, decoded_(4 * std::size_t(source.width())) {
        for (Cached& c : cache_) c.texels.resize(4 * fx.first.size());
    }

    // Source row r reduced along x, 4 floats per output texel (cached: for odd heights,
    // neighbouring output rows share a source row).
    const float* row(int r) {
        for (Cached& c : cache_)
            if (c.index == r) return c.texels.data();
        Cached& slot = cache_[next_++ % cache_.size()];
        slot.index = r;
        float* const in = decoded_.data();
        const std::size_t n = 4 * std::size_t(source_.width());
        if (source_.is_hdr()) {
            for (int i = 0; i < source_.width(); ++i) {
                const Color4 c = source_.texel(i, r);
                in[4 * i] = c.x, in[4 * i + 1] = c.y, in[4 * i + 2] = c.z, in[4 * i + 3] = c.w;
            }
        } else {  // as Image::texel decodes: colour through the table, alpha as k / 255
            const LdrLevel l = source_.ldr_level();
            const std::uint8_t* t = l.texels + std::size_t(r) * l.row_bytes;
            for (std::size_t k = 0; k < n; k += 4) {
                in[k] = l.decode[t[k]], in[k + 1] = l.decode[t[k + 1]], in[k + 2] = l.decode[t[k + 2]];
                in[k + 3] = t[k + 3] * (1.0f / 255.0f);
            }
        }
        float* out = slot.texels.data();
        const std::size_t stride = std::size_t(fx_.max_count);
        if (!fx_.index.empty()) {  // node levels: taps by index
            for (std::size_t i = 0; i < fx_.first.size(); ++i, out += 4) {
                float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
                for (std::size_t k = 0; k < std::size_t(fx_.count[i]); ++k) {
                    const int j = fx_.index[i * stride + k];
                    const float* t = j < 0 ? border_ : in + 4 * std::size_t(j);
                    for (int ch = 0; ch < 4; ++ch) sum[ch] += fx_.weight[i * stride + k] * t[ch];
                }
                for (int ch = 0; ch < 4; ++ch) out[ch] = sum[ch];
            }
            return slot.texels.data();
        }
        for (std::size_t i = 0; i < fx_.first.size(); ++i, out += 4) {
            const float* t = in + 4 * std::size_t(fx_.first[i]);
            const float* w = &fx_.weight[i * stride];
            float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
            for (int k = 0; k < fx_.count[i]; ++k, t += 4)
                for (int ch = 0; ch < 4; ++ch) sum[ch] += w[k] * t[ch];
            for (int ch = 0; ch < 4; ++ch) out[ch] = sum[ch];
        }
        return slot.texels.data();
    }

private:
    struct Cached {
        int index = -1;
        std::vector<float> texels;
    };
    const Image& source_;
    const Footprints& fx_;
    float border_[4];
    std::vector<float> decoded_;  // the source row being reduced
    std::array<Cached, 4> cache_;
    std::size_t next_ = 0;
};

// Linear [0, 1] to 0..255, rounded half away from zero (as std::lround, without its call):
// v - floor(v) is exact for v < 2^23. NaN maps to 0.
std::uint8_t to_unorm8(float linear) {
    if (!(linear > 0.0f)) return 0;
    if (linear >= 1.0f) return 255;
    const float v = linear * 255.0f;
    const int k = int(v);
    return std::uint8_t(k + (v - float(k) >= 0.5f ? 1 : 0));
}

// One level of mw x mh texels from `source` through the footprints along x and y.
Image reduce(const Image& source, int mw, int mh, const Footprints& fx, const Footprints& fy, const Color4& border) {
    RowReducer reducer(source, fx, border);
    const std::size_t count = std::size_t(mw) * std::size_t(mh);
    LargeVector<float> hdr(source.is_hdr() ? count * 4 : 0);
    LargeVector<std::uint8_t> ldr(source.is_hdr() ? 0 : count * 4);
    const bool srgb = source.color_space() == ColorSpace::srgb;
    const std::uint8_t* const srgb_table = linear_to_srgb8_table();
    std::vector<float> out_row(4 * std::size_t(mw));
    for (int j = 0; j < mh; ++j) {
        std::fill(out_row.begin(), out_row.end(), 0.0f);
        const std::size_t stride = std::size_t(fy.max_count);
        for (int k = 0; k < fy.count[std::size_t(j)]; ++k) {
            const std::size_t tap = std::size_t(j) * stride + std::size_t(k);
            const float weight = fy.weight[tap];
            float* __restrict out = out_row.data();
            if (!fy.index.empty() && fy.index[tap] < 0) {  // a border row (node levels)
                for (std::size_t i = 0; i < out_row.size(); i += 4) {
                    out[i] += weight * border.x, out[i + 1] += weight * border.y;
                    out[i + 2] += weight * border.z, out[i + 3] += weight * border.w;
                }
                continue;
            }
            const float* __restrict r = reducer.row(fy.index.empty() ? fy.first[std::size_t(j)] + k : fy.index[tap]);
            for (std::size_t i = 0; i < out_row.size(); i += 4) {  // (written out: -O3 does the 4 at once)
                out[i] += weight * r[i], out[i + 1] += weight * r[i + 1];
                out[i + 2] += weight * r[i + 2], out[i + 3] += weight * r[i + 3];
            }
        }
        const std::size_t p = 4 * std::size_t(j) * std::size_t(mw);
        if (source.is_hdr()) {
            std::copy(out_row.begin(), out_row.end(), hdr.begin() + std::ptrdiff_t(p));
            continue;
        }
        for (std::size_t i = 0; i < out_row.size(); i += 4) {
            for (std::size_t ch = 0; ch < 3; ++ch)
                ldr[p + i + ch] = srgb ? linear_to_srgb8(out_row[i + ch], srgb_table) : to_unorm8(out_row[i + ch]);
            ldr[p + i + 3] = to_unorm8(out_row[i + 3]);  // alpha is linear
        }
    }
    if (source.is_hdr()) return Image::hdr(mw, mh, std::move(hdr));
    return Image::ldr(mw, mh, source.color_space(), std::move(ldr));
}

// The size of the level below one of n texels: max(1, floor(n / 2)) cells; floor(n / 2) + 1
// nodes (1 from 2 or fewer), which keeps the spacing 2^l base spacings (mipmap.h).
int next_size(int n, bool node) {
    if (node) return n <= 2 ? 1 : n / 2 + 1;
    return std::max(1, n / 2);
}

}  // namespace

Image downsample(const Image& source) {
    const int w = source.width(), h = source.height();
    const int mw = next_size(w, false), mh = next_size(h, false);
    return reduce(source, mw, mh, footprints(w, mw), footprints(h, mh), Color4(0.0f));
}

Image downsample_nodes(const Image& source, const Sampler& sampler) {
    const int w = source.width(), h = source.height();
    const int mw = next_size(w, true), mh = next_size(h, true);
    return reduce(source, mw, mh, node_footprints(w, mw, sampler.wrap_u), node_footprints(h, mh, sampler.wrap_v),
                  sampler.border);
}

int MipMap::count_levels(const Image& base, bool node) {
    int levels = 1;
    for (int w = base.width(), h = base.height(); w > 1 || h > 1; w = next_size(w, node), h = next_size(h, node))
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
        for (int l = 1; l < count; ++l) {
            const Image& source = l == 1 ? *base_ : levels.back();
            levels.push_back(node_ ? downsample_nodes(source, sampler_) : downsample(source));
        }
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

std::size_t MipMap::decoded_bytes() const {
    std::size_t total = 0;
    if (built()) for (const Image& l : levels_) total += l.decoded_bytes();
    return total;
}

}  // namespace texr
