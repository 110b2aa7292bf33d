// The lecture's "Triangle Parameterization" slides: per triangle, the 3x3 homography
//   M:      (u, v, 1)  -> (x', y', w),   (x, y) = (x'/w, y'/w)
//   M^-1:   (x, y, 1)  -> (u', v', q),   (u, v) = (u'/q, v'/q)
// The inverse is computed directly (docs/design.md, "The homography") as
//   M^-1 = U * diag(1/w0, 1/w1, 1/w2) * adj(S) / det(S)
// with S = [x_i; y_i; 1] (screen vertices as columns) and U = [u_i; v_i; 1]. adj(S) * (x, y, 1)
// is det(S) times the screen-space barycentric coordinates, so this needs only a
// non-degenerate *screen* triangle; collinear or coincident UVs still give finite values.
// The divide by det(S) (which cancels in u'/q either way) makes q exactly 1/w.
// Each row of M^-1 is a Plane: u', v', q are linear in x, y with constant derivatives.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "texr/raster/plane.h"

namespace texr {

// Screen-space barycentric planes: lambda_i(x, y) for a triangle with the given screen
// vertices (rows of adj(S) / det(S)). Requires det(S) != 0.
// (Inline: triangle setup calls these for every triangle.)
inline std::array<Plane, 3> barycentric_planes(const std::array<glm::dvec2, 3>& s) {
    // Row i of adj(S) is the edge function of the edge opposite vertex i:
    //   lambda_0 * det = (y1 - y2) x + (x2 - x1) y + (x1 y2 - x2 y1), and cyclically.
    const double det = (s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y);
    const double inv_det = 1.0 / det;  // one division per triangle, not nine
    std::array<Plane, 3> planes;
    for (int i = 0; i < 3; ++i) {
        const glm::dvec2& a = s[std::size_t((i + 1) % 3)];
        const glm::dvec2& b = s[std::size_t((i + 2) % 3)];
        planes[std::size_t(i)] = {(a.y - b.y) * inv_det, (b.x - a.x) * inv_det, (a.x * b.y - b.x * a.y) * inv_det};
    }
    return planes;
}

// A perspective-correct attribute: plane of a/w, from the vertex values a_i and 1/w_i.
// value = plane / q-plane at any pixel.
inline Plane over_w_plane(const std::array<Plane, 3>& barycentric, const std::array<double, 3>& value,
                          const std::array<double, 3>& inv_w) {
    Plane p{0.0, 0.0, 0.0};
    for (std::size_t i = 0; i < 3; ++i) {
        const double k = value[i] * inv_w[i];
        p.dx += k * barycentric[i].dx;
        p.dy += k * barycentric[i].dy;
        p.c += k * barycentric[i].c;
    }
    return p;
}

struct TextureHomography {
    Plane u_prime, v_prime, q;  // rows of M^-1

    // M^-1 as a matrix (rows u', v', q; columns x, y, 1), for teaching output and tests.
    glm::dmat3 inverse() const;
    // The forward M = (M^-1)^-1, only when the UVs are not collinear (M^-1 invertible).
    std::optional<glm::dmat3> forward() const;

    // (u, v) at screen point (x, y).
    glm::dvec2 uv_at(double x, double y) const {
        const double qv = q.at(x, y);
        return {u_prime.at(x, y) / qv, v_prime.at(x, y) / qv};
    }
};

// screen: vertex positions in pixels; inv_w: 1/w_clip per vertex; uv: texture coordinates.
TextureHomography texture_homography(const std::array<glm::dvec2, 3>& screen,
                                     const std::array<double, 3>& inv_w,
                                     const std::array<glm::dvec2, 3>& uv);

// Exact screen-space derivatives by the quotient rule, at a point where u = u'/q, v = v'/q:
//   du/dx = (du'/dx - u * dq/dx) / q   (and likewise for v and for y).
struct UVDerivatives {
    double dudx, dvdx, dudy, dvdy;
};
inline UVDerivatives uv_derivatives_from_inverse_q(const TextureHomography& h, double u, double v, double inv_q) {
    return {(h.u_prime.dx - u * h.q.dx) * inv_q, (h.v_prime.dx - v * h.q.dx) * inv_q,
            (h.u_prime.dy - u * h.q.dy) * inv_q, (h.v_prime.dy - v * h.q.dy) * inv_q};
}
inline UVDerivatives uv_derivatives(const TextureHomography& h, double u, double v, double q) {
    return uv_derivatives_from_inverse_q(h, u, v, 1.0 / q);
}

// A pixel's footprint in (u, v): the longer of |d(u,v)/dx| and |d(u,v)/dy|.
inline double footprint_length(const UVDerivatives& d) {
    return std::max(std::sqrt(d.dudx * d.dudx + d.dvdx * d.dvdx), std::sqrt(d.dudy * d.dudy + d.dvdy * d.dvdy));
}

// The same quotient rule for a vector attribute P = P'/q given by its three planes over w
// (the world position): dP/dx = (dP'/dx - P dq/dx) / q, and likewise for y.
inline void attribute_derivatives(const std::array<Plane, 3>& over_w, const Plane& q, const glm::dvec3& p, double inv_q,
                                  glm::dvec3& dx, glm::dvec3& dy) {
    for (int i = 0; i < 3; ++i) {
        dx[i] = (over_w[std::size_t(i)].dx - p[i] * q.dx) * inv_q;
        dy[i] = (over_w[std::size_t(i)].dy - p[i] * q.dy) * inv_q;
    }
}

}  // namespace texr
