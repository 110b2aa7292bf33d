// Triangle parameterization: M^-1 = U * diag(1/w) * adj(S) / det(S) (see the header).
#include "texr/raster/homography.h"

#include <cmath>
#include <limits>
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
    // Collinear UVs make the rows u', v', q of M^-1 linearly dependent. The test is on the rows
    // each divided by its largest entry (D^-1 M^-1, D = diag of those), so that neither the
    // rows' scales nor overflow decide it: with UVs near 1e300 the q row is 1e-300 of the
    // others, and the plain determinant and the old bound scale^3 were both infinite, so UVs
    // that are not collinear read as such. M = (D N)^-1 = N^-1 D^-1: column i of N^-1 over d_i.
    double row_scale[3] = {0.0, 0.0, 0.0};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) row_scale[r] = std::max(row_scale[r], std::fabs(m[c][r]));
    glm::dmat3 normalised = m;
    for (int r = 0; r < 3; ++r) {
        if (!(row_scale[r] > 0.0 && row_scale[r] <= std::numeric_limits<double>::max())) return std::nullopt;
        for (int c = 0; c < 3; ++c) normalised[c][r] /= row_scale[r];
    }
    if (!(std::fabs(glm::determinant(normalised)) > 1e-12)) return std::nullopt;
    glm::dmat3 forward = glm::inverse(normalised);
    for (int c = 0; c < 3; ++c) forward[c] /= row_scale[c];
    return forward;
}

}  // namespace texr
