// Span texture coordinate modes (see include/texr/raster/span_modes.h).
#include "texr/raster/span_modes.h"

#include <algorithm>
#include <cmath>

#include "texr/raster/span_walk.h"

namespace texr {

namespace {

const char* const names[span_mode_count] = {"exact", "incremental", "affine8", "affine16", "affine32", "affine", "adaptive"};

// Exact (u, v) at the centre of pixel x of the row whose centre is yc.
inline void exact_at(const TextureHomography& h, double x, double yc, double& u, double& v) {
    const double inv_q = 1.0 / h.q.at(x + 0.5, yc);
    u = h.u_prime.at(x + 0.5, yc) * inv_q;
    v = h.v_prime.at(x + 0.5, yc) * inv_q;
}

// Fills the pixels from a to b (either order, a != b) linearly between exact values at a
// and b; u[a], v[a] are given (and in `bound`), the exact value at b is added to `bound`.
// The pixels between need not be: with M the larger of |u[a]| and |u[b]|, each is
// u[a] + du k with du = (u[b] - u[a]) (1/L) and 0 < k < L, which is within M after five
// roundings: at most M (1 + 10 2^-53) < M (1 + 2^-48) (CoordinateBound).
// Where the step between the ends is not finite (they differ by more than the largest
// double, |u| above 9e307 on both sides of 0; or an end is infinite or NaN, as where the
// homography itself overflowed), a line between them would be inf or NaN where the exact
// values are not: those pixels are worked out exactly instead (and added to `bound`).
// Returns the divides made.
inline int linear_between(const TextureHomography& h, double yc, int x0, int a, int b, double* u, double* v,
                          CoordinateBound& bound) {
    exact_at(h, double(b), yc, u[b - x0], v[b - x0]);
    bound.include(u[b - x0], v[b - x0]);
    const double inv_length = 1.0 / double(b - a);
    const double ua = u[a - x0], va = v[a - x0];
    const double du = (u[b - x0] - ua) * inv_length, dv = (v[b - x0] - va) * inv_length;
    // The pixels strictly between, in increasing x whichever way the sub-span was walked,
    // each array in a loop of its own: loops the compiler turns into vector instructions.
    const int from = std::min(a, b) + 1, to = std::max(a, b);
    if (!(std::isfinite(du) && std::isfinite(dv))) {
        for (int x = from; x < to; ++x) exact_at(h, double(x), yc, u[x - x0], v[x - x0]), bound.include(u[x - x0], v[x - x0]);
        return 1 + (to - from);
    }
    for (int x = from; x < to; ++x) u[x - x0] = ua + du * double(x - a);
    for (int x = from; x < to; ++x) v[x - x0] = va + dv * double(x - a);
    return 1;
}

int subdivided(const SpanTexturing& t, int length, int y, int x0, int n, double* u, double* v, CoordinateBound& bound) {
    const double yc = y + 0.5;
    exact_at(*t.h, x0, yc, u[0], v[0]);
    bound.include(u[0], v[0]);
    int divides = 1;
    const int last = x0 + n - 1;
    for (int a = x0; a < last;) {
        const int b = std::min(a + length, last);
        divides += linear_between(*t.h, yc, x0, a, b, u, v, bound);
        a = b;
    }
    return divides;
}

// Adaptive sub-spans shorter than stepped_below pixels are not worth sizing: a sub-span
// costs a square root and a divide to size and a divide at its end, while stepping costs a
// divide per pixel, which pipelines. Measured on the grazing square with callgrind: sizing
// down to 2 pixels, then 8 exact pixels, took 88.1M instructions; stepping runs of 32
// pixels wherever the bound allows fewer than 16 took 79.0M (bilinear, incremental 63.2M).
constexpr int stepped_below = 16, stepped_run = 32;

// The bound's curvature along the row whose centre is yc: max |u''| in texels is
// curvature / q^3, with K = (du'/dx) q - u' (dq/dx) constant along the row.
double adaptive_curvature(const SpanTexturing& t, double yc, int x0) {
    const TextureHomography& h = *t.h;
    const double q0 = h.q.at(x0 + 0.5, yc);
    const double k_u = h.u_prime.dx * q0 - h.u_prime.at(x0 + 0.5, yc) * h.q.dx;
    const double k_v = h.v_prime.dx * q0 - h.v_prime.at(x0 + 0.5, yc) * h.q.dx;
    return 2.0 * std::fabs(h.q.dx) * std::max(std::fabs(k_u) * t.width, std::fabs(k_v) * t.height);
}

// The longest sub-span the bound allows from a pixel where q has the value q:
//   L^2 / 8 * curvature / q^3 <= tolerance.
double adaptive_fit(const SpanTexturing& t, double curvature, double q) {
    return std::sqrt(8.0 * t.tolerance * q * q * q / curvature);
}

int adaptive(const SpanTexturing& t, int y, int x0, int n, double* u, double* v, CoordinateBound& bound) {
    const TextureHomography& h = *t.h;
    const double yc = y + 0.5;
    const int last = x0 + n - 1;
    const double curvature = adaptive_curvature(t, yc, x0);
    // Walk the span in the direction in which q grows: then the smallest q of every sub-span
    // is at its start, and the longest allowed length follows in closed form,
    //   L^2 / 8 * curvature / q_start^3 <= tolerance.
    const int direction = h.q.dx >= 0.0 ? 1 : -1;
    const int first = direction > 0 ? x0 : last, end = direction > 0 ? last : x0;
    exact_at(h, first, yc, u[first - x0], v[first - x0]);
    bound.include(u[first - x0], v[first - x0]);
    int divides = 1;
    for (int a = first; a != end;) {
        const int remaining = (end - a) * direction;
        int length = remaining;
        if (curvature > 0.0) {
            const double fit = adaptive_fit(t, curvature, h.q.at(a + 0.5, yc));
            length = fit < double(remaining) ? std::max(1, int(fit)) : std::isnan(fit) ? 1 : remaining;
        } else if (std::isnan(curvature)) {
            length = 1;
        }
        // (A NaN bound, whose products overflowed at |u'| or q^3 near 1e308: stepped.)
        if (length < stepped_below) {
            // Where the bound allows only short sub-spans (near a horizon), sizing them costs
            // more than it saves: take the next pixels as the incremental mode does, stepping
            // u', v' and q from pixel a, with a divide per pixel.
            const int b = a + direction * std::min(remaining, stepped_run);
            SteppedPlane up{h.u_prime.at(a + 0.5, yc), direction * h.u_prime.dx};
            SteppedPlane vp{h.v_prime.at(a + 0.5, yc), direction * h.v_prime.dx};
            SteppedPlane q{h.q.at(a + 0.5, yc), direction * h.q.dx};
            for (int x = a + direction; x != b + direction; x += direction) {
                up.advance(), vp.advance(), q.advance();
                const double inv_q = 1.0 / q.value;
                u[x - x0] = up.value * inv_q, v[x - x0] = vp.value * inv_q;
                bound.include(u[x - x0], v[x - x0]);
            }
            divides += std::abs(b - a);
            a = b;
            continue;
        }
        const int b = a + direction * length;
        divides += linear_between(h, yc, x0, a, b, u, v, bound);
        a = b;
    }
    return divides;
}

}  // namespace

bool adaptive_steps_whole_span(const SpanTexturing& t, int y, int x0, int n) {
    if (n <= 0) return false;
    const double yc = y + 0.5;
    const double curvature = adaptive_curvature(t, yc, x0);
    if (!(curvature > 0.0)) return false;  // straight (or unmeasurable): adaptive() decides
    // q is linear along the span, largest at one end, and the allowed length grows with q.
    const double q_max = std::max(t.h->q.at(x0 + 0.5, yc), t.h->q.at(x0 + n - 0.5, yc));
    return adaptive_fit(t, curvature, q_max) < double(stepped_below);
}

const char* span_mode_name(SpanMode mode) { return names[int(mode)]; }

bool parse_span_mode(const std::string& name, SpanMode& out) {
    for (int i = 0; i < span_mode_count; ++i)
        if (name == names[i]) {
            out = SpanMode(i);
            return true;
        }
    return false;
}

int span_texture_coordinates(SpanMode mode, const SpanTexturing& t, int y, int x0, int n, double* u, double* v,
                             CoordinateBound& bound) {
    if (n <= 0) return 0;  // an empty span
    const TextureHomography& h = *t.h;
    const double yc = y + 0.5;
    switch (mode) {
        case SpanMode::exact:
            for (int k = 0; k < n; ++k) exact_at(h, x0 + k, yc, u[k], v[k]), bound.include(u[k], v[k]);
            return n;
        case SpanMode::incremental: {
            SteppedPlane up = SteppedPlane::start(h.u_prime, x0, y), vp = SteppedPlane::start(h.v_prime, x0, y),
                         q = SteppedPlane::start(h.q, x0, y);
            for (int k = 0; k < n; ++k) {
                const double inv_q = 1.0 / q.value;
                u[k] = up.value * inv_q, v[k] = vp.value * inv_q;
                bound.include(u[k], v[k]);
                up.advance(), vp.advance(), q.advance();
            }
            return n;
        }
        case SpanMode::affine8: return subdivided(t, 8, y, x0, n, u, v, bound);
        case SpanMode::affine16: return subdivided(t, 16, y, x0, n, u, v, bound);
        case SpanMode::affine32: return subdivided(t, 32, y, x0, n, u, v, bound);
        case SpanMode::affine: {
            SteppedPlane au = SteppedPlane::start(t.u_affine, x0, y), av = SteppedPlane::start(t.v_affine, x0, y);
            for (int k = 0; k < n; ++k) u[k] = au.value, v[k] = av.value, bound.include(u[k], v[k]), au.advance(), av.advance();
            return 0;
        }
        case SpanMode::adaptive: return adaptive(t, y, x0, n, u, v, bound);
    }
    return 0;
}

}  // namespace texr
