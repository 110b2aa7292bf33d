// Ways to compute (u, v) along a span, from exact to plainly wrong, for trading run time
// against error (texr bench spans):
//   exact        u = u'(x) / q(x) from the plane equations at every pixel (a divide each)
//   incremental  the lecture's stepping: u' += du'/dx, q += dq/dx, a divide each
//   affine8/16/32  exact at every 8th/16th/32nd pixel and at the span's end, linear in
//                between: one divide per sub-span (the classic perspective texture mapper)
//   affine       no perspective at all: u interpolated linearly in screen space over the
//                triangle. Wrong; kept for contrast
//   adaptive     sub-spans as long as the error bound below allows, at most `tolerance`
//                texels (default 1/64)
// The adaptive bound: along a row u(x) = u'(x)/q(x) with u' and q linear in x, so
//   u'' = -2 (dq/dx) K / q^3,   K = (du'/dx) q - u' (dq/dx),
// and K is constant along the row (its x derivative cancels). Linear interpolation between exact values L pixels apart
// errs by at most L^2 / 8 * max|u''|, and max|u''| is where q is smallest. The span is walked
// in the direction in which q grows, so that is each sub-span's start and L follows in closed
// form. Measured in texels (u times the texture width, v times its height), L is chosen so
// that bound stays <= tolerance. Where it allows fewer than 16 pixels (near a horizon), the
// next 32 pixels are stepped as in the incremental mode, a divide each; so are they where
// the bound cannot be worked out (its products overflow, at |u'| near 1e308).
#pragma once
#include <cmath>
#include <string>

#include "texr/raster/homography.h"

namespace texr {

enum class SpanMode { exact, incremental, affine8, affine16, affine32, affine, adaptive };
constexpr int span_mode_count = 7;

const char* span_mode_name(SpanMode mode);
bool parse_span_mode(const std::string& name, SpanMode& out);

struct SpanTexturing {
    const TextureHomography* h = nullptr;
    Plane u_affine, v_affine;  // for SpanMode::affine only: u, v linear in screen space
    double width = 1, height = 1;    // texture size in texels, to measure error in texels
    double tolerance = 1.0 / 64.0;   // adaptive: the largest error allowed, in texels
};

// A bound on the coordinates a span mode wrote: every |u| written is at most u (1 + 2^-48),
// every |v| at most v (1 + 2^-48); NaN if any of them is NaN. The values a mode computes
// itself are included one by one; those it interpolates between two computed values are
// bounded by the larger of the two, up to a few roundings (span_modes.cpp, linear_between),
// so they need no look. (Where the step between two ends is not finite, the pixels between
// are computed exactly, and included, instead.) This holds for values of normal size: where
// the step between the ends underflows, the values between can be a little larger than the
// bound. Such bounds are below 1e-300, far from any limit they are checked against. The
// span walk checks a span against the texture paths' limits with it, instead of reading
// every pixel's coordinates once more.
struct CoordinateBound {
    double u = 0.0, v = 0.0;
    void include(double a, double b) {
        // A NaN value enters (no comparison with it is true) and then stays.
        if (!(std::fabs(a) <= u) && !std::isnan(u)) u = std::fabs(a);
        if (!(std::fabs(b) <= v) && !std::isnan(v)) v = std::fabs(b);
    }
};

// Texture coordinates of pixels x0 .. x0 + n - 1 of row y (sampled at pixel centres) into
// u[0..n) and v[0..n), and a bound on them into `bound` (which starts at 0, 0). Returns the
// number of divisions it made.
int span_texture_coordinates(SpanMode mode, const SpanTexturing& t, int y, int x0, int n, double* u, double* v,
                             CoordinateBound& bound);

// Whether the adaptive mode steps every pixel of this span: the bound allows fewer than 16
// pixels even where q is largest. The span walk then steps them itself, as in the
// incremental mode, instead of having them computed first (same arithmetic, less traffic).
bool adaptive_steps_whole_span(const SpanTexturing& t, int y, int x0, int n);

}  // namespace texr
