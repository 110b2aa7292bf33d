// Mipmaps (lecture, "Texture Mapping": integrate over the pixel's pre-image): a pyramid of
// prefiltered copies of an image, level l about 2^l times smaller per side.
// Any size, not only powers of two: level l + 1 has max(1, floor(n / 2)) texels along an
// axis of n, and each of its texels is the exact area-weighted box average of the source
// texels its footprint [i n / m, (i + 1) n / m) overlaps. For even n that is the usual 2x2
// average; for odd n the footprint spans 2 + 1/m texels with fractional weights at its
// ends, so no texel is dropped and every level keeps the base image's mean. The box is the
// filter that preserves the mean exactly and never overshoots; its mild aliasing is what
// trilinear and anisotropic filtering sample between anyway.
// Averaging happens in linear space: each level is built from the one above it, its texels
// decoded to linear float, averaged, and stored again as 8-bit (sRGB-encoded for colour
// images; so each level adds at most half a step of rounding) or, for HDR, as float. The
// build streams a few rows at a time: it needs no memory beyond the levels themselves.
// Levels are built on first use, only for textures that are minified; building is
// thread-safe.
//
// Node registration (sampler.h: texel i at u = i / (n - 1)) has levels of its own: box
// averages sit between the nodes of the level below, so a node lattice would read them up
// to half a level's texel away from where they belong. Level l + 1 has m = floor(n / 2) + 1
// nodes along an axis of n > 2 (and 1 for n <= 2), node i at the source lattice position
// x = i r, r = (n - 1) / (m - 1), the spacing ratio: for odd n, r = 2, every other node
// (2^k + 1 nodes give 2^(k-1) + 1); for even n, r = 2 - 2/n, and the next level has an odd
// size (1024 nodes give 513, 257, ...). So level l's spacing is 2^l base spacings, or
// 2^l (n - 1) / n for even n, as the level of detail, measured in base spacings
// (sampler.h, lattice_texels), assumes (ceil(n / 2) nodes would make the last levels of a
// 1024 texture up to twice as coarse). A node's value is the mean,
// over [x - r/2, x + r/2], of the source level's linear interpolation between nodes: for
// r = 2 the weights 1/4, 1/2, 1/4, for other r up to four weights. The mean of a linear
// function over an interval is its value at the centre, so a linear ramp stays exactly
// where it was on every level, at the nodes whose interval lies within the image (an end
// node's interval reaches past the ends, read as below: under clamp a 9-node ramp
// 0, 31, ..., 255 gives 8, 63, 127, 191, 247). Nodes beyond the ends are read through the
// sampler's wrap mode (repeat every n - 1 nodes, mirror, clamp, or the border colour), so these levels
// belong to one sampler's wrap modes; a level of one node holds the mean of the two-node
// level above it over [0, 1] (the trapezoid rule; for repeat, the period's mean).
#pragma once
#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

#include "texr/texture/image.h"
#include "texr/texture/sampler.h"

namespace texr {

// One box-filtered level below `source`.
Image downsample(const Image& source);
// One node-registered level below `source` (see above), read beyond its ends through
// `sampler`'s wrap modes and border colour.
Image downsample_nodes(const Image& source, const Sampler& sampler);

class MipMap {
public:
    // Levels for cell registration.
    explicit MipMap(std::shared_ptr<const Image> base) : base_(std::move(base)), level_count_(count_levels(*base_, false)) {}
    // Levels for `sampler`'s registration: box levels for cell registration (the same as
    // above), node levels read through its wrap modes for node registration.
    MipMap(std::shared_ptr<const Image> base, const Sampler& sampler)
        : base_(std::move(base)), node_(sampler.registration == Registration::node), sampler_(sampler),
          level_count_(count_levels(*base_, node_)) {}

    const Image& base() const { return *base_; }
    // Level l (0 is the base); builds the pyramid on first call with l > 0.
    const Image& level(int l) const {
        if (l == 0) return *base_;
        if (!built_flag_.load(std::memory_order_acquire)) build();  // once; then only this load
        return levels_[std::size_t(l - 1)];
    }
    // Every level, base first, as the short texture paths read them (image.h); builds the
    // pyramid on first call. Only for a base that is_ldr_pow2() (then so is every level).
    // with_decoded: with the decoded copies of the levels that may have one (Image::
    // decoded_texels), made on the first such call.
    const LdrLevel* ldr_levels(bool with_decoded = false) const {
        if (!built_flag_.load(std::memory_order_acquire)) build();
        if (!with_decoded) return ldr_levels_.data();
        if (!decoded_flag_.load(std::memory_order_acquire))  // once; then only this load
            std::call_once(decoded_once_, [this] {
                std::vector<LdrLevel> views;
                for (int l = 0; l < level_count_; ++l) views.push_back(level(l).ldr_level(true));
                decoded_levels_ = std::move(views);
                decoded_flag_.store(true, std::memory_order_release);
            });
        return decoded_levels_.data();
    }
    // Number of levels including the base (down to 1x1). Does not build them.
    int level_count() const { return level_count_; }
    bool node_levels() const { return node_; }
    bool built() const { return built_flag_.load(); }
    double build_seconds() const { return build_seconds_; }
    std::size_t bytes() const;  // all levels above the base
    std::size_t decoded_bytes() const;  // their decoded copies (Image::decoded_texels), if made
    void build() const;

private:
    static int count_levels(const Image& base, bool node);
    std::shared_ptr<const Image> base_;
    bool node_ = false;
    Sampler sampler_;  // node levels: the wrap modes and border colour they are read with
    int level_count_;
    mutable std::once_flag once_;
    mutable std::vector<Image> levels_;
    mutable std::vector<LdrLevel> ldr_levels_;
    mutable std::once_flag decoded_once_;
    mutable std::vector<LdrLevel> decoded_levels_;
    mutable std::atomic<bool> decoded_flag_{false};
    mutable std::atomic<bool> built_flag_{false};
    mutable double build_seconds_ = 0.0;
};

}  // namespace texr
