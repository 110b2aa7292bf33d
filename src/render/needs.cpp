// Which per-pixel quantities a material needs (see include/texr/render/needs.h).
#include "texr/render/needs.h"

namespace texr {

Needs needs_of(const Material& material, const Scene& scene) {
    Needs needs = 0;
    if (material.texture >= 0) {
        const Texture& t = scene.textures[std::size_t(material.texture)];
        if (material.projector >= 0 || material.mapping.kind != Intermediate::none) {
            // Thrown by a projector: read where it falls on the world position (its footprint
            // from the same planes).
            needs |= need_world_position;
        } else if (t.procedural && t.procedural->solid) {
            // A solid texture reads the world position alone (its footprint comes from the same
            // planes: scanline.h, world_footprint).
            needs |= need_world_position;
        } else if (t.procedural) {
            // Noise, turbulence and marble are band-limited by the footprint.
            needs |= need_uv;
            if (band_limited(t.procedural->pattern)) needs |= need_uv_derivatives;
        } else {
            needs |= need_uv;
            if (uses_footprint(t.sampler.filter)) needs |= need_uv_derivatives;
        }
    }
    if (material.vertex_colors) needs |= need_color;
    if (material.slope) needs |= need_normal;  // (alpha = n . direction)
    if (material.lightmap >= 0) {              // read at (u, v), filtered with their derivatives
        needs |= need_uv;
        if (uses_footprint(scene.textures[std::size_t(material.lightmap)].sampler.filter)) needs |= need_uv_derivatives;
    }
    // A reflection: the view ray from the eye to the surface point, and the normal.
    if (material.reflect > 0.0 && scene.environment >= 0) needs |= need_normal | need_world_position;
    // A bump map: (u, v) to read it and their derivatives (its step is at least the pixel's
    // footprint), the normal it changes, and the corners' world positions, which give the
    // triangle's tangents O_u and O_v (setup_stage.h). It shows in lighting and reflections.
    if (material.bump >= 0 && (material.lighting == Lighting::lambert || (material.reflect > 0.0 && scene.environment >= 0)))
        needs |= need_uv | need_uv_derivatives | need_normal | need_world_position;
    if (material.lighting == Lighting::lambert && !scene.lights.empty()) {
        needs |= need_normal;
        for (const Light& light : scene.lights)
            if (light.kind == Light::Kind::point) needs |= need_world_position;
    }
    return needs;
}

std::string describe(Needs needs) {
    static const char* names[] = {"uv", "uv derivatives", "normal", "vertex colour", "world position"};
    std::string used, skipped;
    for (int i = 0; i < 5; ++i) {
        std::string& list = (needs & (1u << i)) ? used : skipped;
        list += (list.empty() ? "" : ", ") + std::string(names[i]);
    }
    return (used.empty() ? std::string("nothing but depth") : used) + (skipped.empty() ? "" : "; skips " + skipped);
}

}  // namespace texr
