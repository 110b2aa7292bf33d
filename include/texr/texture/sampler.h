// How an image texture is read: reconstruction / minification filter, wrap per axis, border
// colour and registration (where texel centres sit in [0, 1]).
//   cell (default, OpenGL): texel i has its centre at (i + 1/2) / n
//   node (the lecture's bilinear slide): texel i sits at i / (n - 1)
#pragma once
#include <string>

#include "texr/core/color.h"
#include "texr/texture/wrap.h"

namespace texr {

enum class Filter {
    nearest,               // one texel (lecture: nearest neighbour)
    bilinear,              // 2x2 texels (lecture: bilinear interpolation)
    bicubic,               // 4x4 texels, Mitchell-Netravali (B, C); Catmull-Rom by default
    nearest_mip_nearest,   // nearest texel of the nearest mip level
    bilinear_mip_nearest,  // bilinear in the nearest mip level
    trilinear,             // bilinear in the two nearest levels, blended
    anisotropic,           // trilinear probes along the footprint's major axis
    ewa,                   // Heckbert's elliptical weighted average, Gaussian weights
};
constexpr int filter_count = 8;

const char* filter_name(Filter f);
// Parses a name as filter_name writes it; returns false if unknown.
bool parse_filter(const std::string& name, Filter& out);
// The filters that look at the pixel's footprint: they need du/dx ... and mip levels.
inline bool uses_footprint(Filter f) { return f >= Filter::nearest_mip_nearest; }

enum class Registration { cell, node };

// Texels per unit of texture coordinate along an axis of n texels, on the lattice the
// registration reads: n cells, or n - 1 spacings between nodes (node registration puts texel
// i at i / (n - 1); a single node counts as 1). Footprints are measured in these units, so
// that one texel per pixel is level of detail 0 in either registration.
inline int lattice_texels(Registration r, int n) { return r == Registration::node ? (n > 1 ? n - 1 : 1) : n; }

struct Sampler {
    Filter filter = Filter::bilinear;
    Wrap wrap_u = Wrap::repeat;
    Wrap wrap_v = Wrap::repeat;
    Color4 border{0.0f, 0.0f, 0.0f, 1.0f};
    Registration registration = Registration::cell;
    float cubic_b = 0.0f, cubic_c = 0.5f;  // Mitchell-Netravali parameters; (0, 1/2) is Catmull-Rom
    bool clamp_overshoot = false;          // bicubic: clamp to the range of the 2x2 nearest texels
    float max_anisotropy = 16.0f;          // anisotropic and EWA: longest/shortest footprint axis

    // The default layout, which the filters read by a shorter path on power-of-two images.
    bool repeats_cells() const {
        return registration == Registration::cell && wrap_u == Wrap::repeat && wrap_v == Wrap::repeat;
    }
};

}  // namespace texr
