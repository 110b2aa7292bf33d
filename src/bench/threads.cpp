// texr bench threads: the receding plane at 1024x768 with nearest, bilinear, trilinear and
// EWA filtering, on 1 thread and on every core: covered pixels per second and the scaling.
#include "common.h"

#include <cstdio>
#include <thread>
#include <utility>

#include "texr/bench/plot.h"
#include "texr/scene/parser.h"

namespace texr::bench {

namespace {

struct ThreadRow {
    std::string filter;
    int threads;
    double frame_ms, mpix_per_s, scaling;
};

std::vector<ThreadRow> bench_threads(const BenchOptions& o) {
    const int most = std::max(2, int(std::thread::hardware_concurrency()));
    Scene scene = load_scene(o.models + "/bench/plane.scene");
    for (const Texture& t : scene.textures) t.mipmap->build();
    std::vector<ThreadRow> rows;
    for (Filter filter : {Filter::nearest, Filter::bilinear, Filter::trilinear, Filter::ewa}) {
        for (Texture& t : scene.textures) t.sampler.filter = filter;
        double single_ms = 0.0;
        for (int threads : {1, most}) {
            RenderOptions options;
            options.width = o.width, options.height = o.height, options.threads = threads;
            RenderStats stats;
            const double ms = timed_median(scene, options, o.repeat, stats);
            if (threads == 1) single_ms = ms;
            rows.push_back({filter_name(filter), threads, ms, double(stats.pixels_shaded) / (ms * 1e3), single_ms / ms});
            std::fprintf(stderr, "bench threads: %-10s %d thread(s): %8.2f ms %8.1f Mpx/s  x%.2f\n", filter_name(filter), threads,
                         ms, rows.back().mpix_per_s, rows.back().scaling);
        }
    }
    return rows;
}

void write_threads_report(const BenchOptions& o, const std::vector<ThreadRow>& rows) {
    std::string csv = "scene,width,height,threads,filter,mode,frame_ms_median,covered_mpix_per_s,speedup_over_1_thread\n";
    std::string md = "| scene | size | threads | filter | span mode | frame ms (median) | covered Mpx/s | speed-up over 1 thread |\n"
                     "|---|---|---|---|---|---:|---:|---:|\n";
    std::vector<PlotPoint> points;
    const std::string size = std::to_string(o.width) + "x" + std::to_string(o.height);
    for (const ThreadRow& r : rows) {
        csv += "plane," + std::to_string(o.width) + "," + std::to_string(o.height) + "," + std::to_string(r.threads) + "," +
               r.filter + ",incremental," + fixed(r.frame_ms, 3) + "," + fixed(r.mpix_per_s, 2) + "," + fixed(r.scaling, 3) + "\n";
        md += "| plane | " + size + " | " + std::to_string(r.threads) + " | " + r.filter + " | incremental | " + fixed(r.frame_ms, 2) +
              " | " + fixed(r.mpix_per_s, 1) + " | " + fixed(r.scaling, 2) + " |\n";
        points.push_back({std::to_string(r.threads) + " thread(s)", r.filter, r.frame_ms, r.mpix_per_s});
    }
    write_text_file(o.out + "/threads.csv", csv);
    write_text_file(o.out + "/threads.md", md);
    PlotAxes axes{"texr bench threads: covered pixels per second", "median frame time, ms", "covered Mpixel/s", true};
    axes.log_y = true;
    write_text_file(o.out + "/threads.svg", scatter_svg(axes, points));
}

// Issue 4's targets on 2 threads (this benchmark uses every core, at least 2): nearest >= 400,
// bilinear >= 260, trilinear >= 170, EWA >= 20 Mpx/s of covered pixels; 1 -> 2 threads >= 1.8x.
std::vector<Target> threads_targets(const BenchOptions& o, const std::vector<ThreadRow>& rows) {
    std::vector<Target> targets;
    const std::pair<const char*, double> rates[] = {{"nearest", 400.0}, {"bilinear", 260.0}, {"trilinear", 170.0}, {"ewa", 20.0}};
    for (const auto& [filter, rate] : rates)
        for (const ThreadRow& r : rows)
            if (r.filter == filter && r.threads > 1) {
                const std::string conditions = conditions_of(o.width, o.height, r.threads);
                targets.push_back(at_least("threads", std::string("plane, ") + filter + ", 2 threads: >= " + fixed(rate, 0) + " covered Mpx/s",
                                           conditions, r.mpix_per_s, rate, "Mpx/s", 1));
                targets.push_back(at_least("threads", std::string("plane, ") + filter + ": 1 -> 2 threads >= 1.8x", conditions,
                                           r.scaling, 1.8, "x", 2));
            }
    return targets;
}

}  // namespace

std::vector<Target> run_threads(const BenchOptions& o) {
    const std::vector<ThreadRow> rows = bench_threads(o);
    write_threads_report(o, rows);
    return threads_targets(o, rows);
}

}  // namespace texr::bench
