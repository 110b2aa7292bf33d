// libFuzzer target: arbitrary bytes as an OBJ file, loaded through texr's OBJ path and
// rendered at a tiny size. Loading must succeed or throw InputError.
#include <cstdint>
#include <cstdio>
#include <string>
#include <unistd.h>

#include "texr/core/error.h"
#include "texr/render/renderer.h"
#include "texr/scene/obj_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // tinyobjloader reads files: hand it the bytes through a private temporary file.
    static const std::string path = "/tmp/texr-fuzz-" + std::to_string(::getpid()) + ".obj";
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return 0;
    std::fwrite(data, 1, size, f);
    std::fclose(f);
    try {
        texr::Scene scene;
        scene.materials.push_back(texr::Material{});
        scene.meshes.push_back(texr::load_obj(path, [](const texr::ObjMaterialInfo&) { return 0; }));
        scene.objects.push_back(texr::Object{0, glm::dmat4(1.0), false});
        scene.camera.eye = {0.0, 0.0, 5.0};
        texr::RenderOptions options;
        options.width = 24, options.height = 16, options.threads = 1;
        texr::RenderStats stats;
        texr::render(scene, options, stats);
    } catch (const texr::InputError&) {
    }
    std::remove(path.c_str());  // (left behind, one per run, they piled up in /tmp)
    return 0;
}
