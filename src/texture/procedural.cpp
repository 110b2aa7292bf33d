// Procedural textures (see include/texr/texture/procedural.h).
#include "texr/texture/procedural.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

namespace texr {

namespace {

// A permutation of 0..255 from a fixed seed (splitmix64 driving a Fisher-Yates shuffle),
// twice over, so that perm[perm[i] + j] needs no second modulo.
const std::array<int, 512>& permutation() {
    static const std::array<int, 512> table = [] {
        std::array<int, 256> p{};
        for (int i = 0; i < 256; ++i) p[std::size_t(i)] = i;
        std::uint64_t state = 0x7465787220706e6fULL;  // "texr pno"
        const auto next = [&state] {
            std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
            z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
            z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
            return z ^ (z >> 31);
        };
        for (int i = 255; i > 0; --i) std::swap(p[std::size_t(i)], p[std::size_t(next() % std::uint64_t(i + 1))]);
        std::array<int, 512> twice{};
        for (int i = 0; i < 512; ++i) twice[std::size_t(i)] = p[std::size_t(i & 255)];
        return twice;
    }();
    return table;
}

// The 12 directions from a cube's centre to its edges' midpoints, four of them twice, so
// that a hash's low 4 bits pick one without the bias of a modulo by 12 (Perlin 2002).
constexpr int gradients[16][3] = {{1, 1, 0}, {-1, 1, 0}, {1, -1, 0}, {-1, -1, 0}, {1, 0, 1},  {-1, 0, 1},
                                  {1, 0, -1}, {-1, 0, -1}, {0, 1, 1}, {0, -1, 1}, {0, 1, -1}, {0, -1, -1},
                                  {1, 1, 0}, {-1, 1, 0}, {0, -1, 1}, {0, -1, -1}};

// floor(x) modulo 256, in 0..255, exact for any finite x (fmod of a double is exact).
int lattice_index(double floor_x) {
    const double m = std::fmod(floor_x, 256.0);
    return int(m < 0.0 ? m + 256.0 : m);
}

int hash(int i, int j, int k) {
    const std::array<int, 512>& p = permutation();
    return p[std::size_t(p[std::size_t(p[std::size_t(i)] + j)] + k)];
}

double dot_gradient(int h, double x, double y, double z) {
    const int* g = gradients[h & 15];
    return g[0] * x + g[1] * y + g[2] * z;
}

double lerp(double t, double a, double b) { return a + t * (b - a); }

Color mix(const Color& a, const Color& b, double t) { return a + float(t) * (b - a); }

double mean_abs(const Procedural& p) { return p.solid ? mean_abs_noise_3d : mean_abs_noise_2d; }

// The lattice cell of pattern coordinates: each floored after a nudge of about 1e-12 of its
// size (and 1e-9 near 0), so that a surface lying on a cell boundary (a floor at y = 1 under
// a solid checker), whose coordinates the renderer works out a rounding error to either side
// of it from pixel to pixel, falls in one cell, not in both at random.
glm::dvec3 cell(const glm::dvec3& c) {
    const auto nudged = [](double x) { return std::floor(x + (1e-9 + 1e-12 * std::fabs(x))); };
    return {nudged(c.x), nudged(c.y), nudged(c.z)};
}

// The checkerboard's parity, (lu + lv (+ lw)) mod 2, from each coordinate's own parity: the
// sum of cells beyond 2^53 would round.
int checker_parity(const glm::dvec3& c, bool solid) {
    const glm::dvec3 l = cell(c);
    const auto odd = [](double x) { return std::fabs(std::fmod(x, 2.0)) == 1.0 ? 1 : 0; };
    return (odd(l.x) + odd(l.y) + (solid ? odd(l.z) : 0)) % 2;
}

// Tile's and brick's fractions fu, fv of the cell (brick: odd rows shifted by half a cell).
glm::dvec2 tile_fractions(const glm::dvec3& c, bool brick) {
    double u = c.x;
    const double row = cell(c).y;
    if (brick) u -= 0.5 * std::fabs(std::fmod(row, 2.0));
    return {u - cell({u, 0.0, 0.0}).x, c.y - row};
}

// Noise's blend (weight noise + 1) / 2, where the weight, the share of its one octave that the
// footprint allows (turbulence_octaves(f, 1)), fades it to its mean, 0, as its period falls
// below 2 footprints.
double noise_blend(const glm::dvec3& c, double f) {
    return std::clamp(0.5 * (std::min(1.0, turbulence_octaves(f, 1)) * gradient_noise(c) + 1.0), 0.0, 1.0);
}

// Marble's sine, averaged over a footprint f wide along x: sin(x) times sin(f/2) / (f/2) (the
// mean of a sine over an interval), taken as 0 from f = 2 pi on, where a pixel spans a whole
// period; 1 for a point.
double sine_filter(double f) {
    if (!(f > 0.0)) return 1.0;
    if (!(f < 2.0 * 3.14159265358979323846)) return 0.0;
    return std::sin(0.5 * f) / (0.5 * f);
}

std::string format(const char* pattern, double a = 0, double b = 0, double c = 0, double d = 0) {
    const int n = std::snprintf(nullptr, 0, pattern, a, b, c, d);
    std::string out(std::size_t(n > 0 ? n : 0) + 1, '\0');
    std::snprintf(out.data(), out.size(), pattern, a, b, c, d);
    out.resize(std::size_t(n > 0 ? n : 0));
    return out;
}

}  // namespace

const char* pattern_name(Pattern p) {
    static const char* const names[pattern_count] = {"checker", "tile", "brick", "noise", "turbulence", "marble"};
    return names[int(p)];
}

double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

glm::dvec3 lattice_gradient(long long i, long long j, long long k) {
    const int* g = gradients[hash(lattice_index(double(i)), lattice_index(double(j)), lattice_index(double(k))) & 15];
    return {double(g[0]), double(g[1]), double(g[2])};
}

double gradient_noise(const glm::dvec3& p) {
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) return 0.0;
    const double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
    const int i = lattice_index(fx), j = lattice_index(fy), k = lattice_index(fz);
    const int i1 = (i + 1) & 255, j1 = (j + 1) & 255, k1 = (k + 1) & 255;
    const double x = p.x - fx, y = p.y - fy, z = p.z - fz;  // in [0, 1)
    const double a = fade(x), b = fade(y), c = fade(z);
    // The eight corners' g . (p - corner), blended along x, then y, then z.
    const double x00 = lerp(a, dot_gradient(hash(i, j, k), x, y, z), dot_gradient(hash(i1, j, k), x - 1, y, z));
    const double x10 = lerp(a, dot_gradient(hash(i, j1, k), x, y - 1, z), dot_gradient(hash(i1, j1, k), x - 1, y - 1, z));
    const double x01 = lerp(a, dot_gradient(hash(i, j, k1), x, y, z - 1), dot_gradient(hash(i1, j, k1), x - 1, y, z - 1));
    const double x11 = lerp(a, dot_gradient(hash(i, j1, k1), x, y - 1, z - 1), dot_gradient(hash(i1, j1, k1), x - 1, y - 1, z - 1));
    return lerp(c, lerp(b, x00, x10), lerp(b, x01, x11));
}

double turbulence_octaves(double footprint, int most) {
    if (!(footprint > 0.0)) return double(most);  // (0 or NaN: no footprint)
    if (!std::isfinite(footprint)) return 0.0;
    // Octave i is kept while 2^-i >= 2 footprint: i <= log2(1 / (2 footprint)).
    const double count = std::log2(1.0 / (2.0 * footprint)) + 1.0;
    return std::min(double(most), std::max(0.0, count));
}

double turbulence(const glm::dvec3& p, double octaves, int most, double mean_abs) {
    double sum = 0.0, frequency = 1.0;
    for (int i = 0; i < most; ++i, frequency *= 2.0) {
        // The share of octave i evaluated: 1, the last one's fraction, or 0 (its mean instead).
        const double weight = std::clamp(octaves - double(i), 0.0, 1.0);
        const double value = weight > 0.0 ? weight * std::fabs(gradient_noise(frequency * p)) : 0.0;
        sum += (value + (1.0 - weight) * mean_abs) / frequency;
    }
    return sum;
}

Color4 procedural_value(const Procedural& p, const glm::dvec3& coordinates, double footprint) {
    const glm::dvec3 c = p.scale * coordinates;
    const double f = p.scale * footprint;
    // (a coordinate beyond a double's range, or NaN: no pattern to evaluate)
    if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z))) return Color4(p.color0, 1.0f);
    Color out = p.color0;
    switch (p.pattern) {
        case Pattern::checker: out = checker_parity(c, p.solid) == 1 ? p.color1 : p.color0; break;
        case Pattern::tile:
        case Pattern::brick: {
            const glm::dvec2 fraction = tile_fractions(c, p.pattern == Pattern::brick);
            out = (fraction.x < p.mortar || fraction.y < p.mortar) ? p.color1 : p.color0;
            break;
        }
        case Pattern::noise: out = mix(p.color0, p.color1, noise_blend(c, f)); break;
        case Pattern::turbulence:
            out = mix(p.color0, p.color1, std::clamp(turbulence(c, turbulence_octaves(f, p.octaves), p.octaves, mean_abs(p)), 0.0, 1.0));
            break;
        case Pattern::marble: {
            const double t = turbulence(c, turbulence_octaves(f, p.octaves), p.octaves, mean_abs(p));
            out = mix(p.color0, p.color1, 0.5 * (1.0 + sine_filter(f) * std::sin(c.x + p.amplitude * t)));
            break;
        }
    }
    return Color4(out, 1.0f);
}

std::string procedural_steps(const Procedural& p, const glm::dvec3& coordinates, double footprint) {
    const glm::dvec3 c = p.scale * coordinates;
    const double f = p.scale * footprint;
    std::string out = format("    pattern coordinates = scale %.6g x ", p.scale) +
                      (p.solid ? "the world position" : "(u, v, 0)") + format(" = (%.6g, %.6g, %.6g)\n", c.x, c.y, c.z);
    if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z))) {
        out += "    (not finite: color0)\n";
    } else {
        switch (p.pattern) {
            case Pattern::checker: {
                const glm::dvec3 l = cell(c);
                out += p.solid ? format("    lattice (lu, lv, lw) = (%.0f, %.0f, %.0f): parity (lu + lv + lw) %% 2 = ", l.x, l.y, l.z)
                               : format("    lattice (lu, lv) = (%.0f, %.0f): parity (lu + lv) %% 2 = ", l.x, l.y);
                out += checker_parity(c, p.solid) == 1 ? "1: color1\n" : "0: color0\n";
                break;
            }
            case Pattern::tile:
            case Pattern::brick: {
                if (p.pattern == Pattern::brick) {
                    const double parity = std::fabs(std::fmod(cell(c).y, 2.0));
                    out += format("    row parity floor(v) %% 2 = %.0f: u - parity/2 = %.6g\n", parity, c.x - 0.5 * parity);
                }
                const glm::dvec2 fraction = tile_fractions(c, p.pattern == Pattern::brick);
                out += format("    fractions fu = %.6g, fv = %.6g against the mortar's width %.6g: ", fraction.x, fraction.y, p.mortar) +
                       (fraction.x < p.mortar || fraction.y < p.mortar ? "mortar (color1)\n" : "tile (color0)\n");
                break;
            }
            case Pattern::noise: {
                const double n = gradient_noise(c), weight = std::min(1.0, turbulence_octaves(f, 1));
                out += format("    gradient noise = %.6g; footprint %.4g pattern units: its weight %.4g (1 while its period is at "
                              "least 2 footprints)\n", n, f, weight) +
                       format("    blend t = (weight x noise + 1) / 2 = %.6g of color0 -> color1\n", noise_blend(c, f));
                break;
            }
            case Pattern::turbulence:
            case Pattern::marble: {
                const double octaves = turbulence_octaves(f, p.octaves);
                out += format("    footprint %.4g pattern units: octaves kept while their period 2^-i >= 2 footprints: %.4g", f, octaves) +
                       format(" (at most %.0f)\n", p.octaves);
                const double t = turbulence(c, octaves, p.octaves, mean_abs(p));
                out += format("    turbulence = sum of |noise(2^i p)| / 2^i = %.6g", t) +
                       (octaves < p.octaves ? format(" (the octaves beyond %.4g by their mean, %.4g / 2^i)\n", octaves, mean_abs(p)) : "\n");
                if (p.pattern == Pattern::turbulence)
                    out += format("    blend t = min(turbulence, 1) = %.6g of color0 -> color1\n", std::clamp(t, 0.0, 1.0));
                else
                    out += format("    blend t = (1 + k sin(x + %.6g turbulence)) / 2 = %.6g of color0 -> color1", p.amplitude,
                                  0.5 * (1.0 + sine_filter(f) * std::sin(c.x + p.amplitude * t))) +
                           format(", k = %.4g (the sine's mean over the footprint)\n", sine_filter(f));
                break;
            }
        }
    }
    const Color4 value = procedural_value(p, coordinates, footprint);
    return out + format("    the pattern's value, linear RGB: (%.5f, %.5f, %.5f)\n", value.x, value.y, value.z);
}

}  // namespace texr
