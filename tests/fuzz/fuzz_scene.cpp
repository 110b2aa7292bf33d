// libFuzzer target: arbitrary bytes as a scene file. Parsing must either succeed or throw
// InputError; a parsed scene is rendered at a tiny size and must not crash or write out of
// bounds (the sanitizers watch). Files the scene names are looked up in the corpus folder.
#include <cstdint>
#include <sstream>
#include <string>

#include "texr/core/error.h"
#include "texr/render/renderer.h"
#include "texr/scene/parser.h"

#ifndef TEXR_FUZZ_FOLDER
#define TEXR_FUZZ_FOLDER "."
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    try {
        const texr::Scene scene = texr::parse_scene(in, std::string(TEXR_FUZZ_FOLDER) + "/fuzz.scene");
        texr::RenderOptions options;
        options.width = 24, options.height = 16, options.threads = 1;
        texr::RenderStats stats;
        const texr::Framebuffer fb = texr::render(scene, options, stats);
        for (const auto& c : fb.color)
            if (c.x != c.x || c.y != c.y || c.z != c.z) __builtin_trap();  // NaN in the frame
    } catch (const texr::InputError&) {
        // Bad input is expected; it must be reported, not crash.
    }
    return 0;
}
