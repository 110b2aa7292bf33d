// Shared pieces of the benchmarks (see src/bench/common.h).
#include "common.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sys/stat.h>

#include "texr/core/error.h"
#include "texr/io/frame_writer.h"
#include "texr/scene/parser.h"

namespace texr::bench {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::vector<bool> covered(const Framebuffer& fb) {
    std::vector<bool> mask(fb.depth.size());
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = fb.drawn(i);
    return mask;
}

Scene load_bench_scene(const BenchOptions& o, const std::string& name) {
    const std::string path = o.models + "/bench/" + name + ".scene";
    Scene scene = load_scene(path);
    for (const Texture& t : scene.textures)
        if (t.procedural)
            throw InputError(path, 0, "texture " + shown_name(t.name) +
                                          " is procedural: texr bench times and scores image textures (their filters and span modes)");
    for (const Object& object : scene.objects)
        for (const int m : scene.meshes[std::size_t(object.mesh)].triangle_material)
            if (scene.materials[std::size_t(m)].texture >= 0) return scene;
    throw InputError(path, 0, "no object of this benchmark scene is drawn with a texture (texr bench times and scores texture filtering)");
}

void make_folders(const std::string& path) {
    if (path.empty()) throw InputError("--out needs a folder name");
    std::string partial;
    for (std::size_t i = 0; i <= path.size(); ++i) {
        if ((i == path.size() || path[i] == '/') && !partial.empty() && ::mkdir(partial.c_str(), 0755) != 0 && errno != EEXIST)
            throw InputError(partial, 0, std::string("cannot make the output folder: ") + std::strerror(errno));
        if (i < path.size()) partial += path[i];
    }
    struct stat info;
    if (::stat(path.c_str(), &info) != 0 || !S_ISDIR(info.st_mode))
        throw InputError(path, 0, "cannot make the output folder: a file of that name is in the way");
    // Every benchmark writes its files here at its end: find out now, not after the work.
    check_output_path(path + "/index.md");
}

void write_text_file(const std::string& path, const std::string& text) {
    write_file_atomically(path, std::vector<std::uint8_t>(text.begin(), text.end()));
}

std::string conditions_of(int width, int height, int threads) {
    return std::to_string(width) + "x" + std::to_string(height) + ", " + std::to_string(threads) + (threads == 1 ? " thread" : " threads");
}

std::string fixed(double v, int digits) {
    char buffer[64];
    if (std::isinf(v)) return v > 0.0 ? "inf" : "-inf";
    std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
    return buffer;
}

double timed_median(const Scene& scene, const RenderOptions& options, int repeat, RenderStats& stats) {
    std::vector<TimedCase> cases(1);
    cases[0].scene = &scene, cases[0].options = options, cases[0].keep_last = false;
    time_interleaved(cases, repeat);
    stats = cases[0].stats;
    return cases[0].median_ms;
}

void time_interleaved(std::vector<TimedCase>& cases, int repeat) {
    std::vector<std::vector<double>> times(cases.size());
    // Frames are drawn into reused buffers, as a renderer draws frame after frame (the warm-up
    // frames allocate them): a case whose last frame is kept has buffers of its own, the
    // others share one set (so that memory does not grow with the number of cases).
    std::vector<Framebuffer> kept(cases.size(), Framebuffer(0, 0, Framebuffer::Uncleared{}));
    Framebuffer shared(0, 0, Framebuffer::Uncleared{});
    const auto frame_of = [&](std::size_t i) -> Framebuffer& { return cases[i].keep_last ? kept[i] : shared; };
    for (std::size_t i = 0; i < cases.size(); ++i) {
        RenderStats warm;
        render(*cases[i].scene, cases[i].options, warm, frame_of(i));
    }
    for (int r = 0; r < repeat; ++r)
        for (std::size_t i = 0; i < cases.size(); ++i) {
            TimedCase& c = cases[i];
            if (cases.size() > 1) {  // (see common.h)
                RenderStats warm;
                render(*c.scene, c.options, warm, frame_of(i));
            }
            c.stats = RenderStats{};
            const auto start = Clock::now();
            render(*c.scene, c.options, c.stats, frame_of(i));
            times[i].push_back(ms_since(start));
        }
    for (std::size_t i = 0; i < cases.size(); ++i)
        if (cases[i].keep_last) cases[i].last = std::move(kept[i]);
    for (std::size_t i = 0; i < cases.size(); ++i) cases[i].median_ms = median(times[i]);
}

}  // namespace texr::bench
