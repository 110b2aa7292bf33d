// Wrap modes (lecture, "Wrap Mode" slides): what a texture coordinate outside [0, 1] means.
// Two forms of each mode:
//  - wrap_*(u): the slides' functions on a texture coordinate, returning t in [0, 1];
//  - wrap_*_index(i, n): the same rule on an integer texel index (OpenGL's results), used by
//    the filters once a coordinate is on the texel lattice.
// Large coordinates: u arrives as a double. For repeat and mirror the lattice coordinate is
// reduced by whole periods *in double* (reduce_lattice) before it is converted to int, so
// |u| up to 1e7 on a 16384-texel image (1.6e11 texels) neither overflows an int nor loses
// the fraction (a double has 53 bits, leaving 16 bits of sub-texel precision at 1.6e11).
#pragma once
#include <algorithm>
#include <cmath>

namespace texr {

enum class Wrap { repeat, mirror, clamp, border };

// --- the slides' coordinate form -------------------------------------------------------
inline double wrap_repeat(double u) { return u - std::floor(u); }

inline double wrap_mirror(double u) {
    const double lattice = std::floor(u);
    const double t = u - lattice;
    const bool odd = std::fmod(std::fabs(lattice), 2.0) == 1.0;  // exact for integral doubles
    return odd ? 1.0 - t : t;
}

inline double wrap_clamp(double u) { return u < 0.0 ? 0.0 : (u > 1.0 ? 1.0 : u); }

// Border: true when u lies outside [0, 1] and the border colour is to be returned.
inline bool outside_border(double u) { return u < 0.0 || u > 1.0; }

// --- integer texel index form (n texels along the axis) ---------------------------------
inline int floor_mod(int i, int n) {
    const int r = i % n;
    return r < 0 ? r + n : r;
}
inline int wrap_repeat_index(int i, int n) { return floor_mod(i, n); }
inline int wrap_mirror_index(int i, int n) {  // ... 1 0 | 0 1 ... n-1 | n-1 ... 0 | 0 1 ...
    const int k = floor_mod(i, 2 * n);
    return k < n ? k : 2 * n - 1 - k;
}
inline int wrap_clamp_index(int i, int n) { return std::clamp(i, 0, n - 1); }
// Border: -1 marks "use the border colour".
inline int wrap_border_index(int i, int n) { return (i < 0 || i >= n) ? -1 : i; }

inline int wrap_index(Wrap mode, int i, int n) {
    switch (mode) {
        case Wrap::repeat: return wrap_repeat_index(i, n);
        case Wrap::mirror: return wrap_mirror_index(i, n);
        case Wrap::clamp: return wrap_clamp_index(i, n);
        case Wrap::border: return wrap_border_index(i, n);
    }
    return 0;
}

// Brings a lattice coordinate x (in texels) into a small range that the mode treats the
// same: whole periods (n texels for repeat, 2n for mirror) are removed; for clamp and
// border everything beyond two texels outside the image behaves like two texels outside.
inline double reduce_lattice(Wrap mode, double x, int n) {
    switch (mode) {
        case Wrap::repeat: return x - double(n) * std::floor(x / double(n));
        case Wrap::mirror: return x - 2.0 * double(n) * std::floor(x / (2.0 * double(n)));
        case Wrap::clamp:
        case Wrap::border: return std::clamp(x, -2.0, double(n) + 2.0);
    }
    return x;
}

}  // namespace texr
