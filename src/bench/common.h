// Shared pieces of the benchmarks (src/bench/*.cpp): options, timing, output files.
#pragma once
#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "texr/bench/targets.h"
#include "texr/render/framebuffer.h"
#include "texr/render/renderer.h"

#ifndef TEXR_MODELS_DIR
#define TEXR_MODELS_DIR "models"
#endif

namespace texr::bench {

using Clock = std::chrono::steady_clock;
inline double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

struct BenchOptions {
    int width = 1024, height = 768, repeat = 7, spp = 16, threads = 1;
    bool threads_given = false;
    bool quick = false;  // a smoke test: small sizes everywhere
    std::string models = TEXR_MODELS_DIR, out = "out/bench";
};

double median(std::vector<double> v);
// Renders once to warm caches, then `repeat` timed frames; returns the median in ms and the
// last frame's counters (time_interleaved with one configuration).
double timed_median(const Scene& scene, const RenderOptions& options, int repeat, RenderStats& stats);
// Several configurations timed in interleaved rounds: one warm-up frame each, then `repeat`
// rounds in which each renders an untimed frame and then a timed one; the median of each.
// A slow spell of a shared host (often seconds long) then falls on every configuration
// alike, so the ratios between them hold far better than when each is timed in a block of
// its own. The untimed frame gives each timed frame the caches a renderer drawing frame
// after frame would have, whatever configuration came before it: with only timed frames,
// the span modes' `adaptive`, which follows `affine` (whose wrong coordinates read other
// texels), took 1.02-1.04x `incremental`'s time on the grazing square, with the frame
// before 1.006-1.01x (their instruction counts are within 1%).
struct TimedCase {
    const Scene* scene = nullptr;
    RenderOptions options;
    RenderStats stats;                          // the last frame's counters
    bool keep_last = true;                      // keep the last frame (filters scores it)
    Framebuffer last{1, 1, Color(0.0f)};        // the last frame, if kept
    double median_ms = 0.0;
};
void time_interleaved(std::vector<TimedCase>& cases, int repeat);
// The benchmark scene o.models/bench/NAME.scene ("plane" or "grazing"), loaded; throws
// InputError if none of its objects is drawn with a texture (each benchmark times and scores
// texture filtering, so such a scene would measure nothing).
Scene load_bench_scene(const BenchOptions& o, const std::string& name);
// The pixels a frame's surfaces cover.
std::vector<bool> covered(const Framebuffer& fb);
// Makes the folder and its parents; throws InputError naming the one that cannot be made,
// or when files cannot be written in it.
void make_folders(const std::string& path);
// Written atomically, like frames.
void write_text_file(const std::string& path, const std::string& text);
// v with `digits` decimals ("inf" for infinity).
std::string fixed(double v, int digits);

// The benchmarks: each renders, measures and writes NAME.csv, NAME.md and NAME.svg, and
// returns its targets checked against what it measured.
std::vector<Target> run_filters(const BenchOptions& o);
std::vector<Target> run_spans(const BenchOptions& o);
std::vector<Target> run_scale(const BenchOptions& o);
std::vector<Target> run_threads(const BenchOptions& o);
// "1024x768, 1 thread" (or "threads")
std::string conditions_of(int width, int height, int threads);

}  // namespace texr::bench
