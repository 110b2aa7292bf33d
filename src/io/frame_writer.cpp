// PNG (stb_image_write) and PPM frame output, written atomically (see the header).
#include "texr/io/frame_writer.h"

#include <stb_image_write.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <unistd.h>

#include "texr/core/error.h"

namespace texr {

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
    if (s.size() < suffix.size()) return false;
    for (std::size_t i = 0; i < suffix.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) != suffix[i]) return false;
    return true;
}

void append_bytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<std::uint8_t>*>(context);
    const auto* bytes = static_cast<const std::uint8_t*>(data);
    out->insert(out->end(), bytes, bytes + size);
}

}  // namespace

FrameFormat frame_format_for(const std::string& path) {
    if (ends_with(path, ".png")) return FrameFormat::png;
    if (ends_with(path, ".ppm")) return FrameFormat::ppm;
    throw InputError(path, 0, "output file must end in .png or .ppm");
}

std::vector<std::uint8_t> encode_srgb8(const Framebuffer& fb) {
    std::vector<std::uint8_t> rgb(std::size_t(fb.width) * std::size_t(fb.height) * 3);
    const std::uint8_t* table = linear_to_srgb8_table();
    for (std::size_t i = 0; i < fb.color.size(); ++i) {
        const Color& c = fb.color[i];
        rgb[3 * i] = linear_to_srgb8(c.x, table);
        rgb[3 * i + 1] = linear_to_srgb8(c.y, table);
        rgb[3 * i + 2] = linear_to_srgb8(c.z, table);
    }
    return rgb;
}

std::vector<std::uint8_t> encode_frame(const Framebuffer& fb, FrameFormat format) {
    const std::vector<std::uint8_t> rgb = encode_srgb8(fb);
    std::vector<std::uint8_t> out;
    if (format == FrameFormat::ppm) {
        const std::string header = "P6\n" + std::to_string(fb.width) + " " + std::to_string(fb.height) + "\n255\n";
        out.assign(header.begin(), header.end());
        out.insert(out.end(), rgb.begin(), rgb.end());
        return out;
    }
    if (!stbi_write_png_to_func(append_bytes, &out, fb.width, fb.height, 3, rgb.data(), fb.width * 3))
        throw InputError("cannot encode the frame as PNG");
    return out;
}

void write_file_atomically(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    // A short hidden name in the same folder (so that rename replaces the file in one step),
    // whatever the length of the file's own name; numbered, so that writes from several
    // threads of one process never share one.
    static std::atomic<unsigned> writes{0};
    const auto slash = path.find_last_of('/');
    const std::string folder = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
    const std::string temporary = folder + ".texr-" + std::to_string(::getpid()) + "-" + std::to_string(writes++) + ".tmp";
    std::FILE* file = std::fopen(temporary.c_str(), "wb");
    if (!file) throw InputError(path, 0, std::string("cannot write output file: ") + std::strerror(errno));
    const bool written = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
    const bool closed = std::fclose(file) == 0;
    if (!written || !closed) {
        std::remove(temporary.c_str());
        throw InputError(path, 0, "cannot write output file (disk full?)");
    }
    if (std::rename(temporary.c_str(), path.c_str()) != 0) {
        const int error = errno;
        std::remove(temporary.c_str());
        throw InputError(path, 0, std::string("cannot write output file: ") + std::strerror(error));
    }
}

void write_frame(const Framebuffer& fb, const std::string& path) {
    write_file_atomically(path, encode_frame(fb, frame_format_for(path)));
}

}  // namespace texr
