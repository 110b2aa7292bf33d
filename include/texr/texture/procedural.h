// Procedural textures, as the lecture's "Procedural Textures" part gives them: the 2D and 3D
// checkerboard, tile, brick, Perlin's gradient noise, turbulence and marble. A procedural
// texture is a function evaluated at each pixel's texture coordinates (u, v, 0), or, with
// `solid`, at its world position (x, y, z): a solid texture, carved out of a 3D pattern.
// It has no texels, so no reconstruction filter, wrap mode or mip levels; turbulence is
// band-limited by the pixel's footprint instead (the lecture's "until period < 2 pixels").
#pragma once
#include <string>

#include <glm/vec3.hpp>

#include "texr/core/color.h"

namespace texr {

enum class Pattern { checker, tile, brick, noise, turbulence, marble };
constexpr int pattern_count = 6;
const char* pattern_name(Pattern p);
// Whether the pattern is band-limited by the pixel's footprint (noise, turbulence, marble):
// the others are point-sampled and need no derivatives.
inline bool band_limited(Pattern p) { return p == Pattern::noise || p == Pattern::turbulence || p == Pattern::marble; }

struct Procedural {
    Pattern pattern = Pattern::checker;
    // Pattern coordinates are scale times the texture coordinates (or the world position):
    // a checker of scale 8 has 8 squares along a unit of u.
    double scale = 1.0;
    // Linear colours (the scene gives them in sRGB): checker's parity 0 and 1; tile's and
    // brick's tile (color0) and mortar (color1); the ends that noise, turbulence and marble
    // blend between.
    Color color0{0.0f}, color1{1.0f};  // (a scene's defaults: sRGB 0.1 and 0.9 greys)
    double mortar = 0.1;  // tile, brick: the mortar's width, a fraction of a cell
    int octaves = 8;      // turbulence, marble: the most octaves summed (the footprint may allow fewer)
    double amplitude = 1.0;  // marble: the turbulence's weight in sin(x + amplitude turbulence)
    bool solid = false;      // evaluated at the world position instead of (u, v, 0)
};

// Perlin's gradient noise (the "improved" form of 2002): a gradient from the 12 directions to
// the edges' midpoints of a cube at every integer lattice point, chosen by hashing the point
// through a fixed permutation of 0..255 (texr's own, made from a fixed seed: every build and
// run gives the same noise); the value is the blend of the eight corners' g . (p - corner)
// with weights fade(t) = 6t^5 - 15t^4 + 10t^3, whose first and second derivatives are 0 at
// the lattice points. It is 0 at every lattice point, repeats every 256 units along each
// axis, and stays within about [-1, 1]. Not finite: 0.
double gradient_noise(const glm::dvec3& p);
// The gradient at lattice point (i, j, k) (any integers: taken modulo 256).
glm::dvec3 lattice_gradient(long long i, long long j, long long k);
// 6t^5 - 15t^4 + 10t^3.
double fade(double t);

// How many octaves turbulence sums for a pixel whose footprint is `footprint` pattern units
// wide (0: unknown, or a point): octave i (frequency 2^i, period 2^-i) is kept while its period
// is at least 2 footprints, so the count is log2(1 / (2 footprint)) + 1, from 0 (even the
// first octave is finer than the pixel) to `most`. The fraction is kept: the last octave is
// weighted by it, so that the sum does not jump where the count changes (a hard cut would
// draw a seam across a receding plane).
double turbulence_octaves(double footprint, int most);

// The mean of |noise| over the plane z = 0, where 2D textures evaluate it at (u, v, 0), and
// over space, where solid textures do: measured over 4M points (a test checks both).
constexpr double mean_abs_noise_2d = 0.2077, mean_abs_noise_3d = 0.2244;

// The lecture's turbulence, the sum over octaves i < most of |noise(2^i p)| / 2^i, of which
// the first `octaves` are evaluated (the last of them weighted by its fraction) and the rest,
// finer than the pixel, are replaced by their mean, mean_abs / 2^i: what a pixel's average of
// them tends to. (Left out, as the lecture's truncation leaves them, they would darken the
// far, band-limited part of the texture against the nearer part: the sum of |noise| has no
// zero mean. On a receding plane at 640x480 against its 8x8 supersampled ground truth,
// whole-frame PSNR: turbulence 39.90 dB, against 34.44 dB with every octave at every pixel;
// marble 32.18 dB, against 31.25 dB with every octave and 28.69 dB with the octaves finer
// than the pixel left out and at least one kept.)
double turbulence(const glm::dvec3& p, double octaves, int most, double mean_abs);

// The texture's value (linear RGB, alpha 1) at texture coordinates or world position
// `coordinates` (before `scale`), for a pixel `footprint` units wide in the same units.
Color4 procedural_value(const Procedural& p, const glm::dvec3& coordinates, double footprint);

// The steps of procedural_value for texr explain: the pattern coordinates, the lattice cell,
// parity or fractions, the noise or the octaves summed, the blend, and the value.
std::string procedural_steps(const Procedural& p, const glm::dvec3& coordinates, double footprint);

}  // namespace texr
