// Wrap modes (lecture, "Wrap Mode" slides): what a texture coordinate outside [0, 1] means.
// Two forms of each mode:
//  - wrap_*(u): the slides' functions on a texture coordinate, returning t in [0, 1];
//  - wrap_*_index(i, n): the same rule on an integer texel index (OpenGL's results), used by
//    the filters once a coordinate is on the texel lattice.
// Large coordinates: u arrives as a double. The lattice coordinate is split into whole
// texels (a 64-bit integer, from which repeat and mirror remove whole periods exactly) and
// the fraction (split_lattice), so |u| up to 1e7 on a 16384-texel image (1.6e11 texels)
// neither overflows an int nor loses the fraction (a double has 53 bits, leaving 15 bits of
// sub-texel precision at 1.6e11, which lies between 2^37 and 2^38).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace texr {

enum class Wrap { repeat, mirror, clamp, border };

// --- the slides' coordinate form -------------------------------------------------------
inline double wrap_repeat(double u) { return u - std::floor(u); }

// The slide tests the period's parity with l_u % 2 == 1, which in C is false for odd
// negative l_u (-1 % 2 is -1), so its periods [-1, 0), [-3, -2), ... would repeat; texr
// mirrors every odd period, as OpenGL's mirrored repeat does, by the parity of |l_u|.
inline double wrap_mirror(double u) {
    const double lattice = std::floor(u);
    const double t = u - lattice;
    const bool odd = std::fmod(std::fabs(lattice), 2.0) == 1.0;  // exact for integral doubles
    return odd ? 1.0 - t : t;
}

inline double wrap_clamp(double u) { return u < 0.0 ? 0.0 : (u > 1.0 ? 1.0 : u); }

// Border: true when u lies outside [0, 1] and the border colour is to be returned (the
// slide's test; NaN is nowhere inside, so it too reads the border colour). The samplers
// apply it with node registration (reconstruct.h).
inline bool outside_border(double u) { return !(u >= 0.0 && u <= 1.0); }

// --- integer texel index form (n texels along the axis) ---------------------------------
inline int floor_mod(int i, int n) {
    if (unsigned(i) < unsigned(n)) return i;  // already in [0, n): the usual case, with no divide
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

// Node registration (texel i at u = i / (n - 1)) repeats every n - 1 texels: the node at
// u = 1 is both texel n - 1 of one period and texel 0 of the next, and with repeat a
// coordinate exactly on it reads texel 0 (the two are equal in a tileable image). Indices inside the image stay as they
// are; outside it, repeat takes them modulo n - 1 and mirror reflects at 0 and n - 1.
inline int wrap_node_index(Wrap mode, int i, int n) {
    if (i >= 0 && i < n) return i;
    if (n == 1) return mode == Wrap::border ? -1 : 0;
    const int period = n - 1;
    switch (mode) {
        case Wrap::repeat: return floor_mod(i, period);
        case Wrap::mirror: {
            const int k = floor_mod(i, 2 * period);
            return k <= period ? k : 2 * period - k;
        }
        case Wrap::clamp: return wrap_clamp_index(i, n);
        case Wrap::border: return -1;
    }
    return 0;
}

// `node`: the sampler uses node registration (see sampler.h). Every mode leaves an index
// inside the image as it is: that, the usual case, is answered first.
inline int wrap_index(Wrap mode, int i, int n, bool node = false) {
    if (unsigned(i) < unsigned(n)) return i;
    if (node) return wrap_node_index(mode, i, n);
    switch (mode) {
        case Wrap::repeat: return wrap_repeat_index(i, n);
        case Wrap::mirror: return wrap_mirror_index(i, n);
        case Wrap::clamp: return wrap_clamp_index(i, n);
        case Wrap::border: return wrap_border_index(i, n);
    }
    return 0;
}

// floor() for |x| < 2^62 without a library call (x86-64's baseline has no rounding opcode),
// as a 64-bit integer and as a double.
inline std::int64_t floor_to_int64(double x) {
    const std::int64_t t = static_cast<std::int64_t>(x);
    return t - (double(t) > x);
}
inline double fast_floor(double x) { return double(floor_to_int64(x)); }

// A lattice coordinate x (in texels) as whole texels and a fraction, x = whole + f with
// f = x - floor(x) in [0, 1): exact for |x| < 2^52, as x - floor(x) needs no rounding there.
// The whole part is brought into a small range that the mode treats the same, in integers:
// for repeat and mirror, whole periods (p = n texels for repeat, 2n for mirror; n - 1 and
// 2(n - 1) with node registration) are removed, so |u| up to 1e7 on a 16384-texel image
// (1.6e11 texels) neither overflows an int nor loses the fraction; for clamp and border,
// everything beyond two texels outside the image behaves like two texels outside.
// (Removing periods from x itself, in double, would round x + p for x just below 0 to the
// precision of p, and could land on the next texel.) Repeat and mirror coordinates beyond
// 1e15 texels, NaN included, carry no fraction any more and are read as 0; NaN reads as 0
// with clamp, and as outside the image with border (as node registration's border test).
struct LatticePoint {
    std::int64_t whole;  // within [-2, n + 2] for clamp and border, [0, period) otherwise
    double fraction;
};

// inv_n = 1 / n (the caller keeps it, so that cell registration needs no division per lookup;
// node registration divides by n - 1).
inline LatticePoint split_lattice(Wrap mode, double x, int n, double inv_n, bool node = false) {
    if (mode == Wrap::clamp || mode == Wrap::border) {
        if (!(x == x)) return {mode == Wrap::border ? -2 : 0, 0.0};  // NaN: outside [0, 1] for border
        x = std::clamp(x, -2.0, double(n) + 2.0);
        const std::int64_t whole = floor_to_int64(x);
        return {whole, x - double(whole)};
    }
    if (!(std::fabs(x) < 1e15)) return {0, 0.0};
    const std::int64_t whole = floor_to_int64(x);
    const std::int64_t p = node ? std::max(1, n - 1) : n;
    const std::int64_t period = mode == Wrap::repeat ? p : 2 * p;
    std::int64_t reduced = whole;
    if (!(reduced >= 0 && reduced < period)) {
        // The quotient whole / period from a product in double (|whole| < 2^50: it is at most
        // one off), the remainder in integers (exact), then put into [0, period).
        const double inv_p = node ? 1.0 / double(p) : inv_n;
        const double inv_period = mode == Wrap::repeat ? inv_p : 0.5 * inv_p;
        reduced = whole - period * floor_to_int64(double(whole) * inv_period);
        if (reduced < 0) reduced += period;
        else if (reduced >= period) reduced -= period;
    }
    return {reduced, x - double(whole)};
}
inline LatticePoint split_lattice(Wrap mode, double x, int n, bool node = false) {
    return split_lattice(mode, x, n, 1.0 / n, node);
}

}  // namespace texr
