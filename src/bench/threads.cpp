// texr bench threads: the receding plane at 1024x768 with nearest, bilinear, trilinear and
// EWA filtering, on 1 and 2 threads (and on every core, where there are more than 2):
// covered pixels per second and the scaling. All configurations are timed in interleaved
// rounds.
#include "common.h"

#include <cstdio>
#include <iterator>
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
    std::vector<int> thread_counts = {1, 2};
    if (usable_cores() > 2) thread_counts.push_back(usable_cores());
    const Scene base = load_bench_scene(o, "plane");
    for (const Texture& t : base.textures) t.mipmap->build();
    // Every configuration (filter x thread count) is timed in interleaved rounds
    // (time_interleaved), so that a slow spell of the host falls on the 1-thread and the
    // many-thread frames alike and the speed-ups compare frames timed side by side.
    const std::size_t per_filter = thread_counts.size();
    const Filter filters[] = {Filter::nearest, Filter::bilinear, Filter::trilinear, Filter::ewa};
    std::vector<Scene> scenes(std::size(filters), base);
    std::vector<TimedCase> cases;
    for (std::size_t f = 0; f < std::size(filters); ++f) {
        for (Texture& t : scenes[f].textures) t.sampler.filter = filters[f];
        for (int threads : thread_counts) {
            TimedCase c;
            c.scene = &scenes[f];
            c.options.width = o.width, c.options.height = o.height, c.options.threads = threads;
            c.keep_last = false;
            cases.push_back(std::move(c));
        }
    }
    time_interleaved(cases, o.repeat);
    std::vector<ThreadRow> rows;
    for (std::size_t k = 0; k < cases.size(); ++k) {
        const TimedCase& c = cases[k];
        const double single_ms = cases[k - k % per_filter].median_ms;  // the same filter on 1 thread
        rows.push_back({filter_name(filters[k / per_filter]), c.options.threads, c.median_ms,
                        double(c.stats.pixels_shaded) / (c.median_ms * 1e3), single_ms / c.median_ms});
        std::fprintf(stderr, "bench threads: %-10s %d thread(s): %8.2f ms %8.1f Mpx/s  x%.2f\n", rows.back().filter.c_str(),
                     c.options.threads, c.median_ms, rows.back().mpix_per_s, rows.back().scaling);
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
    PlotAxes axes;
    axes.title = "texr bench threads: covered pixels per second", axes.x_label = "median frame time, ms";
    axes.y_label = "covered Mpixel/s", axes.log_y = true;
    write_text_file(o.out + "/threads.svg", scatter_svg(axes, points));
}

// Issue 4's targets on 2 threads: nearest >= 400, bilinear >= 260, trilinear >= 170, EWA >= 20
// Mpx/s of covered pixels; 1 -> 2 threads >= 1.8x.
std::vector<Target> threads_targets(const BenchOptions& o, const std::vector<ThreadRow>& rows) {
    std::vector<Target> targets;
    const std::pair<const char*, double> rates[] = {{"nearest", 400.0}, {"bilinear", 260.0}, {"trilinear", 170.0}, {"ewa", 20.0}};
    for (const auto& [filter, rate] : rates)
        for (const ThreadRow& r : rows)
            if (r.filter == filter && r.threads == 2) {
                const std::string conditions = conditions_of(o.width, o.height, r.threads);
                targets.push_back(at_least("threads", std::string("plane, ") + filter + ", 2 threads: >= " + fixed(rate, 0) + " covered Mpx/s",
                                           conditions, r.mpix_per_s, rate, "Mpx/s", 1));
                targets.push_back(at_least("threads", std::string("plane, ") + filter + ": 1 -> 2 threads >= 1.8x", conditions,
                                           r.scaling, 1.8, "x", 2));
                for (std::size_t k = targets.size() - 2; k < targets.size(); ++k)
                    measured_as_asked(targets[k], o.width == 1024 && o.height == 768, "the target is for 1024x768 frames");
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
