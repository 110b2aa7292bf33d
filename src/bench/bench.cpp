// texr bench: parses the command line and runs the benchmarks (src/bench/filters.cpp,
// spans.cpp, threads.cpp, scale.cpp) into out/bench/ with an index and the checked targets.
#include "texr/bench/bench.h"

#include <algorithm>
#include <fstream>
#include <stdexcept>

#include "common.h"

namespace texr {


const char* bench_help =
    "usage: texr bench [NAME...] [options]\n"
    "\n"
    "Benchmarks: the ones named, in that order, or all of them in the order below. Results\n"
    "go to out/bench/ (CSV, a Markdown table and an SVG plot per benchmark, and index.md;\n"
    "filters also writes each filter's frame and the ground truth as PNGs). The issues'\n"
    "targets that the run measures are checked against its numbers: printed, and written\n"
    "to targets.md. Each measurement is printed on stderr as it is taken; stdout gets the\n"
    "targets and the path of index.md.\n"
    "\n"
    "benchmarks:\n"
    "  filters     every texture filter on a receding plane and a grazing-angle square:\n"
    "              median frame time, covered Mpixel/s, PSNR and SSIM against a\n"
    "              supersampled ground truth\n"
    "  spans       every span mode (exact, incremental, affine8/16/32, affine, adaptive)\n"
    "              on the same scenes and a wall turned about the vertical axis: median\n"
    "              frame time, max and mean texel error\n"
    "  threads     the receding plane with nearest, bilinear, trilinear and EWA on 1\n"
    "              and 2 threads (and every core, if more): covered Mpixel/s and the\n"
    "              speed-up\n"
    "  scale       1e4..1e6 triangles at 1920x1080, frames up to 3840x2160, textures up\n"
    "              to 8192^2 with mipmaps: time, triangles/s and peak memory (all cores)\n"
    "\n"
    "options:\n"
    "  --size WxH      frame size (default 1024x768)\n"
    "  --repeat N      timed frames per measurement; the median is reported (default 7)\n"
    "  --spp N         ground truth: N x N samples per pixel, 2..64 (default 16)\n"
    "  --threads N     worker threads for the timed frames, 1..256 (default 1; scale:\n"
    "                  all cores; threads always measures 1, 2 and every core)\n"
    "  --models DIR    folder holding bench/plane.scene, bench/grazing.scene and\n"
    "                  (for spans) bench/wall.scene (default: this build's source\n"
    "                  models/)\n"
    "  --out DIR       output folder (default out/bench), made if missing and checked\n"
    "                  before any benchmark runs\n"
    "  --quick         a smoke test: 1 timed frame, 4x4 ground truth, 256x192, and\n"
    "                  scale at its smallest sizes (--size, --repeat or --spp, given\n"
    "                  anywhere, win over these)\n"
    "\n"
    "scale uses its own frame sizes (it varies them); --size applies to the others.\n";

namespace {

// A whole number in [min, max] (the same limits as texr render's: --threads 1..256; --spp
// 2..64, as texr render --spp 1 is the textures' own filters, no ground truth).
int parse_int(const std::string& text, const std::string& option, int max = 1000000000, int min = 1) {
    std::size_t used = 0;
    int v = 0;
    try {
        v = std::stoi(text, &used);
    } catch (...) {
        used = 0;
    }
    // Digits alone (std::stoi also takes leading white space and a sign).
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || used != text.size() || v < min || v > max)
        throw std::invalid_argument(option + " expects a whole number from " + std::to_string(min) + " to " + std::to_string(max) +
                                    ", got " + shown_token(text));
    return v;
}

}  // namespace

int run_bench(const std::vector<std::string>& args) {
    using namespace bench;
    BenchOptions o;
    std::vector<std::string> names;
    bool size_given = false, repeat_given = false, spp_given = false;
    std::vector<std::string> given;  // the options seen so far
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw std::invalid_argument(a + " needs a value");
            return args[++i];
        };
        // An option given twice is refused: which one was meant is unclear.
        if (a.size() > 1 && a[0] == '-') {
            if (std::find(given.begin(), given.end(), a) != given.end()) throw std::invalid_argument(a + " is given twice: give it once");
            given.push_back(a);
        }
        if (a == "--size") {
            const std::string error = parse_frame_size(value(), o.width, o.height);
            if (!error.empty()) throw std::invalid_argument(error);
            size_given = true;
        } else if (a == "--repeat") o.repeat = parse_int(value(), "--repeat"), repeat_given = true;
        else if (a == "--threads") o.threads = parse_int(value(), "--threads", 256), o.threads_given = true;
        else if (a == "--spp") o.spp = parse_int(value(), "--spp", 64, 2), spp_given = true;
        else if (a == "--models") o.models = value();
        else if (a == "--out") {
            o.out = value();
            if (o.out.empty()) throw std::invalid_argument("--out needs a folder");
        }
        else if (a == "--quick") o.quick = true;
        else if (a == "filters" || a == "spans" || a == "scale" || a == "threads") {
            if (std::find(names.begin(), names.end(), a) == names.end()) names.push_back(a);  // each runs once
        }
        else throw std::invalid_argument("unknown benchmark or option " + shown_token(a) + " (try texr bench --help)");
    }
    if (o.quick) {  // the smoke test's settings, where the command line does not give its own
        if (!repeat_given) o.repeat = 1;
        if (!spp_given) o.spp = 4;
        if (!size_given) o.width = 256, o.height = 192;
    }
    if (names.empty()) names = {"filters", "spans", "threads", "scale"};
    // The scenes are checked before anything is written (threads and scale read the plane).
    load_bench_scene(o, "plane");
    for (const std::string& name : names)
        if (name == "filters" || name == "spans") {
            load_bench_scene(o, "grazing");
            break;
        }
    if (std::find(names.begin(), names.end(), "spans") != names.end()) load_bench_scene(o, "wall");
    make_folders(o.out);
    std::vector<Target> targets;
    const auto checked = [&](std::vector<Target> more) { targets.insert(targets.end(), more.begin(), more.end()); };
    for (const std::string& name : names) {
        if (name == "filters") checked(run_filters(o));
        else if (name == "spans") checked(run_spans(o));
        else if (name == "threads") checked(run_threads(o));
        else if (name == "scale") checked(run_scale(o));
    }
    // The index lists this run's benchmarks, and those an earlier run left in the folder
    // (a run of some of them leaves the others' files), saying so.
    const struct {
        const char* name;
        const char* what;
    } listed[] = {{"filters", "every texture filter, time against error"},
                  {"spans", "span modes, time against texture coordinate error"},
                  {"threads", "nearest, bilinear, trilinear and EWA on 1 and 2 threads"},
                  {"scale", "time and memory as triangles, pixels and texture size grow"}};
    std::string index = "# texr benchmarks\n\n";
    for (const auto& b : listed) {
        const std::string name = b.name;
        const bool this_run = std::find(names.begin(), names.end(), name) != names.end();
        if (!this_run && !std::ifstream(o.out + "/" + name + ".md")) continue;
        index += "- [" + name + "](" + name + ".md): " + b.what + " ([csv](" + name + ".csv), [plot](" + name + ".svg))" +
                 (this_run ? "" : " (from an earlier run: its targets are not in targets.md)") + "\n";
    }
    index += "- [targets](targets.md): the issues' targets, checked against this run\n";
    write_text_file(o.out + "/targets.md", "# texr bench: targets\n\n" + targets_markdown(targets));
    write_text_file(o.out + "/index.md", index);
    for (const Target& t : targets)
        std::printf("target %-3s  %-62s %s%s\n", target_status(t), (t.benchmark + ": " + t.goal).c_str(), t.measured.c_str(),
                    t.not_measured.empty() ? "" : ("  (not measured: " + t.not_measured + ")").c_str());
    const int not_measured = targets_not_measured(targets);
    std::printf("%d of %zu targets met%s (%s/targets.md)\nwrote %s/index.md\n", targets_met(targets), targets.size(),
                not_measured ? (", " + std::to_string(not_measured) + " not measured as the issues ask").c_str() : "",
                shown_path(o.out).c_str(), shown_path(o.out).c_str());
    return 0;
}

}  // namespace texr
