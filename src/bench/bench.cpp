// texr bench filters: every texture filter on two scenes, timed and scored against a
// supersampled ground truth (README, "Benchmarks").
#include "texr/bench/bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <functional>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include "texr/bench/metrics.h"
#include "texr/bench/plot.h"
#include "texr/raster/span_modes.h"
#include "texr/core/error.h"
#include "texr/io/frame_writer.h"
#include "texr/render/renderer.h"
#include "texr/scene/parser.h"

#ifndef TEXR_MODELS_DIR
#define TEXR_MODELS_DIR "models"
#endif

namespace texr {

const char* bench_help =
    "usage: texr bench [NAME] [options]\n"
    "\n"
    "Benchmarks; without NAME runs all of them. Results go to out/bench/ (CSV, a Markdown\n"
    "table and an SVG plot per benchmark, and index.md).\n"
    "\n"
    "benchmarks:\n"
    "  filters     every texture filter on a receding plane and a grazing-angle square:\n"
    "              median frame time, covered Mpixel/s, PSNR and SSIM against a\n"
    "              supersampled ground truth\n"
    "  scale       1e4..1e6 triangles at 1920x1080, frames up to 3840x2160, textures up\n"
    "              to 8192^2 with mipmaps: time, triangles/s and peak memory (all cores)\n"
    "  spans       every span mode (exact, incremental, affine8/16/32, affine, adaptive)\n"
    "              on the same scenes: median frame time, max and mean texel error\n"
    "\n"
    "options:\n"
    "  --size WxH      frame size (default 1024x768)\n"
    "  --repeat N      timed frames per measurement; the median is reported (default 7)\n"
    "  --spp N         ground truth: N x N samples per pixel (default 16)\n"
    "  --threads N     worker threads for the timed frames (default 1; scale: all cores)\n"
    "  --models DIR    folder holding bench/plane.scene and bench/grazing.scene\n"
    "                  (default: this build's source models/)\n"
    "  --out DIR       output folder (default out/bench)\n"
    "  --quick         1 timed frame, 4x4 ground truth, 256x192: a smoke test\n";

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

struct BenchOptions {
    int width = 1024, height = 768, repeat = 7, spp = 16, threads = 1;
    bool threads_given = false;
    std::string models = TEXR_MODELS_DIR, out = "out/bench";
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

FrameBytes bytes_of(const Framebuffer& fb) { return {fb.width, fb.height, encode_srgb8(fb)}; }

std::vector<bool> covered(const Framebuffer& fb) {
    std::vector<bool> mask(fb.depth.size());
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = fb.drawn(i);
    return mask;
}

void make_folders(const std::string& path) {
    std::string partial;
    for (std::size_t i = 0; i <= path.size(); ++i) {
        if (i == path.size() || path[i] == '/') {
            if (!partial.empty()) ::mkdir(partial.c_str(), 0755);
        }
        if (i < path.size()) partial += path[i];
    }
}

void write_text_file(const std::string& path, const std::string& text) {
    write_file_atomically(path, std::vector<std::uint8_t>(text.begin(), text.end()));
}

std::string fixed(double v, int digits) {
    char buffer[64];
    if (std::isinf(v)) return "inf";
    std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
    return buffer;
}

struct FilterRow {
    std::string scene, filter;
    int width, height, threads;
    double load_ms, mip_ms, frame_ms, covered_pixels, mpix_per_s, psnr_db, ssim, texels_per_pixel;
};

std::vector<FilterRow> bench_filters(const BenchOptions& o) {
    std::vector<FilterRow> rows;
    for (const std::string name : {"plane", "grazing"}) {
        const std::string path = o.models + "/bench/" + name + ".scene";
        const auto load_start = Clock::now();
        const Scene base = load_scene(path);
        const double load_ms = ms_since(load_start);
        double mip_ms = 0.0;
        for (const Texture& t : base.textures) {
            t.mipmap->build();  // built once, outside the timed frames, and reported
            mip_ms += 1000.0 * t.mipmap->build_seconds();
        }
        RenderOptions options;
        options.width = o.width, options.height = o.height, options.threads = o.threads;

        std::fprintf(stderr, "bench filters: %s ground truth (%dx%d samples per pixel)...\n", name.c_str(), o.spp, o.spp);
        RenderOptions truth_options = options;
        truth_options.spp = o.spp;
        RenderStats truth_stats;
        const Framebuffer truth = render(base, truth_options, truth_stats);
        const FrameBytes truth_bytes = bytes_of(truth);
        const std::vector<bool> mask = covered(truth);
        write_frame(truth, o.out + "/filters-" + name + "-truth.png");

        for (int f = 0; f < filter_count; ++f) {
            Scene scene = base;
            for (Texture& t : scene.textures) t.sampler.filter = Filter(f);
            RenderStats warm;
            render(scene, options, warm);  // warm caches; not timed
            std::vector<double> times;
            RenderStats stats;
            Framebuffer frame(1, 1, {});
            for (int r = 0; r < o.repeat; ++r) {
                stats = RenderStats{};
                const auto start = Clock::now();
                frame = render(scene, options, stats);
                times.push_back(ms_since(start));
            }
            FilterRow row;
            row.scene = name, row.filter = filter_name(Filter(f));
            row.width = o.width, row.height = o.height, row.threads = o.threads;
            row.load_ms = load_ms, row.mip_ms = mip_ms;
            row.frame_ms = median(times);
            row.covered_pixels = double(stats.pixels_shaded);
            row.mpix_per_s = row.covered_pixels / (row.frame_ms * 1e3);
            const FrameBytes got = bytes_of(frame);
            row.psnr_db = psnr(got, truth_bytes, mask);
            row.ssim = ssim(got, truth_bytes, mask);
            row.texels_per_pixel = double(stats.texels_fetched) / std::max(1.0, row.covered_pixels);
            write_frame(frame, o.out + "/filters-" + name + "-" + row.filter + ".png");
            std::fprintf(stderr, "  %-22s %9.2f ms %8.1f Mpx/s %7.2f dB  SSIM %.4f\n", row.filter.c_str(), row.frame_ms,
                         row.mpix_per_s, row.psnr_db, row.ssim);
            rows.push_back(row);
        }
    }
    return rows;
}

void write_filters_report(const BenchOptions& o, const std::vector<FilterRow>& rows) {
    std::string csv =
        "scene,width,height,threads,filter,mode,load_ms,mip_build_ms,frame_ms_median,covered_pixels,covered_mpix_per_s,"
        "psnr_db,ssim,texels_per_pixel\n";
    std::string md =
        "| scene | size | threads | filter | frame ms (median) | covered Mpx/s | PSNR dB | SSIM | texels/px |\n"
        "|---|---|---|---|---:|---:|---:|---:|---:|\n";
    std::vector<PlotPoint> points;
    for (const FilterRow& r : rows) {
        const std::string size = std::to_string(r.width) + "x" + std::to_string(r.height);
        csv += r.scene + "," + std::to_string(r.width) + "," + std::to_string(r.height) + "," + std::to_string(r.threads) +
               "," + r.filter + ",incremental," + fixed(r.load_ms, 3) + "," + fixed(r.mip_ms, 3) + "," + fixed(r.frame_ms, 3) + "," +
               fixed(r.covered_pixels, 0) + "," + fixed(r.mpix_per_s, 2) + "," + fixed(r.psnr_db, 3) + "," +
               fixed(r.ssim, 5) + "," + fixed(r.texels_per_pixel, 2) + "\n";
        md += "| " + r.scene + " | " + size + " | " + std::to_string(r.threads) + " | " + r.filter + " | " +
              fixed(r.frame_ms, 2) + " | " + fixed(r.mpix_per_s, 1) + " | " + fixed(r.psnr_db, 2) + " | " +
              fixed(r.ssim, 4) + " | " + fixed(r.texels_per_pixel, 1) + " |\n";
        points.push_back({r.scene, r.filter, r.frame_ms, r.psnr_db});
    }
    if (!rows.empty())
        md += "\nScene load " + fixed(rows.front().load_ms, 1) + " ms and mip building " + fixed(rows.front().mip_ms, 1) +
              " ms (first scene) are not part of the frame times. PSNR and SSIM are measured on the covered pixels "
              "against " + std::to_string(o.spp) + "x" + std::to_string(o.spp) + " supersampling.\n";
    write_text_file(o.out + "/filters.csv", csv);
    write_text_file(o.out + "/filters.md", md);
    write_text_file(o.out + "/filters.svg",
                    scatter_svg({"texr bench filters: run time against error", "median frame time, ms", "PSNR, dB", true}, points));
}

// --- texr bench spans ----------------------------------------------------------------------
struct SpanRow {
    std::string scene, mode;
    int width, height, threads;
    double frame_ms, max_error, mean_error, covered_pixels;
};

std::vector<SpanRow> bench_spans(const BenchOptions& o) {
    std::vector<SpanRow> rows;
    for (const std::string name : {"plane", "grazing"}) {
        Scene scene = load_scene(o.models + "/bench/" + name + ".scene");
        for (Texture& t : scene.textures) t.sampler.filter = Filter::bilinear;  // the span cost, not a filter's, dominates
        const double texture_w = scene.textures.at(0).mipmap->base().width();
        const double texture_h = scene.textures.at(0).mipmap->base().height();
        RenderOptions options;
        options.width = o.width, options.height = o.height, options.threads = o.threads;
        // The reference: exact mode, every pixel's (u, v) = u'/q from the plane equations in
        // double precision, nothing accumulated.
        options.capture_uv = true;
        options.span_mode = SpanMode::exact;
        RenderStats reference_stats;
        const Framebuffer reference = render(scene, options, reference_stats);
        std::fprintf(stderr, "bench spans: %s\n", name.c_str());
        for (int m = 0; m < span_mode_count; ++m) {
            options.span_mode = SpanMode(m);
            options.capture_uv = true;
            RenderStats stats;
            const Framebuffer captured = render(scene, options, stats);
            double max_error = 0.0, sum = 0.0;
            std::size_t count = 0;
            for (std::size_t i = 0; i < captured.uv.size(); ++i) {
                if (!reference.drawn(i)) continue;
                const glm::dvec2 a = captured.uv[i], b = reference.uv[i];
                const double e = std::max(std::fabs(a.x - b.x) * texture_w, std::fabs(a.y - b.y) * texture_h);
                max_error = std::max(max_error, e), sum += e, ++count;
            }
            options.capture_uv = false;
            RenderStats warm;
            render(scene, options, warm);
            std::vector<double> times;
            for (int r = 0; r < o.repeat; ++r) {
                RenderStats timed;
                const auto start = Clock::now();
                render(scene, options, timed);
                times.push_back(ms_since(start));
            }
            SpanRow row{name, span_mode_name(SpanMode(m)), o.width, o.height, o.threads, median(times), max_error,
                        count ? sum / double(count) : 0.0, double(reference_stats.pixels_shaded)};
            std::fprintf(stderr, "  %-12s %9.2f ms  max %.3g texel  mean %.3g texel\n", row.mode.c_str(), row.frame_ms,
                         row.max_error, row.mean_error);
            rows.push_back(row);
        }
    }
    return rows;
}

void write_spans_report(const BenchOptions& o, const std::vector<SpanRow>& rows) {
    std::string csv = "scene,width,height,threads,filter,mode,frame_ms_median,max_error_texels,mean_error_texels,covered_pixels\n";
    std::string md = "| scene | size | threads | filter | span mode | frame ms (median) | max error (texels) | mean error (texels) |\n"
                     "|---|---|---|---|---|---:|---:|---:|\n";
    std::vector<PlotPoint> points;
    for (const SpanRow& r : rows) {
        const std::string size = std::to_string(r.width) + "x" + std::to_string(r.height);
        char errors[96];
        std::snprintf(errors, sizeof errors, "%.3g,%.3g", r.max_error, r.mean_error);
        csv += r.scene + "," + std::to_string(r.width) + "," + std::to_string(r.height) + "," + std::to_string(r.threads) +
               ",bilinear," + r.mode + "," + fixed(r.frame_ms, 3) + "," + errors + "," + fixed(r.covered_pixels, 0) + "\n";
        char cells[96];
        std::snprintf(cells, sizeof cells, "%.3g | %.3g", r.max_error, r.mean_error);
        md += "| " + r.scene + " | " + size + " | " + std::to_string(r.threads) + " | bilinear | " + r.mode + " | " +
              fixed(r.frame_ms, 2) + " | " + cells + " |\n";
        points.push_back({r.scene, r.mode, r.frame_ms, std::max(r.max_error, 1e-12)});
    }
    md += "\nErrors are against the exact mode (u'/q from the plane equations at every pixel, in double "
          "precision); the adaptive mode's tolerance is 1/64 texel.\n";
    write_text_file(o.out + "/spans.csv", csv);
    write_text_file(o.out + "/spans.md", md);
    PlotAxes axes{"texr bench spans: run time against texture coordinate error", "median frame time, ms",
                  "max error, texels", true};
    axes.log_y = true;
    write_text_file(o.out + "/spans.svg", scatter_svg(axes, points));
}

// --- texr bench scale -----------------------------------------------------------------------
struct ScaleRow {
    std::string dimension, scene;
    double size;  // triangles, pixels or texels
    int width, height, threads;
    double frame_ms, rate, peak_mb, expected_mb, mip_ms;
    std::string rate_unit;
};

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
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        ScaleRow row = measure();
        row.peak_mb = peak_rss_mb();
        const std::string text = row.dimension + "\t" + row.scene + "\t" + fixed(row.size, 0) + "\t" + std::to_string(row.width) +
                                 "\t" + std::to_string(row.height) + "\t" + std::to_string(row.threads) + "\t" +
                                 fixed(row.frame_ms, 4) + "\t" + fixed(row.rate, 4) + "\t" + fixed(row.peak_mb, 2) + "\t" +
                                 fixed(row.expected_mb, 2) + "\t" + fixed(row.mip_ms, 3) + "\t" + row.rate_unit + "\n";
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
    if (f.size() < 12) throw std::runtime_error("a scale benchmark child process failed");
    return {f[0], f[1], std::stod(f[2]), std::stoi(f[3]), std::stoi(f[4]), std::stoi(f[5]), std::stod(f[6]),
            std::stod(f[7]), std::stod(f[8]), std::stod(f[9]), std::stod(f[10]), f[11]};
}

double timed_median(const Scene& scene, const RenderOptions& options, int repeat, RenderStats& stats) {
    RenderStats warm;
    render(scene, options, warm);
    std::vector<double> times;
    for (int r = 0; r < repeat; ++r) {
        stats = RenderStats{};
        const auto start = Clock::now();
        render(scene, options, stats);
        times.push_back(ms_since(start));
    }
    return median(times);
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
    std::vector<std::uint8_t> rgba(std::size_t(size) * std::size_t(size) * 4);
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
    const int threads = o.threads_given ? o.threads : std::max(1, int(std::thread::hardware_concurrency()));
    std::vector<ScaleRow> rows;
    const double fb_bytes_per_pixel = sizeof(Color) + sizeof(float);
    const std::string plane_path = o.models + "/bench/plane.scene";
    // Triangles: a terrain of 10^4 .. 10^6 triangles at 1920x1080.
    for (int k : {71, 224, 708}) {
        rows.push_back(in_child([&] {
            Scene scene = load_scene(plane_path);
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
                            double(stats.triangles_in) / (ms * 1e3), 0.0, expected, 0.0, "M triangles/s"};
        }));
        std::fprintf(stderr, "bench scale: %.0f triangles: %.2f ms, %.2f M triangles/s, peak %.0f MB\n", rows.back().size,
                     rows.back().frame_ms, rows.back().rate, rows.back().peak_mb);
    }
    // Pixels: the receding plane from 640x480 to 3840x2160.
    for (auto [w, h] : {std::pair{640, 480}, std::pair{1920, 1080}, std::pair{3840, 2160}}) {
        rows.push_back(in_child([&, w = w, h = h] {
            Scene scene = load_scene(plane_path);
            for (Texture& t : scene.textures) t.sampler.filter = Filter::bilinear;
            RenderOptions options;
            options.width = w, options.height = h, options.threads = threads;
            RenderStats stats;
            const double ms = timed_median(scene, options, o.repeat, stats);
            const double expected = (double(scene.textures[0].image->bytes()) + double(w) * h * fb_bytes_per_pixel) / 1048576.0;
            return ScaleRow{"pixels", "plane", double(w) * h, w, h, threads, ms, double(stats.pixels_shaded) / (ms * 1e3), 0.0,
                            expected, 0.0, "M covered px/s"};
        }));
        std::fprintf(stderr, "bench scale: %dx%d: %.2f ms, peak %.0f MB\n", w, h, rows.back().frame_ms, rows.back().peak_mb);
    }
    // Texture size: 1024^2 .. 8192^2, trilinear (so every mip level is built), 1920x1080.
    for (int size : {1024, 4096, 8192}) {
        rows.push_back(in_child([&] {
            Scene scene = load_scene(plane_path);
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
                            double(stats.pixels_shaded) / (ms * 1e3), 0.0, expected, mip_ms, "M covered px/s"};
        }));
        std::fprintf(stderr, "bench scale: texture %d^2: %.2f ms, mips %.0f ms, peak %.0f MB of %.0f MB\n", size,
                     rows.back().frame_ms, rows.back().mip_ms, rows.back().peak_mb, rows.back().expected_mb);
    }
    return rows;
}

void write_scale_report(const BenchOptions& o, const std::vector<ScaleRow>& rows) {
    std::string csv = "dimension,scene,size,width,height,threads,filter,mode,frame_ms_median,rate,rate_unit,mip_build_ms,peak_mb,data_mb,peak_over_data\n";
    std::string md = "| grows | scene | size | frame | threads | frame ms (median) | rate | mip build ms | peak MB | data MB | peak / data |\n"
                     "|---|---|---:|---|---|---:|---:|---:|---:|---:|---:|\n";
    std::vector<PlotPoint> points;
    for (const ScaleRow& r : rows) {
        const std::string frame = std::to_string(r.width) + "x" + std::to_string(r.height);
        csv += r.dimension + "," + r.scene + "," + fixed(r.size, 0) + "," + std::to_string(r.width) + "," + std::to_string(r.height) +
               "," + std::to_string(r.threads) + "," + (r.dimension == "texture" ? "trilinear" : "bilinear") + ",incremental," +
               fixed(r.frame_ms, 3) + "," + fixed(r.rate, 3) + "," + r.rate_unit + "," +
               fixed(r.mip_ms, 1) + "," + fixed(r.peak_mb, 1) + "," + fixed(r.expected_mb, 1) + "," + fixed(r.peak_mb / r.expected_mb, 3) + "\n";
        md += "| " + r.dimension + " | " + r.scene + " | " + fixed(r.size, 0) + " | " + frame + " | " + std::to_string(r.threads) +
              " | " + fixed(r.frame_ms, 2) + " | " + fixed(r.rate, 2) + " " + r.rate_unit + " | " + fixed(r.mip_ms, 1) + " | " +
              fixed(r.peak_mb, 1) + " | " + fixed(r.expected_mb, 1) + " | " + fixed(r.peak_mb / r.expected_mb, 2) + " |\n";
        points.push_back({r.dimension, fixed(r.size, 0), r.size, r.frame_ms});
    }
    md += "\nData MB: texture texels, mip levels, frame buffers (12-byte colour + 4-byte depth per pixel) and mesh "
          "arrays; peak MB: the measuring process's peak resident size (each row in its own process, program and "
          "libraries included).\n";
    write_text_file(o.out + "/scale.csv", csv);
    write_text_file(o.out + "/scale.md", md);
    PlotAxes axes{"texr bench scale: frame time as triangles, pixels and texture size grow", "size (triangles, pixels or texels)",
                  "median frame time, ms", true};
    axes.log_y = true;
    write_text_file(o.out + "/scale.svg", scatter_svg(axes, points));
}

int parse_int(const std::string& text, const std::string& option) {
    std::size_t used = 0;
    int v = 0;
    try {
        v = std::stoi(text, &used);
    } catch (...) {
        used = 0;
    }
    if (used != text.size() || v < 1) throw std::invalid_argument(option + " expects a positive whole number, got '" + text + "'");
    return v;
}

}  // namespace

int run_bench(const std::vector<std::string>& args) {
    BenchOptions o;
    std::vector<std::string> names;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw std::invalid_argument(a + " needs a value");
            return args[++i];
        };
        if (a == "--size") {
            const std::string v = value();
            const auto x = v.find('x');
            if (x == std::string::npos) throw std::invalid_argument("--size expects WxH, got '" + v + "'");
            o.width = parse_int(v.substr(0, x), "--size"), o.height = parse_int(v.substr(x + 1), "--size");
            if (o.width > max_image_side || o.height > max_image_side) throw std::invalid_argument("--size is out of range");
        } else if (a == "--repeat") o.repeat = parse_int(value(), "--repeat");
        else if (a == "--threads") o.threads = parse_int(value(), "--threads"), o.threads_given = true;
        else if (a == "--spp") o.spp = parse_int(value(), "--spp");
        else if (a == "--models") o.models = value();
        else if (a == "--out") o.out = value();
        else if (a == "--quick") o.repeat = 1, o.spp = 4, o.width = 256, o.height = 192;
        else if (a == "filters" || a == "spans" || a == "scale") names.push_back(a);
        else throw std::invalid_argument("unknown benchmark or option '" + a + "' (try texr bench --help)");
    }
    if (names.empty()) names = {"filters", "spans", "scale"};
    make_folders(o.out);
    std::string index = "# texr benchmarks\n\n";
    for (const std::string& name : names) {
        if (name == "filters") {
            write_filters_report(o, bench_filters(o));
            index += "- [filters](filters.md): every texture filter, time against error ([csv](filters.csv), [plot](filters.svg))\n";
        } else if (name == "spans") {
            write_spans_report(o, bench_spans(o));
            index += "- [spans](spans.md): span modes, time against texture coordinate error ([csv](spans.csv), [plot](spans.svg))\n";
        } else if (name == "scale") {
            write_scale_report(o, bench_scale(o));
            index += "- [scale](scale.md): time and memory as triangles, pixels and texture size grow ([csv](scale.csv), [plot](scale.svg))\n";
        }
    }
    write_text_file(o.out + "/index.md", index);
    std::printf("wrote %s/index.md\n", o.out.c_str());
    return 0;
}

}  // namespace texr
