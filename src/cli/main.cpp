// texr command line: texr render SCENE [options], texr explain SCENE X Y [options] and
// texr bench [NAME...] [options] (src/bench/bench.cpp); each command's --help lists its options.
// Exit codes: 0 success, 1 bad input or failed output (one message on stderr), 2 usage error.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <sys/stat.h>

#include "texr/bench/bench.h"
#include "texr/core/error.h"
#include "texr/io/frame_writer.h"
#include "texr/render/explain.h"
#include "texr/render/needs.h"
#include "texr/render/renderer.h"
#include "texr/scene/parser.h"
#include "texr/texture/image.h"
#include "texr/texture/lod_avx2.h"
#include "texr_version.h"  // (generated: TEXR_COMMIT)

namespace {

const char* main_help =
    "texr - a software rasterizer that teaches and performs texturing\n"
    "\n"
    "usage: texr <command> [options]\n"
    "\n"
    "commands:\n"
    "  render SCENE    render a scene file to a PNG or PPM frame\n"
    "  explain SCENE X Y  tell the story of pixel (X, Y): its triangle, homography,\n"
    "                  (u', v', q), u and v, derivatives, level of detail, colour\n"
    "  bench [NAME]    run benchmarks (run time against error) into out/bench/\n"
    "  compare A B     compare two images pixel by pixel (exit 0 if they match)\n"
    "\n"
    "options:\n"
    "  -h, --help      show this help (texr render --help for the command's options)\n"
    "  --version       print the version and the commit texr was built from\n"
    "\n"
    "The scene format is described in docs/scene-format.md.\n";

const char* explain_help =
    "usage: texr explain SCENE X Y [--size WxH] [--span MODE] [--span-tolerance T]\n"
    "\n"
    "Renders SCENE (nothing is written) and explains pixel (X, Y), column X from the left and\n"
    "row Y from the top: the front-most triangle covering its centre, the triangle's inverse\n"
    "homography M^-1 = U diag(1/w) adj(S) / det(S) and forward M, (u', v', q) at the pixel\n"
    "centre, u = u'/q and v = v'/q, the exact derivatives, the level of detail, the mip\n"
    "levels the texture's filter reads and its value, the shading (material colour, vertex\n"
    "colour, the normal and each light), and the colour written. --size, --span and\n"
    "--span-tolerance are render's (the other render options do not apply): with a --span mode\n"
    "that gives the pixel another (u, v) than u'/q, v'/q, the lookup reads those, with the\n"
    "exact derivatives taken there, and explain says by how much they differ. What follows\n"
    "-- is SCENE X Y, even where it starts with '-'.\n";

const char* compare_help =
    "usage: texr compare A B [--max-diff N]\n"
    "\n"
    "Compares two 8-bit images (PNG, PPM, or another format texr reads textures in; not\n"
    "16-bit, nor Radiance HDR) pixel by pixel, by their red, green and blue values (alpha\n"
    "is not compared): a PNG and a PPM of the same pixels match. Prints the size, how\n"
    "many pixels differ, the largest difference (of 255) and the first pixel where it is\n"
    "found (column X from the left, row Y from the top, as texr explain takes them), the\n"
    "mean difference a channel and the PSNR.\n"
    "\n"
    "options (each at most once; --name=value works too):\n"
    "  --max-diff N   the largest difference that still counts as a match, 0..255\n"
    "                 (default 0: the same pixels)\n"
    "  -h, --help     show this help\n"
    "  --             what follows is A and B, even where a name starts with '-'\n"
    "\n"
    "exit status: 0 the images match, 1 they differ (their sizes, or a pixel by more than\n"
    "N), 2 an image cannot be read, a bad command line, or standard output failed\n";

const char* render_help =
    "usage: texr render SCENE [options]\n"
    "\n"
    "Renders the scene file SCENE, writes one frame, and prints where it wrote it and\n"
    "the frame time.\n"
    "\n"
    "options (each at most once; --name=value works too):\n"
    "  -o, --output PATH   output file; .png or .ppm (binary P6) by its extension\n"
    "                      (default: out/<scene name>.png); never a file the scene\n"
    "                      reads\n"
    "  --size WxH          frame size in pixels, overriding the scene's 'size' line\n"
    "                      (each side 1..16384, at most 67108864 pixels)\n"
    "  --repeat N          render the frame N times and print the median frame time\n"
    "                      (1..1000000000, default 1)\n"
    "  --threads N         worker threads, 1..256 (default: one per core this process\n"
    "                      may use); the frame is the same bytes for every N.\n"
    "                      Renders run side by side should share the cores between\n"
    "                      them (e.g. --threads 1 each on 2 cores): more workers than\n"
    "                      cores make each frame slower\n"
    "  --spp N             texture ground truth, 1..64: from 2 on, N x N samples per\n"
    "                      pixel, each a bilinear lookup at its exact (u, v) (a\n"
    "                      procedural texture: its pattern there, every octave),\n"
    "                      box-filtered; 1 (default) is the ordinary render, one\n"
    "                      lookup with the texture's own filter\n"
    "  --span MODE         how (u, v) are computed along spans: exact, incremental\n"
    "                      (default), affine8, affine16, affine32, affine (no\n"
    "                      perspective: wrong, for contrast) or adaptive\n"
    "  --span-tolerance T  with --span adaptive only: largest error in texels\n"
    "                      (default 0.015625 = 1/64)\n"
    "  --stats             print counters (triangles in / clipped / culled / dropped /\n"
    "                      set up, spans, pixels shaded, texels fetched), what each\n"
    "                      material needs, each texture's memory (texels, mip levels\n"
    "                      if built, decoded copies if made; an image that textures\n"
    "                      share counted at the first), the worker threads used, the\n"
    "                      SIMD lanes this CPU and build use (AVX2 where the CPU\n"
    "                      has it, unless the environment sets TEXR_NO_AVX2 to\n"
    "                      anything but empty or 0; the same bytes either way),\n"
    "                      and the time of each stage (with --repeat, the mean over\n"
    "                      all frames, the first, which builds mip levels and\n"
    "                      decoded copies, included)\n"
    "  -h, --help          show this help\n"
    "  --                  what follows is the scene file, even where it starts\n"
    "                      with '-'\n"
    "\n"
    "exit status: 0 success, 1 bad scene or unwritable output (the frame, or standard\n"
    "output), 2 bad command line\n";

// Whether the command's arguments ask for its help (-h or --help before any "--").
bool asks_for_help(const std::vector<std::string>& argv) {
    for (const auto& a : argv) {
        if (a == "--") return false;
        if (a == "-h" || a == "--help") return true;
    }
    return false;
}

// The message for an option the command does not know: a single dash may have been meant
// as a file name.
std::string unknown_option(const std::string& a, const char* command) {
    return "unknown option " + texr::shown_token(a) + " for '" + command + "'" +
           (a.rfind("--", 0) == 0 ? "" : " (a file of that name: put -- before it, or write it as " + texr::shown_name("./" + a) + ")");
}

struct UsageError {
    std::string message;
};

struct RenderArguments {
    std::string scene, output;
    int width = 0, height = 0, repeat = 1, threads = 0, spp = 1;
    bool stats = false;
    texr::SpanMode span = texr::SpanMode::incremental;
    double span_tolerance = 1.0 / 64.0;
    bool output_given = false;  // -o given (else the default out/NAME.png)
};

int parse_positive(const std::string& text, const std::string& option) {
    std::size_t used = 0;
    long long value = 0;
    try {
        value = std::stoll(text, &used);
    } catch (...) {
        used = 0;
    }
    // (The same words as texr bench's.)
    const long long most = option == "--threads" ? 256 : option == "--spp" ? 64 : 1000000000LL;
    // Digits alone (std::stoll also takes leading white space and a sign).
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || used != text.size() || value < 1 || value > most)
        throw UsageError{option + " expects a whole number from 1 to " + std::to_string(most) + ", got " + texr::shown_token(text)};
    return int(value);
}

void parse_size(const std::string& text, RenderArguments& args) {
    const std::string error = texr::parse_frame_size(text, args.width, args.height);
    if (!error.empty()) throw UsageError{error};
}

int parse_coordinate(const std::string& text, const std::string& name, int limit) {
    std::size_t used = 0;
    long long value = -1;
    try {
        value = std::stoll(text, &used);
    } catch (...) {
        used = 0;
    }
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || used != text.size() || value < 0 || value >= limit)
        throw UsageError{name + " must be a pixel index from 0 to " + std::to_string(limit - 1) + ", got " + texr::shown_token(text)};
    return int(value);
}

std::string default_output(const std::string& scene) {
    std::string name = scene.substr(scene.find_last_of('/') + 1);
    const auto dot = name.find_last_of('.');
    if (dot != std::string::npos && dot > 0) name = name.substr(0, dot);
    return "out/" + name + ".png";
}

RenderArguments parse_render_arguments(const std::vector<std::string>& argv) {
    RenderArguments args;
    bool output_given = false, tolerance_given = false;
    bool names_only = false;  // after "--": a file name, whatever it starts with
    std::vector<std::string> given;  // the options seen so far (-o as --output)
    for (std::size_t i = 0; i < argv.size(); ++i) {
        const std::string& a = argv[i];
        if (!names_only && a == "--") {
            names_only = true;
            continue;
        }
        if (names_only) {
            if (!args.scene.empty()) throw UsageError{"texr render takes one scene file; '" + a + "' is one too many"};
            args.scene = a;
            continue;
        }
        auto value = [&]() -> const std::string& {
            if (i + 1 >= argv.size()) throw UsageError{a + " needs a value"};
            return argv[++i];
        };
        // An option given twice is refused, as in a scene file: which one was meant is unclear.
        if (const std::string name = a == "-o" ? "--output" : a; name.size() > 1 && name[0] == '-') {
            if (std::find(given.begin(), given.end(), name) != given.end()) throw UsageError{a + " is given twice: give it once"};
            given.push_back(name);
        }
        if (a == "-o" || a == "--output") args.output = value(), output_given = true;
        else if (a == "--size") parse_size(value(), args);
        else if (a == "--repeat") args.repeat = parse_positive(value(), "--repeat");
        else if (a == "--threads") args.threads = parse_positive(value(), "--threads");
        else if (a == "--spp") args.spp = parse_positive(value(), "--spp");
        else if (a == "--span") {
            const std::string name = value();
            if (!texr::parse_span_mode(name, args.span))
                throw UsageError{"unknown span mode " + texr::shown_token(name) + " (expected exact, incremental, affine8, affine16, affine32, affine or adaptive)"};
        } else if (a == "--span-tolerance") {
            tolerance_given = true;
            const std::string text = value();
            char* end = nullptr;
            args.span_tolerance = std::strtod(text.c_str(), &end);
            if (text.empty() || *end != '\0' || !(args.span_tolerance > 0.0 && args.span_tolerance <= 1000.0))
                throw UsageError{"--span-tolerance expects a number of texels above 0 and at most 1000, got " + texr::shown_token(text)};
        } else if (a == "--stats") args.stats = true;
        else if (!a.empty() && a[0] == '-') throw UsageError{unknown_option(a, "texr render")};
        else if (args.scene.empty()) args.scene = a;
        else throw UsageError{"texr render takes one scene file; '" + a + "' is one too many"};
    }
    if (args.scene.empty()) throw UsageError{"texr render needs a scene file"};
    if (tolerance_given && args.span != texr::SpanMode::adaptive)
        throw UsageError{"--span-tolerance applies to --span adaptive only (the other span modes have no tolerance)"};
    if (!output_given) args.output = default_output(args.scene);
    if (args.output.empty()) throw UsageError{"-o needs a file name"};
    try {
        texr::frame_format_for(args.output);  // reject a bad extension before any work
    } catch (const texr::InputError& e) {
        throw UsageError{e.what()};
    }
    args.output_given = output_given;
    return args;
}

double milliseconds(std::chrono::steady_clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
}

void print_stats(const texr::Scene& scene, const texr::RenderStats& s, double load_ms, double write_ms, int frames) {
    const auto per_frame = [&](std::uint64_t v) { return v / std::uint64_t(frames); };
    std::printf("triangles in       %llu\n", (unsigned long long)per_frame(s.triangles_in));
    std::printf("triangles clipped  %llu\n", (unsigned long long)per_frame(s.triangles_clipped));
    std::printf("triangles culled   %llu  (outside the view, facing away with cull back, or covering no pixel centre;"
                " each piece of a clipped triangle counts)\n",
                (unsigned long long)per_frame(s.triangles_culled));
    std::printf("triangles dropped  %llu  (NaN/Inf or zero area)\n", (unsigned long long)per_frame(s.triangles_dropped));
    std::printf("triangles set up   %llu\n", (unsigned long long)per_frame(s.triangles_set_up));
    std::printf("spans              %llu\n", (unsigned long long)per_frame(s.spans));
    std::printf("pixels shaded      %llu\n", (unsigned long long)per_frame(s.pixels_shaded));
    std::printf("texels fetched     %llu\n", (unsigned long long)per_frame(s.texels_fetched));
    for (const texr::Material& m : scene.materials)
        std::printf("material %-12s needs %s\n", texr::shown_text(m.name, texr::shown_token_bytes).c_str(),
                    texr::describe(texr::needs_of(m, scene)).c_str());
    // What each texture holds after the frames: what was built or decoded shows what was read.
    // Textures of one file share its image (and, with cell registration, its mip levels):
    // the memory is counted at the first texture that names them.
    const auto mib = [](std::size_t bytes) { return double(bytes) / 1048576.0; };
    std::map<const texr::Image*, std::string> image_of;   // image -> the first texture naming it
    std::map<const texr::MipMap*, std::string> levels_of;  // likewise for mip levels
    for (const texr::Texture& t : scene.textures) {
        if (t.procedural) {
            std::printf("texture %-12s procedural %s%s: no texels\n", texr::shown_text(t.name, texr::shown_token_bytes).c_str(),
                        texr::pattern_name(t.procedural->pattern), t.procedural->solid ? ", solid" : "");
            continue;
        }
        const texr::Image& image = *t.image;
        const auto [at_image, first_image] = image_of.emplace(&image, t.name);
        const auto [at_levels, first_levels] = levels_of.emplace(t.mipmap.get(), t.name);
        std::string line = std::to_string(image.width()) + "x" + std::to_string(image.height()) +
                           (image.is_hdr() ? " float " : " 8-bit ");
        char text[64];
        std::size_t decoded = 0;
        if (first_image) {
            std::snprintf(text, sizeof text, "%.2f MiB", mib(image.bytes()));
            line += text;
            decoded += image.decoded_bytes();
        } else {
            line += "(the image of texture " + at_image->second + ")";
        }
        if (!t.mipmap || !t.mipmap->built()) {
            line += "; mip levels not built";
        } else if (first_levels) {
            std::snprintf(text, sizeof text, "; mip levels %.2f MiB", mib(t.mipmap->bytes()));
            line += text;
            decoded += t.mipmap->decoded_bytes();
        } else {
            line += "; mip levels of texture " + at_levels->second;
        }
        if (first_image || first_levels) {
            std::snprintf(text, sizeof text, "; decoded copies %.2f MiB", mib(decoded));
            line += decoded ? text : "; decoded copies none";
        }
        std::printf("texture %-12s %s\n", texr::shown_text(t.name, texr::shown_token_bytes).c_str(), line.c_str());
    }
    std::printf("threads            %d  (worker threads: --threads, or one per core; at most one per 8 rows)\n", s.workers);
#if defined(__SSE2__)
    const char* const lanes = texr::avx2_lanes_available() ? "AVX2 and SSE2 (TEXR_NO_AVX2=1: SSE2 alone)" : "SSE2";
#else
    const char* const lanes = "none (scalar code)";
#endif
    std::printf("lanes              %s  (the same bytes either way)\n", lanes);
    std::printf("time load          %.3f ms  (scene, textures, meshes)\n", load_ms);
    // (the mean over the frames: with --repeat, the first frame's building of mip levels and
    // copies is part of it, as the median frame time printed above is not)
    if (frames > 1) std::printf("stage times        the mean over %d frames, the first included\n", frames);
    std::printf("time clear         %.3f ms%s\n", 1000.0 * s.seconds_clear / frames,
                scene.environment >= 0 ? "  (the environment map's background included)" : "");
    std::printf("time vertex        %.3f ms\n", 1000.0 * s.seconds_vertex / frames);
    std::printf("time raster        %.3f ms  (clip, setup, spans, shading)\n", 1000.0 * s.seconds_raster / frames);
    std::printf("time write         %.3f ms\n", write_ms);
}

int run_render(const std::vector<std::string>& argv) {
    if (asks_for_help(argv)) {
        std::fputs(render_help, stdout);
        return 0;
    }
    const RenderArguments args = parse_render_arguments(argv);
    // The default output goes to out/ in the current folder, made if need be; a frame that
    // cannot be written is refused before the scene is read.
    if (!args.output_given && ::mkdir("out", 0755) != 0 && errno != EEXIST)
        throw texr::InputError(args.output, 0, std::string("cannot make the default output folder 'out' here: ") + std::strerror(errno) +
                                                   " (give -o PATH)");
    texr::check_output_path(args.output);
    using Clock = std::chrono::steady_clock;

    const auto load_start = Clock::now();
    const texr::Scene scene = texr::load_scene(args.scene);
    const double load_ms = milliseconds(Clock::now() - load_start);
    texr::check_not_an_input(args.output, scene.files);

    texr::RenderOptions options;
    options.width = args.width;
    options.height = args.height;
    options.threads = args.threads;
    options.spp = args.spp;
    options.span_mode = args.span;
    options.span_tolerance = args.span_tolerance;
    texr::RenderStats stats;
    std::vector<double> frame_ms;
    texr::Framebuffer frame(0, 0, texr::Framebuffer::Uncleared{});  // drawn into frame after frame
    for (int i = 0; i < args.repeat; ++i) {
        const auto start = Clock::now();
        texr::render(scene, options, stats, frame);
        frame_ms.push_back(milliseconds(Clock::now() - start));
    }
    const auto write_start = Clock::now();
    texr::write_frame(frame, args.output);
    const double write_ms = milliseconds(Clock::now() - write_start);

    std::sort(frame_ms.begin(), frame_ms.end());
    const double median = frame_ms.size() % 2 ? frame_ms[frame_ms.size() / 2]
                                              : 0.5 * (frame_ms[frame_ms.size() / 2 - 1] + frame_ms[frame_ms.size() / 2]);
    std::printf("wrote %s (%dx%d)\n", texr::shown_path(args.output).c_str(), frame.width, frame.height);
    if (args.repeat > 1)
        std::printf("median frame time %.3f ms over %d frames (min %.3f, max %.3f)\n", median, args.repeat,
                    frame_ms.front(), frame_ms.back());
    else
        std::printf("frame time %.3f ms\n", median);
    if (args.stats) print_stats(scene, stats, load_ms, write_ms, args.repeat);
    if (stats.pixels_shaded == 0) {  // an empty frame is rarely what was meant: say why it is empty
        const auto per_frame = [&](std::uint64_t v) { return (unsigned long long)(v / std::uint64_t(args.repeat)); };
        std::fprintf(stderr,
                     "texr: note: no surface is in the frame, only the background (triangles in: %llu; culled: %llu, "
                     "counting each piece clipping made: outside the view, facing away with cull back, or covering no "
                     "pixel centre; dropped as NaN/Inf or zero area: %llu)\n",
                     per_frame(stats.triangles_in), per_frame(stats.triangles_culled), per_frame(stats.triangles_dropped));
    }
    return 0;
}

int run_explain(const std::vector<std::string>& argv) {
    if (asks_for_help(argv)) {
        std::fputs(explain_help, stdout);
        return 0;
    }
    std::vector<std::string> positional, options;
    bool names_only = false;  // after "--": SCENE, X and Y, whatever they start with
    for (std::size_t i = 0; i < argv.size(); ++i) {
        if (!names_only && argv[i] == "--") {
            names_only = true;
        } else if (names_only) {
            positional.push_back(argv[i]);
        } else if (argv[i] == "--size" || argv[i] == "--span" || argv[i] == "--span-tolerance") {
            if (i + 1 == argv.size()) throw UsageError{argv[i] + " needs a value (try texr explain --help)"};
            options.push_back(argv[i]);
            options.push_back(argv[++i]);
        } else if (!argv[i].empty() && argv[i][0] == '-' && !(argv[i].size() > 1 && std::isdigit(static_cast<unsigned char>(argv[i][1])))) {
            throw UsageError{unknown_option(argv[i], "texr explain")};
        } else {
            positional.push_back(argv[i]);
        }
    }
    if (positional.size() > 3) throw UsageError{"texr explain takes SCENE X Y; '" + positional[3] + "' is one too many"};
    if (positional.size() != 3) throw UsageError{"texr explain needs SCENE X Y (try texr explain --help)"};
    options.push_back("-o");
    options.push_back("unused.png");  // parse_render_arguments wants an output; nothing is written
    options.push_back("--");
    options.push_back(positional[0]);
    const RenderArguments args = parse_render_arguments(options);
    const texr::Scene scene = texr::load_scene(args.scene);
    texr::RenderOptions o;
    o.width = args.width, o.height = args.height, o.span_mode = args.span, o.span_tolerance = args.span_tolerance;
    const int width = o.width > 0 ? o.width : scene.width, height = o.height > 0 ? o.height : scene.height;
    const int x = parse_coordinate(positional[1], "X", width), y = parse_coordinate(positional[2], "Y", height);
    o.explain_x = x, o.explain_y = y;
    o.capture_uv = true;  // the (u, v) the span mode gave the pixel's lookup
    texr::RenderStats stats;
    const texr::Framebuffer fb = texr::render(scene, o, stats);
    texr::PixelExplanation e = *fb.explanation;
    e.span_mode = o.span_mode;
    e.uv_read = fb.uv[fb.index(x, y)];
    e.uv_read_known = e.covered && !std::isnan(e.uv_read.x) && !std::isnan(e.uv_read.y);
    e.world_read = fb.world_read[fb.index(x, y)];
    e.world_read_known = e.covered && !std::isnan(e.world_read.x);
    std::fputs(texr::describe(e, scene).c_str(), stdout);
    return 0;
}

// The exit status for a failure other than the command's own: 1 (a bad scene, an unwritable
// output), or 2 for texr compare, whose 1 means "the images differ".
int trouble_status = 1;

// texr compare (compare_help): 0 when A and B match within max_diff, 1 when not, 2 when an
// image cannot be read (usage errors: 2, by run's catch).
int run_compare(const std::vector<std::string>& argv) {
    trouble_status = 2;
    if (asks_for_help(argv)) {
        std::fputs(compare_help, stdout);
        return 0;
    }
    std::vector<std::string> files;
    int max_diff = 0;
    bool max_diff_given = false, names_only = false;  // (after "--": file names)
    for (std::size_t i = 0; i < argv.size(); ++i) {
        if (!names_only && argv[i] == "--") {
            names_only = true;
        } else if (names_only) {
            files.push_back(argv[i]);
        } else if (argv[i] == "--max-diff") {
            if (max_diff_given) throw UsageError{"--max-diff given twice"};
            if (i + 1 == argv.size()) throw UsageError{"--max-diff needs a value (try texr compare --help)"};
            const std::string& text = argv[++i];
            const std::size_t first_digit = std::min(text.find_first_not_of('0'), text.size() - 1);  // (leading zeros skipped)
            if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() - first_digit > 3 ||
                std::stoi(text.substr(first_digit)) > 255)
                throw UsageError{"--max-diff expects a whole number from 0 to 255, got " + texr::shown_token(text)};
            max_diff = std::stoi(text.substr(first_digit)), max_diff_given = true;
        } else if (argv[i].size() > 1 && argv[i][0] == '-') {
            throw UsageError{unknown_option(argv[i], "texr compare")};
        } else {
            files.push_back(argv[i]);
        }
    }
    if (files.size() > 2) throw UsageError{"texr compare takes two images A B; '" + files[2] + "' is one too many"};
    if (files.size() != 2) throw UsageError{"texr compare needs two images A B (try texr compare --help)"};
    texr::Image images[2];
    try {
        for (int k = 0; k < 2; ++k) {
            const std::string& file = files[std::size_t(k)];
            images[k] = texr::load_image(file, texr::ColorSpace::linear);
            if (images[k].is_hdr()) throw texr::InputError(file, 0, "a Radiance HDR image: texr compare reads 8-bit images");
            if (texr::image_file_is_16_bit(file))
                throw texr::InputError(file, 0, "an image of 16 bits a channel: texr compare reads 8-bit images");
        }
    } catch (const texr::InputError& e) {
        std::fprintf(stderr, "texr: %s\n", e.what());
        return 2;
    }
    const int width = images[0].width(), height = images[0].height();
    if (images[1].width() != width || images[1].height() != height) {
        std::printf("sizes differ: %dx%d against %dx%d\n", width, height, images[1].width(), images[1].height());
        return 1;
    }
    // Rows from the top (the images hold theirs bottom row first), pixels from the left.
    const texr::LdrLevel a = images[0].ldr_level(), b = images[1].ldr_level();
    std::uint64_t differing = 0, sum = 0, sum_of_squares = 0;
    int largest = 0, largest_x = 0, largest_y = 0;
    for (int y = 0; y < height; ++y) {
        const std::size_t row = std::size_t(height - 1 - y);
        for (int x = 0; x < width; ++x) {
            const std::uint8_t* p = a.texels + row * a.row_bytes + 4 * std::size_t(x);
            const std::uint8_t* q = b.texels + row * b.row_bytes + 4 * std::size_t(x);
            int pixel_largest = 0;
            for (int c = 0; c < 3; ++c) {
                const int d = std::abs(int(p[c]) - int(q[c]));
                sum += std::uint64_t(d), sum_of_squares += std::uint64_t(d * d);
                pixel_largest = std::max(pixel_largest, d);
            }
            differing += pixel_largest > 0;
            if (pixel_largest > largest) largest = pixel_largest, largest_x = x, largest_y = y;
        }
    }
    if (differing == 0) {
        std::printf("%dx%d: the same pixels\n", width, height);
        return 0;
    }
    const double channels = 3.0 * double(width) * double(height);
    std::printf("%dx%d: %llu of %llu pixels differ, by at most %d of 255 (first at pixel (%d, %d)); mean difference %.4g a "
                "channel, PSNR %.2f dB%s\n",
                width, height, static_cast<unsigned long long>(differing), static_cast<unsigned long long>(width) * height, largest,
                largest_x, largest_y, double(sum) / channels, 10.0 * std::log10(255.0 * 255.0 / (double(sum_of_squares) / channels)),
                largest <= max_diff ? (", within --max-diff " + std::to_string(max_diff)).c_str() : "");
    return largest <= max_diff ? 0 : 1;
}

// `--name=value` as the two arguments `--name value`, for the options that take a value
// (texr render's, explain's and bench's); a flag given a value is refused.
std::vector<std::string> split_option_values(const std::vector<std::string>& args) {
    static const char* const with_values[] = {"--output", "--size", "--repeat", "--threads", "--spp",
                                              "--span", "--span-tolerance", "--models", "--out", "--max-diff"};
    std::vector<std::string> out;
    bool names_only = false;  // after "--": file names, kept as they are
    for (const std::string& a : args) {
        if (names_only || a == "--") {
            names_only = true;
            out.push_back(a);
            continue;
        }
        const std::size_t equals = a.find('=');
        if (a.rfind("--", 0) != 0 || equals == std::string::npos || equals <= 2) {
            out.push_back(a);
            continue;
        }
        const std::string name = a.substr(0, equals);
        const bool takes_value = std::find(std::begin(with_values), std::end(with_values), name) != std::end(with_values);
        if (!takes_value && (name == "--stats" || name == "--quick" || name == "--help"))
            throw UsageError{name + " takes no value (give it as '" + name + "')"};
        if (!takes_value) {
            out.push_back(a);  // (an unknown option, named whole in its message)
            continue;
        }
        out.push_back(name);
        out.push_back(a.substr(equals + 1));
    }
    return out;
}

int run(const std::vector<std::string>& raw_args) {
    try {
        const std::vector<std::string> args = split_option_values(raw_args);
        if (args.empty()) {
            std::fputs(main_help, stderr);
            return 2;
        }
        const std::string command = args[0];
        if (command == "-h" || command == "--help" || command == "help") {
            std::fputs(main_help, stdout);
            return 0;
        }
        if (command == "--version") {
            std::puts("texr 0.1 (commit " TEXR_COMMIT ")");
            return 0;
        }
        if (command == "render") return run_render({args.begin() + 1, args.end()});
        if (command == "explain") return run_explain({args.begin() + 1, args.end()});
        if (command == "compare") return run_compare({args.begin() + 1, args.end()});
        if (command == "bench") {
            const std::vector<std::string> rest(args.begin() + 1, args.end());
            if (asks_for_help(rest)) {
                std::fputs(texr::bench_help, stdout);
                return 0;
            }
            try {
                return texr::run_bench(rest);
            } catch (const std::invalid_argument& e) {
                throw UsageError{e.what()};
            }
        }
        throw UsageError{"unknown command " + texr::shown_token(command) + " (try texr --help)"};
    } catch (const UsageError& e) {
        // Usage messages quote what was typed (an unknown option, a bad number, an argument
        // too many): its control bytes (a terminal's escape codes) and bytes that are not
        // UTF-8 are shown as \xNN here, for every such message at once, as words from files are.
        std::fprintf(stderr, "texr: %s\n", texr::shown_text(e.message, std::string::npos).c_str());
        return 2;
    } catch (const texr::InputError& e) {
        std::fprintf(stderr, "texr: %s\n", e.what());
        return trouble_status;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "texr: out of memory\n");
        return trouble_status;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "texr: internal error: %s\n", e.what());
        return trouble_status;
    }
}

}  // namespace

int main(int argc, char** argv) {
    texr::remove_partial_outputs_on_signals();
    const int code = run(std::vector<std::string>(argv + 1, argv + argc));
    // What texr printed (an explanation, a table, help) is lost if standard output could not
    // take it (a full disk, a closed pipe): say so, and fail.
    errno = 0;
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
        std::fprintf(stderr, "texr: could not write to standard output%s%s\n", errno ? ": " : "", errno ? std::strerror(errno) : "");
        return std::max(code, trouble_status);
    }
    return code;
}
