// texr bench scale: how time and memory grow with triangles, pixels and texture size. Each
// case runs in a child process so that its peak memory is its own.
#include "common.h"

#include <cmath>
#include <utility>
#include <vector>
#include <cstdio>
#include <functional>
#include <stdexcept>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include "texr/bench/plot.h"
#include "texr/scene/parser.h"

namespace texr::bench {

namespace {

struct ScaleRow {
    std::string dimension, scene;
    double size;  // triangles, pixels or texels
    int width, height, threads;
    double frame_ms, rate, peak_mb, expected_mb, mip_ms;
    std::string rate_unit;
    double decoded_mb = 0.0;  // the decoded texel copies the frames made (not in expected_mb)
};

// The decoded copies (image.h, Image::decoded_texels) of a scene's textures and their mip
// levels, in MB.
double decoded_mb(const Scene& scene) {
    std::size_t bytes = 0;
    for (const Texture& t : scene.textures) bytes += t.image->decoded_bytes() + (t.mipmap ? t.mipmap->decoded_bytes() : 0);
    return double(bytes) / 1048576.0;
}

// A row's point on the plot: "1.0M triangles", "3840x2160", "8192^2 texels".
std::string point_label(const ScaleRow& r) {
    char text[64];
    if (r.dimension == "pixels") {
        std::snprintf(text, sizeof text, "%dx%d", r.width, r.height);
    } else if (r.dimension == "texture") {
        std::snprintf(text, sizeof text, "%.0f^2 texels", std::sqrt(r.size));
    } else if (r.size >= 1e6) {
        std::snprintf(text, sizeof text, "%.1fM %s", r.size / 1e6, r.dimension.c_str());
    } else {
        std::snprintf(text, sizeof text, "%.0fk %s", r.size / 1e3, r.dimension.c_str());
    }
    return text;
}

// Peak resident memory of this process so far, in MB.
double peak_rss_mb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // Linux reports kilobytes
}

// Runs `measure` in a child process so that its peak memory is its own, and returns the row
// it filled in (through a pipe).
ScaleRow in_child(const std::function<ScaleRow()>& measure) {
    int fds[2];
    if (pipe(fds) != 0) return measure();
    // The child starts with this process's resident pages, which count towards its peak:
    // give the free heap that earlier benchmarks left behind back to the system first.
#ifdef __GLIBC__
    malloc_trim(0);
#endif
    release_worker_threads();  // (the child starts its own)
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        ScaleRow row = measure();
        row.peak_mb = peak_rss_mb();
        const std::string text = row.dimension + "\t" + row.scene + "\t" + fixed(row.size, 0) + "\t" + std::to_string(row.width) +
                                 "\t" + std::to_string(row.height) + "\t" + std::to_string(row.threads) + "\t" +
                                 fixed(row.frame_ms, 4) + "\t" + fixed(row.rate, 4) + "\t" + fixed(row.peak_mb, 2) + "\t" +
                                 fixed(row.expected_mb, 2) + "\t" + fixed(row.mip_ms, 3) + "\t" + row.rate_unit + "\t" +
                                 fixed(row.decoded_mb, 2) + "\n";
        if (write(fds[1], text.data(), text.size()) < 0) _exit(1);
        close(fds[1]);
        _exit(0);
    }
    close(fds[1]);
    std::string text;
    char buffer[512];
    ssize_t n;
    while ((n = read(fds[0], buffer, sizeof buffer)) > 0) text.append(buffer, std::size_t(n));
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    std::vector<std::string> f;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= text.size(); ++i)
        if (i == text.size() || text[i] == '\t' || text[i] == '\n') {
            f.push_back(text.substr(start, i - start));
            start = i + 1;
        }
    if (f.size() < 13) throw std::runtime_error("a scale benchmark child process failed");
    return {f[0], f[1], std::stod(f[2]), std::stoi(f[3]), std::stoi(f[4]), std::stoi(f[5]), std::stod(f[6]),
            std::stod(f[7]), std::stod(f[8]), std::stod(f[9]), std::stod(f[10]), f[11], std::stod(f[12])};
}

// A wavy k x k grid of quads (2 k^2 triangles) filling the view of `camera_scene`.
Mesh terrain(int k) {
    Mesh m;
    m.has_uv = true;
    for (int j = 0; j <= k; ++j)
        for (int i = 0; i <= k; ++i) {
            Vertex v;
            const double x = -4.0 + 8.0 * i / k, z = -1.0 - 6.0 * j / k;
            v.position = glm::vec3(float(x), float(-1.0 + 0.1 * std::sin(7 * x) * std::cos(5 * z)), float(z));
            v.uv = {4.0 * i / k, 4.0 * j / k};
            m.vertices.push_back(v);
        }
    for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
            const auto at = [&](int a, int b) { return std::uint32_t(b * (k + 1) + a); };
            m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    m.triangle_material.assign(m.triangles.size(), 0);
    return m;
}

// A procedural size x size sRGB texture (cells and a fine checker, like detail.png).
std::shared_ptr<const Image> procedural_texture(int size) {
    LargeVector<std::uint8_t> rgba(std::size_t(size) * std::size_t(size) * 4);
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            const std::size_t p = 4 * (std::size_t(j) * std::size_t(size) + std::size_t(i));
            const int cu = i / 32, cv = j / 32, fine = ((i / 8) + (j / 8)) % 2;
            rgba[p] = std::uint8_t(60 + (cu * 37) % 180 + 40 * fine);
            rgba[p + 1] = std::uint8_t(60 + (cv * 53) % 180 + 40 * fine);
            rgba[p + 2] = std::uint8_t(60 + ((cu + cv) * 29) % 180);
            rgba[p + 3] = 255;
        }
    return std::make_shared<const Image>(Image::ldr(size, size, ColorSpace::srgb, std::move(rgba)));
}

std::vector<ScaleRow> bench_scale(const BenchOptions& o) {
    const int threads = o.threads_given ? o.threads : usable_cores();
    std::vector<ScaleRow> rows;
    const double fb_bytes_per_pixel = sizeof(Color) + sizeof(float);
    // Triangles: a terrain of 10^4 .. 10^6 triangles at 1920x1080.
    const std::vector<int> grids = o.quick ? std::vector<int>{71} : std::vector<int>{71, 224, 708};
    for (int k : grids) {
        rows.push_back(in_child([&] {
            Scene scene = load_bench_scene(o, "plane");
            for (Texture& t : scene.textures) t.sampler.filter = Filter::bilinear;
            scene.meshes = {terrain(k)};
            scene.objects = {Object{0, glm::dmat4(1.0), false}};
            scene.camera.eye = {0.0, 0.5, 0.5}, scene.camera.target = {0.0, -1.0, -4.0};
            RenderOptions options;
            options.width = 1920, options.height = 1080, options.threads = threads;
            RenderStats stats;
            const double ms = timed_median(scene, options, o.repeat, stats);
            const double expected = (double(scene.textures[0].image->bytes()) + 1920.0 * 1080.0 * fb_bytes_per_pixel +
                                     double(scene.meshes[0].vertices.size() * sizeof(Vertex) +
                                            scene.meshes[0].triangles.size() * (sizeof(std::array<std::uint32_t, 3>) + sizeof(int)))) /
                                    1048576.0;
            return ScaleRow{"triangles", "terrain", double(stats.triangles_in), 1920, 1080, threads, ms,
                            double(stats.triangles_in) / (ms * 1e3), 0.0, expected, 0.0, "M triangles/s", decoded_mb(scene)};
        }));
        std::fprintf(stderr, "bench scale: %.0f triangles: %.2f ms, %.2f M triangles/s, peak %.0f MB\n", rows.back().size,
                     rows.back().frame_ms, rows.back().rate, rows.back().peak_mb);
    }
    // Pixels: the receding plane from 640x480 to 3840x2160.
    const std::vector<std::pair<int, int>> frames =
        o.quick ? std::vector<std::pair<int, int>>{{640, 480}} : std::vector<std::pair<int, int>>{{640, 480}, {1920, 1080}, {3840, 2160}};
    for (auto [w, h] : frames) {
        rows.push_back(in_child([&, w = w, h = h] {
            Scene scene = load_bench_scene(o, "plane");
            for (Texture& t : scene.textures) t.sampler.filter = Filter::bilinear;
            RenderOptions options;
            options.width = w, options.height = h, options.threads = threads;
            RenderStats stats;
            const double ms = timed_median(scene, options, o.repeat, stats);
            const double expected = (double(scene.textures[0].image->bytes()) + double(w) * h * fb_bytes_per_pixel) / 1048576.0;
            return ScaleRow{"pixels", "plane", double(w) * h, w, h, threads, ms, double(stats.pixels_shaded) / (ms * 1e3), 0.0,
                            expected, 0.0, "M covered px/s", decoded_mb(scene)};
        }));
        std::fprintf(stderr, "bench scale: %dx%d: %.2f ms, peak %.0f MB\n", w, h, rows.back().frame_ms, rows.back().peak_mb);
    }
    // Texture size: 1024^2 .. 8192^2, trilinear (so every mip level is built), 1920x1080.
    const std::vector<int> textures = o.quick ? std::vector<int>{1024} : std::vector<int>{1024, 4096, 8192};
    for (int size : textures) {
        rows.push_back(in_child([&] {
            Scene scene = load_bench_scene(o, "plane");
            for (Texture& t : scene.textures) {
                t.image = procedural_texture(size);
                t.mipmap = std::make_shared<MipMap>(t.image);
                t.sampler.filter = Filter::trilinear;
            }
            scene.textures.resize(1);  // only the procedural texture stays alive
            scene.textures[0].mipmap->build();
            const double mip_ms = 1000.0 * scene.textures[0].mipmap->build_seconds();
            RenderOptions options;
            options.width = 1920, options.height = 1080, options.threads = threads;
            RenderStats stats;
            const double ms = timed_median(scene, options, o.repeat, stats);
            const MipMap& mip = *scene.textures[0].mipmap;
            const double expected = (double(mip.base().bytes()) + double(mip.bytes()) + 1920.0 * 1080.0 * fb_bytes_per_pixel) / 1048576.0;
            return ScaleRow{"texture", "plane", double(size) * size, 1920, 1080, threads, ms,
                            double(stats.pixels_shaded) / (ms * 1e3), 0.0, expected, mip_ms, "M covered px/s", decoded_mb(scene)};
        }));
        std::fprintf(stderr, "bench scale: texture %d^2: %.2f ms, mips %.0f ms, peak %.0f MB of %.0f MB\n", size,
                     rows.back().frame_ms, rows.back().mip_ms, rows.back().peak_mb, rows.back().expected_mb);
    }
    return rows;
}

void write_scale_report(const BenchOptions& o, const std::vector<ScaleRow>& rows) {
    std::string csv = "dimension,scene,count,width,height,threads,filter,mode,frame_ms_median,rate,rate_unit,mip_build_ms,decoded_mb,peak_mb,data_mb,peak_over_data\n";
    std::string md = "| grows | scene | count | frame | threads | filter | span mode | frame ms (median) | rate | mip build ms | decoded MB | peak MB | data MB | peak / data |\n"
                     "|---|---|---:|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
    std::vector<PlotPoint> points;
    for (const ScaleRow& r : rows) {
        const std::string frame = std::to_string(r.width) + "x" + std::to_string(r.height);
        csv += r.dimension + "," + r.scene + "," + fixed(r.size, 0) + "," + std::to_string(r.width) + "," + std::to_string(r.height) +
               "," + std::to_string(r.threads) + "," + (r.dimension == "texture" ? "trilinear" : "bilinear") + ",incremental," +
               fixed(r.frame_ms, 3) + "," + fixed(r.rate, 3) + "," + r.rate_unit + "," +
               fixed(r.mip_ms, 1) + "," + fixed(r.decoded_mb, 1) + "," + fixed(r.peak_mb, 1) + "," + fixed(r.expected_mb, 1) + "," + fixed(r.peak_mb / r.expected_mb, 3) + "\n";
        md += "| " + r.dimension + " | " + r.scene + " | " + fixed(r.size, 0) + " | " + frame + " | " + std::to_string(r.threads) +
              " | " + (r.dimension == "texture" ? "trilinear" : "bilinear") + " | incremental | " + fixed(r.frame_ms, 2) + " | " + fixed(r.rate, 2) + " " + r.rate_unit + " | " + fixed(r.mip_ms, 1) + " | " +
              fixed(r.decoded_mb, 1) + " | " + fixed(r.peak_mb, 1) + " | " + fixed(r.expected_mb, 1) + " | " + fixed(r.peak_mb / r.expected_mb, 2) + " |\n";
        points.push_back({r.dimension, point_label(r), r.size, r.frame_ms});
    }
    md += "\nCount: what grows, in its unit (triangles, frame pixels, or texture texels). Data MB: texture texels, mip levels, frame buffers (12-byte colour + 4-byte depth per pixel) and mesh "
          "arrays; decoded MB: the decoded texel copies the frames made for the blending filters (in the peak, not in "
          "the data); peak MB: the measuring process's peak resident size (each row in its own process, program and "
          "libraries included).\n";
    write_text_file(o.out + "/scale.csv", csv);
    write_text_file(o.out + "/scale.md", md);
    PlotAxes axes;
    axes.title = "texr bench scale: frame time as triangles, pixels and texture size grow";
    axes.x_label = "count (triangles, pixels or texels)", axes.y_label = "median frame time, ms";
    axes.log_y = true, axes.connect = true;
    write_text_file(o.out + "/scale.svg", scatter_svg(axes, points));
}

// Issue 4's targets: the largest terrain (1M triangles) at >= 10 M triangles/s on 2 threads
// (not measured on another number of threads: --threads 2 measures it); the
// largest texture (8192^2) with its mip levels in at most 1.25x the data's memory.
std::vector<Target> scale_targets(const std::vector<ScaleRow>& rows) {
    const ScaleRow* terrain = nullptr;
    const ScaleRow* texture = nullptr;
    for (const ScaleRow& r : rows) {
        if (r.dimension == "triangles" && (!terrain || r.size > terrain->size)) terrain = &r;
        if (r.dimension == "texture" && (!texture || r.size > texture->size)) texture = &r;
    }
    std::vector<Target> targets;
    if (terrain) {
        targets.push_back(at_least("scale", "1M-triangle terrain: >= 10 M triangles/s on 2 threads",
                                   fixed(terrain->size, 0) + " triangles, " + conditions_of(terrain->width, terrain->height, terrain->threads),
                                   terrain->rate, 10.0, "M triangles/s", 2));
        measured_as_asked(targets.back(), terrain->size >= 1e6, "the target is for 1M triangles");
        if (terrain->size >= 1e6) measured_as_asked(targets.back(), terrain->threads == 2, "the target is for 2 threads (--threads 2)");
    }
    if (texture)
        targets.push_back(at_most("scale", "8192^2 texture: peak memory <= 1.25x texels + mip levels + frame",
                                  std::to_string(int(std::lround(std::sqrt(texture->size)))) + "^2 texture, " +
                                      conditions_of(texture->width, texture->height, texture->threads),
                                  texture->peak_mb / texture->expected_mb, 1.25,
                                  "x (" + fixed(texture->peak_mb, 0) + " / " + fixed(texture->expected_mb, 0) + " MB)", 2));
    if (texture) measured_as_asked(targets.back(), texture->size >= 8192.0 * 8192.0, "the target is for an 8192^2 texture");
    return targets;
}

}  // namespace

std::vector<Target> run_scale(const BenchOptions& o) {
    const std::vector<ScaleRow> rows = bench_scale(o);
    write_scale_report(o, rows);
    return scale_targets(rows);
}

}  // namespace texr::bench
