// Sutherland-Hodgman clipping of a triangle in homogeneous clip space (see the header).
#include "texr/raster/clip.h"

#include <algorithm>

namespace texr {

GuardBand guard_band_for(int width, int height) {
    // Screen x = (ndc + 1) / 2 * width: |ndc| <= g keeps |x - width/2| <= g * width / 2.
    const double reach = 16384.0;  // pixels from the viewport centre
    return {std::max(1.0, 2.0 * reach / std::max(width, 1)),
            std::max(1.0, 2.0 * reach / std::max(height, 1))};
}

namespace {

constexpr int plane_count = 6;

double plane_distance(int plane, const glm::dvec4& p, const GuardBand& band) {
    switch (plane) {
        case 0: return p.z + p.w;             // near
        case 1: return p.w - p.z;             // far
        case 2: return band.x * p.w + p.x;    // left
        case 3: return band.x * p.w - p.x;    // right
        case 4: return band.y * p.w + p.y;    // bottom
        default: return band.y * p.w - p.y;   // top
    }
}

// One Sutherland-Hodgman pass: keep the part of `in` where plane_distance >= 0.
void clip_against(int plane, const GuardBand& band, const ClipPolygon& in, ClipPolygon& out) {
    out.count = 0;
    for (int i = 0; i < in.count; ++i) {
        const ClipVertex& a = in.vertices[i];
        const ClipVertex& b = in.vertices[(i + 1) % in.count];
        const double da = plane_distance(plane, a.position, band);
        const double db = plane_distance(plane, b.position, band);
        // Each pass adds at most one vertex in exact arithmetic; the cap keeps rounding on a
        // nearly degenerate polygon from ever writing past the array. It counts what this
        // edge writes (a, the crossing, or both): a cap of 2 for every edge dropped the last
        // corner of a triangle that all six planes cut, 9 corners (found in review: a sliver
        // of about 3 pixels along the frame's edge went missing).
        const int writes = int(da >= 0.0) + int((da >= 0.0) != (db >= 0.0));
        if (out.count + writes > ClipPolygon::max_vertices) break;
        if (da >= 0.0) out.vertices[out.count++] = a;
        if ((da >= 0.0) != (db >= 0.0)) {
            // The crossing point, computed from the inside vertex towards the outside one
            // so that the same edge clipped from either triangle gives the same point.
            const bool a_inside = da >= 0.0;
            const ClipVertex& from = a_inside ? a : b;
            const ClipVertex& to = a_inside ? b : a;
            const double d_from = a_inside ? da : db, d_to = a_inside ? db : da;
            const double t = d_from / (d_from - d_to);
            ClipVertex v;
            v.position = from.position + t * (to.position - from.position);
            v.weights = from.weights + t * (to.weights - from.weights);
            out.vertices[out.count++] = v;
        }
    }
}

}  // namespace

int clip_outcode(const glm::dvec4& p, const GuardBand& band) {
    int mask = 0;
    for (int k = 0; k < plane_count; ++k)
        if (!(plane_distance(k, p, band) >= 0.0)) mask |= 1 << k;
    return mask;
}

ClipResult clip_triangle(const glm::dvec4& a, const glm::dvec4& b, const glm::dvec4& c,
                         const GuardBand& band, ClipPolygon& polygon) {
    const glm::dvec4 p[3] = {a, b, c};
    int outside_mask_all = (1 << plane_count) - 1, outside_mask_any = 0;
    for (const auto& v : p) {
        const int mask = clip_outcode(v, band);
        outside_mask_all &= mask;
        outside_mask_any |= mask;
    }
    polygon.count = 3;
    for (int i = 0; i < 3; ++i) {
        polygon.vertices[i].position = p[i];
        polygon.vertices[i].weights = glm::dvec3(i == 0, i == 1, i == 2);
    }
    if (outside_mask_all) return ClipResult::outside;  // all three beyond one plane
    if (!outside_mask_any) return ClipResult::inside;

    ClipPolygon scratch;
    ClipPolygon* in = &polygon;
    ClipPolygon* out = &scratch;
    for (int k = 0; k < plane_count; ++k) {
        if (!(outside_mask_any & (1 << k))) continue;
        clip_against(k, band, *in, *out);
        std::swap(in, out);
        if (in->count < 3) return ClipResult::outside;
    }
    if (in != &polygon) polygon = *in;
    return ClipResult::clipped;
}

}  // namespace texr
