// What texr bench writes agrees with itself and with the frames it saves: each rate is its
// row's pixels over its time, each PSNR is the saved frame's against the saved ground truth on
// the covered pixels, and each target quotes the row it is about. (A mutation-testing round
// found the bench's arithmetic untested: a rate off by 1000, PSNR over the whole frame, the
// targets reading another filter's row all passed.)
#include <doctest/doctest.h>

#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "helpers.h"
#include "texr/bench/metrics.h"
#include "texr/raster/span_modes.h"
#include "texr/render/renderer.h"
#include "texr/scene/parser.h"

using namespace texr;
using namespace texr::testing;

namespace {

// A CSV file's rows as maps from its header's column names to the cells.
std::vector<std::map<std::string, std::string>> read_csv(const std::string& path) {
    std::ifstream in(path);
    std::string line;
    std::vector<std::string> columns;
    std::vector<std::map<std::string, std::string>> rows;
    const auto split = [](const std::string& text) {
        std::vector<std::string> cells;
        std::stringstream s(text);
        for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
        return cells;
    };
    if (std::getline(in, line)) columns = split(line);
    while (std::getline(in, line)) {
        const std::vector<std::string> cells = split(line);
        std::map<std::string, std::string> row;
        for (std::size_t i = 0; i < columns.size() && i < cells.size(); ++i) row[columns[i]] = cells[i];
        rows.push_back(row);
    }
    return rows;
}

const std::map<std::string, std::string>& row_of(const std::vector<std::map<std::string, std::string>>& rows, const std::string& scene,
                                                 const std::string& column, const std::string& value) {
    for (const auto& row : rows)
        if (row.at("scene") == scene && row.at(column) == value) return row;
    FAIL("no row for " << scene << " " << value);
    return rows.front();
}

double number(const std::map<std::string, std::string>& row, const std::string& column) { return std::stod(row.at(column)); }

// The line of targets.md that starts "| benchmark | goal".
std::string target_line(const std::string& targets, const std::string& benchmark, const std::string& goal) {
    const std::size_t at = targets.find("| " + benchmark + " | " + goal);
    REQUIRE(at != std::string::npos);
    return targets.substr(at, targets.find('\n', at) - at);
}

// The number a targets.md line gives as measured (its third column).
double measured(const std::string& line) {
    std::size_t at = 0;
    for (int bar = 0; bar < 3; ++bar) at = line.find("| ", at) + 2;
    return std::stod(line.substr(at));
}

FrameBytes load_png(const std::string& path) {
    int w = 0, h = 0, channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 3);
    REQUIRE(data != nullptr);
    FrameBytes f{w, h, std::vector<std::uint8_t>(data, data + std::size_t(w) * std::size_t(h) * 3)};
    stbi_image_free(data);
    return f;
}

}  // namespace

TEST_CASE("texr bench filters and spans: rates, PSNR on the covered pixels, and targets agree with their rows and frames") {
    const std::string dir = scratch_folder("bench-tables");
    const RunResult r = run_texr("bench filters spans --quick --threads 1 --size 160x120 --out " + dir);
    CAPTURE(r.output);
    REQUIRE(r.exit_code == 0);
    const auto filters = read_csv(dir + "/filters.csv");
    const auto spans = read_csv(dir + "/spans.csv");
    const std::string targets = read_file(dir + "/targets.md");
    REQUIRE(filters.size() == 16);  // 8 filters on 2 scenes
    std::map<std::string, std::vector<bool>> coverage;
    for (const std::string scene : {"plane", "grazing"}) {
        RenderOptions options;
        options.width = 160, options.height = 120, options.count_coverage = true;
        RenderStats stats;
        const Framebuffer fb = render(load_scene(source_path("models/bench/" + scene + ".scene")), options, stats);
        for (const std::uint16_t c : fb.coverage) coverage[scene].push_back(c > 0);
    }
    for (const auto& row : filters) {
        CAPTURE(row.at("scene"));
        CAPTURE(row.at("filter"));
        // covered Mpixel/s = covered pixels / (ms 1000), each printed rounded
        const double rate = number(row, "covered_pixels") / (number(row, "frame_ms_median") * 1000.0);
        CHECK(number(row, "covered_mpix_per_s") == doctest::Approx(rate).epsilon(0.01));
        // PSNR and SSIM of the saved frame against the saved truth, on the pixels the surface
        // covers (as the renderer counts them on the scene at this size).
        const std::string stem = dir + "/filters-" + row.at("scene") + "-";
        const FrameBytes frame = load_png(stem + row.at("filter") + ".png"), truth = load_png(stem + "truth.png");
        const std::vector<bool>& covered = coverage.at(row.at("scene"));
        const std::size_t count = std::size_t(std::count(covered.begin(), covered.end(), true));
        CHECK(double(count) == number(row, "covered_pixels"));
        double sum = 0.0;
        for (std::size_t p = 0; p < covered.size(); ++p)
            for (int c = 0; covered[p] && c < 3; ++c) {
                const double d = double(frame.rgb[3 * p + std::size_t(c)]) - double(truth.rgb[3 * p + std::size_t(c)]);
                sum += d * d;
            }
        CHECK(std::fabs(number(row, "psnr_db") - 10.0 * std::log10(255.0 * 255.0 * 3.0 * double(count) / sum)) <= 0.000501);  // (printed to 3 decimals)
        CHECK(number(row, "ssim") == doctest::Approx(ssim(frame, truth, covered)).epsilon(1e-4));
    }
    // The filters' targets quote the plane's rows: bilinear's and trilinear's rates,
    // trilinear's and EWA's PSNR, EWA's time over trilinear's.
    const auto& bilinear = row_of(filters, "plane", "filter", "bilinear");
    const auto& trilinear = row_of(filters, "plane", "filter", "trilinear");
    const auto& ewa = row_of(filters, "plane", "filter", "ewa");
    // (each rounded from the same value: the table to 1 or 2 decimals, the CSV to 2 or 3)
    CHECK(std::fabs(measured(target_line(targets, "filters", "plane, bilinear: >= 120")) - number(bilinear, "covered_mpix_per_s")) <= 0.0501);
    CHECK(std::fabs(measured(target_line(targets, "filters", "plane, trilinear: >= 70")) - number(trilinear, "covered_mpix_per_s")) <= 0.0501);
    CHECK(std::fabs(measured(target_line(targets, "filters", "plane, trilinear: PSNR")) - number(trilinear, "psnr_db")) <= 0.00501);
    CHECK(std::fabs(measured(target_line(targets, "filters", "plane, EWA: PSNR")) - number(ewa, "psnr_db")) <= 0.00501);
    const double quoted = measured(target_line(targets, "filters", "plane, EWA: frame time"));
    CHECK(quoted == doctest::Approx(number(ewa, "frame_ms_median") / number(trilinear, "frame_ms_median")).epsilon(0.01));
    // Spans: the exact mode has no error, the others' largest error is at least their mean,
    // and the targets quote the adaptive mode's largest error and its time over the fastest
    // other mode's (affine included). The wall has every mode's row and no target.
    REQUIRE(spans.size() == 21);  // 7 modes on 3 scenes
    CHECK(targets.find("wall") == std::string::npos);
    for (const std::string scene : {"plane", "grazing", "wall"}) {
        CAPTURE(scene);
        double fastest_ms = INFINITY;
        for (const auto& row : spans) {
            if (row.at("scene") != scene) continue;
            CAPTURE(row.at("mode"));
            CHECK(number(row, "max_error_texels") >= number(row, "mean_error_texels"));
            if (row.at("mode") == "exact") CHECK(number(row, "max_error_texels") == 0.0);
            if (row.at("mode") == "affine") CHECK(number(row, "max_error_texels") > 1.0);  // (the wrong answer, for contrast)
            if (row.at("mode") != "adaptive") fastest_ms = std::min(fastest_ms, number(row, "frame_ms_median"));
        }
        if (scene == "wall") continue;
        // (times are printed to 1 microsecond: modes that tie there may be the fastest)
        std::vector<std::string> fastest;
        for (const auto& row : spans)
            if (row.at("scene") == scene && row.at("mode") != "adaptive" && number(row, "frame_ms_median") <= fastest_ms + 0.0011)
                fastest.push_back(row.at("mode"));
        const auto& adaptive = row_of(spans, scene, "mode", "adaptive");
        CHECK(measured(target_line(targets, "spans", scene + ", adaptive: max error")) ==
              doctest::Approx(number(adaptive, "max_error_texels")).epsilon(0.01));
        const std::string time = target_line(targets, "spans", scene + ", adaptive: frame time");
        const std::size_t at = time.find("(affine included) | ") + 20;
        CHECK(measured(time) == doctest::Approx(number(adaptive, "frame_ms_median") / fastest_ms).epsilon(0.03));
        const std::string quoted_mode = time.substr(time.find("x ", at) + 2, time.find(" (", at) - time.find("x ", at) - 2);
        CHECK(std::find(fastest.begin(), fastest.end(), quoted_mode) != fastest.end());
    }
}

TEST_CASE("texels fetched: trilinear at exactly one texel per pixel reads the base level's 4, not 8") {
    // The 256-texel checker on a unit square at distance 1, seen at 90 degrees in 512 pixels:
    // a pixel is a texel, the level of detail 0, one bilinear lookup a pixel.
    const std::string dir = scratch_folder("texels-at-one");
    write_text(dir + "/s.scene", "size 512 512\ncamera eye 0 0 1 target 0 0 0 fov 90\ntexture t file " + source_path("models/textures/checker.png") +
                                     " filter trilinear\nmaterial m texture t\n"
                                     "quad material m v -0.5 -0.5 0 0 0 v 0.5 -0.5 0 1 0 v 0.5 0.5 0 1 1 v -0.5 0.5 0 0 1\n");
    const RunResult r = run_texr("render " + dir + "/s.scene -o " + dir + "/o.ppm --stats");
    CAPTURE(r.output);
    CHECK(r.output.find("pixels shaded      65536\n") != std::string::npos);
    CHECK(r.output.find("texels fetched     262144\n") != std::string::npos);
}

TEST_CASE("texr bench spans: each error is the larger of |du| W and |dv| H against the exact mode, over the covered pixels") {
    // The bench scenes with a texture 4 times wider than high, so that an error measured in
    // the other axis's texels, or as the sum of the two, or averaged over the whole frame,
    // would be another number.
    const std::string dir = scratch_folder("bench-span-errors");
    std::string ppm = "P6\n64 16\n255\n";
    for (int i = 0; i < 64 * 16 * 3; ++i) ppm += char((i * 37) % 251);
    write_text(dir + "/wide.ppm", ppm);
    std::system(("mkdir -p " + dir + "/models/bench").c_str());
    for (const std::string scene : {"plane", "grazing", "wall"}) {
        std::string text = read_file(source_path("models/bench/" + scene + ".scene"));
        const std::string file = "../textures/detail.png";
        REQUIRE(text.find(file) != std::string::npos);
        text.replace(text.find(file), file.size(), "../../wide.ppm");
        write_text(dir + "/models/bench/" + scene + ".scene", text);
    }
    const RunResult r = run_texr("bench spans --quick --threads 1 --size 64x48 --models " + dir + "/models --out " + dir + "/out");
    CAPTURE(r.output);
    REQUIRE(r.exit_code == 0);
    const auto spans = read_csv(dir + "/out/spans.csv");
    REQUIRE(spans.size() == 21);  // 7 modes on 3 scenes
    for (const std::string scene : {"plane", "grazing", "wall"}) {
        CAPTURE(scene);
        const Scene s = load_scene(dir + "/models/bench/" + scene + ".scene");
        REQUIRE(s.textures.at(0).image->width() == 64);
        REQUIRE(s.textures.at(0).image->height() == 16);
        RenderOptions options;
        options.width = 64, options.height = 48, options.capture_uv = true, options.span_mode = SpanMode::exact;
        RenderStats stats;
        const Framebuffer exact = render(s, options, stats);
        for (const SpanMode mode : {SpanMode::exact, SpanMode::incremental, SpanMode::affine16, SpanMode::affine, SpanMode::adaptive}) {
            CAPTURE(span_mode_name(mode));
            options.span_mode = mode;
            const Framebuffer f = render(s, options, stats);
            double largest = 0.0, sum = 0.0, covered = 0.0;
            for (std::size_t i = 0; i < exact.uv.size(); ++i) {
                if (!exact.drawn(i)) continue;
                const double e = std::max(std::fabs(f.uv[i].x - exact.uv[i].x) * 64.0, std::fabs(f.uv[i].y - exact.uv[i].y) * 16.0);
                largest = std::max(largest, e), sum += e, covered += 1.0;
            }
            REQUIRE(covered > 100.0);
            const auto& row = row_of(spans, scene, "mode", span_mode_name(mode));
            CHECK(number(row, "covered_pixels") == covered);
            // (printed to 3 significant digits)
            CHECK(number(row, "max_error_texels") == doctest::Approx(largest).epsilon(0.002));
            CHECK(number(row, "mean_error_texels") == doctest::Approx(sum / covered).epsilon(0.002));
            if (mode == SpanMode::affine) CHECK(largest > 1.0);
        }
    }
    // The plot draws the exact mode's error of 0 at 1e-12, and says so: its log axis then
    // spans a few more decades than the errors, not the 300 down to where a 0 would go.
    const std::string svg = read_file(dir + "/out/spans.svg");
    CHECK(svg.find(">exact (error 0)<") != std::string::npos);
    const std::regex tick("<text x=\"94.0\" y=\"[-0-9.]+\" text-anchor=\"end\">([^<]+)</text>");
    int ticks = 0;
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), tick); it != std::sregex_iterator(); ++it, ++ticks) {
        CAPTURE((*it)[1]);
        CHECK(std::stod((*it)[1]) >= 1e-14);
    }
    CHECK(ticks >= 2);
}

TEST_CASE("texr bench filters: its targets count only at 1024x768 on 1 thread against 16x16 supersampling") {
    // A small quad on the plane's horizon (about 270 pixels of the frame), so that the frames
    // at the targets' own size are quick. Its trilinear PSNR is over 29.5 dB: met, where measured.
    const std::string dir = scratch_folder("bench-targets-as-asked");
    std::system(("mkdir -p " + dir + "/models/bench").c_str());
    const std::string scene = "size 1024 768\ncamera eye 0 1 0 target 0 0.75 -4 up 0 1 0 fov 60\ntexture t file " +
                              source_path("models/textures/detail.png") +
                              " filter trilinear\nmaterial m texture t\n"
                              "quad material m v -0.05 0 -3 0 0 v 0.05 0 -3 4 0 v 0.05 0 -3.2 4 4 v -0.05 0 -3.2 0 4\n";
    write_text(dir + "/models/bench/plane.scene", scene);
    write_text(dir + "/models/bench/grazing.scene", scene);
    int runs = 0;
    const auto statuses = [&](const std::string& options) {
        const std::string out = dir + "/out" + std::to_string(++runs);
        const RunResult r = run_texr("bench filters --repeat 1 --models " + dir + "/models --out " + out + " " + options);
        CAPTURE(r.output);
        REQUIRE(r.exit_code == 0);
        const std::string targets = read_file(out + "/targets.md");
        std::vector<std::string> last_cells;
        for (const std::string goal : {"plane, bilinear: >= 120", "plane, trilinear: >= 70", "plane, trilinear: PSNR", "plane, EWA: PSNR",
                                       "plane, EWA: frame time"}) {
            const std::string line = target_line(targets, "filters", goal);
            const std::size_t end = line.rfind(" |"), start = line.rfind("| ", end - 1) + 2;
            last_cells.push_back(line.substr(start, end - start));
        }
        return last_cells;
    };
    const std::string not_measured = "not measured: the target is for 1024x768 on 1 thread against 16x16 supersampling";
    std::vector<std::string> got = statuses("--size 1024x768 --threads 1 --spp 16");
    CHECK(got[2] == "yes");
    for (const std::string& status : got) CHECK((status == "yes" || status == "no"));
    for (const std::string options : {"--size 1024x768 --threads 2 --spp 16", "--size 1024x768 --threads 1 --spp 4",
                                      "--size 1024x767 --threads 1 --spp 16"}) {
        CAPTURE(options);
        got = statuses(options);
        for (const std::string& status : got) CHECK(status == not_measured);
    }
}
