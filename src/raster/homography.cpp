// Triangle parameterization: M^-1 = U * diag(1/w) * adj(S) (see the header).
#include "texr/raster/homography.h"

#include <cmath>
#include <glm/matrix.hpp>

namespace texr {

std::array<Plane, 3> barycentric_planes(const std::array<glm::dvec2, 3>& s) {
    // Row i of adj(S) is the edge function of the edge opposite vertex i:
    //   lambda_0 * det = (y1 - y2) x + (x2 - x1) y + (x1 y2 - x2 y1), and cyclically.
    const double det = (s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y);
    const double inv_det = 1.0 / det;  // one division per triangle, not nine
    std::array<Plane, 3> planes;
    for (int i = 0; i < 3; ++i) {
        const glm::dvec2& a = s[(i + 1) % 3];
        const glm::dvec2& b = s[(i + 2) % 3];
        planes[i] = {(a.y - b.y) * inv_det, (b.x - a.x) * inv_det, (a.x * b.y - b.x * a.y) * inv_det};
    }
    return planes;
}

Plane over_w_plane(const std::array<Plane, 3>& barycentric, const std::array<double, 3>& value,
                   const std::array<double, 3>& inv_w) {
    Plane p{0.0, 0.0, 0.0};
    for (int i = 0; i < 3; ++i) {
        const double k = value[i] * inv_w[i];
        p.dx += k * barycentric[i].dx;
        p.dy += k * barycentric[i].dy;
        p.c += k * barycentric[i].c;
    }
    return p;
}

TextureHomography texture_homography(const std::array<glm::dvec2, 3>& screen,
                                     const std::array<double, 3>& inv_w,
                                     const std::array<glm::dvec2, 3>& uv) {
    const auto lambda = barycentric_planes(screen);
    TextureHomography h;
    h.u_prime = over_w_plane(lambda, {uv[0].x, uv[1].x, uv[2].x}, inv_w);
    h.v_prime = over_w_plane(lambda, {uv[0].y, uv[1].y, uv[2].y}, inv_w);
    h.q = over_w_plane(lambda, {1.0, 1.0, 1.0}, inv_w);
    return h;
}

glm::dmat3 TextureHomography::inverse() const {
    // glm is column-major: m[column][row].
    glm::dmat3 m;
    const Plane rows[3] = {u_prime, v_prime, q};
    for (int r = 0; r < 3; ++r) {
        m[0][r] = rows[r].dx;
        m[1][r] = rows[r].dy;
        m[2][r] = rows[r].c;
    }
    return m;
}

std::optional<glm::dmat3> TextureHomography::forward() const {
    const glm::dmat3 m = inverse();
    const double det = glm::determinant(m);
    // Relative test: collinear UVs make M^-1 singular up to rounding.
    double scale = 0.0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) scale = std::max(scale, std::fabs(m[c][r]));
    if (!(std::fabs(det) > 1e-12 * scale * scale * scale)) return std::nullopt;
    return glm::inverse(m);
}

}  // namespace texr
