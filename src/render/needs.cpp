// Which per-pixel quantities a material needs (see include/texr/render/needs.h).
#include "texr/render/needs.h"

namespace texr {

Needs needs_of(const Material& material, const Scene& scene) {
    Needs needs = 0;
    if (material.texture >= 0) {
        needs |= need_uv;
        if (uses_footprint(scene.textures[std::size_t(material.texture)].sampler.filter)) needs |= need_uv_derivatives;
    }
    if (material.vertex_colors) needs |= need_color;
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
