// Triangle parameterization: M^-1 = U * diag(1/w) * adj(S) (see the header).
#include "texr/raster/homography.h"

#include <cmath>
#include <glm/matrix.hpp>

namespace texr {

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
