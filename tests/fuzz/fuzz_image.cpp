// libFuzzer target: arbitrary bytes as an image file. Loading must either succeed or throw
// InputError; a loaded image of at most 2^20 texels gets its mip levels built and every
// level's texels must be finite (the sanitizers watch the decoder and the downsampling).
// Not run by `./build.sh test`: a find inside stb_image would fail CI for a bug texr cannot
// mend at its root (see README, "Quick start", on fuzzing image loading). Run it with `./build.sh fuzz-images`.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>

#include <unistd.h>

#include "texr/core/error.h"
#include "texr/texture/image.h"
#include "texr/texture/mipmap.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // load_image reads a path: one scratch file per fuzzing process, removed after each input,
    // in TEXR_FUZZ_SCRATCH (./build.sh sets a folder it removes, also after a crash) or /tmp.
    static const std::string path = [] {
        const char* folder = std::getenv("TEXR_FUZZ_SCRATCH");
        return std::string(folder && *folder ? folder : "/tmp") + "/texr-fuzz-image-" + std::to_string(getpid());
    }();
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), std::streamsize(size));
    struct Removed {
        ~Removed() { std::remove(path.c_str()); }
    } removed;
    try {
        // The first byte's low bit picks the colour space, as a scene's texture line would.
        const auto space = size > 0 && (data[0] & 1) ? texr::ColorSpace::linear : texr::ColorSpace::srgb;
        auto image = std::make_shared<const texr::Image>(texr::load_image(path, space));
        if (double(image->width()) * image->height() > double(1 << 20)) return 0;
        const texr::MipMap mips(image);
        for (int l = 0; l < mips.level_count(); ++l) {
            const texr::Image& level = mips.level(l);
            for (int j = 0; j < level.height(); ++j)
                for (int i = 0; i < level.width(); ++i) {
                    const texr::Color4 c = level.texel(i, j);
                    for (int k = 0; k < 4; ++k)
                        if (!std::isfinite(c[k])) __builtin_trap();
                }
        }
    } catch (const texr::InputError&) {
        // A file texr cannot read is expected; it must be reported, not crash.
    }
    return 0;
}
