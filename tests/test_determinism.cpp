// The same scene and options give the same bytes, whatever the thread count.
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <sched.h>
#include <sys/types.h>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "helpers.h"
#include "texr/io/frame_writer.h"
#include "texr/raster/span_modes.h"
#include "texr/render/explain.h"
#include "texr/render/renderer.h"
#include "texr/scene/parser.h"

using namespace texr;

TEST_CASE("frames are byte-identical for 1, 2, 3, 5 and 16 threads") {
    for (const char* file : {"models/demo.scene", "models/bench/grazing.scene", "models/bench/plane.scene"}) {
        for (const Filter filter : {Filter::trilinear, Filter::bilinear}) {
            CAPTURE(file);
            CAPTURE(int(filter));
            // A fresh scene for every render, so the mip levels and the decoded texel copies are
            // made lazily inside it, by whichever worker first needs them.
            auto fresh_scene = [&] {
                Scene scene = load_scene(testing::source_path(file));
                for (Texture& t : scene.textures) t.sampler.filter = filter;
                return scene;
            };
            RenderOptions options;
            options.width = 203, options.height = 157;  // rows not a multiple of the band height
            options.threads = 1;
            RenderStats reference_stats;
            const Framebuffer reference = render(fresh_scene(), options, reference_stats);
            for (int threads : {2, 3, 5, 16}) {
                options.threads = threads;
                RenderStats stats;
                const Scene scene = fresh_scene();
                const Framebuffer fb = render(scene, options, stats);
                if (filter == Filter::trilinear) {
                    CHECK(scene.textures[0].mipmap->built());
                    CHECK(scene.textures[0].image->decoded_bytes() > 0u);  // (the trilinear short path reads it)
                }
                CHECK(fb.color == reference.color);
                CHECK(fb.depth == reference.depth);
                CHECK(stats.pixels_shaded == reference_stats.pixels_shaded);
                CHECK(stats.triangles_set_up == reference_stats.triangles_set_up);
                CHECK(stats.texels_fetched == reference_stats.texels_fetched);
            }
        }
    }
}

TEST_CASE("frames are byte-identical for 1, 2 and 5 threads in every span mode and with supersampling") {
    // The README's promise covers --span, --span-tolerance and --spp as well as --threads.
    for (const char* file : {"models/demo.scene", "models/bench/grazing.scene"}) {
        for (int mode = 0; mode < span_mode_count; ++mode) {
            for (const int spp : {1, 3}) {
                if (spp > 1 && mode != int(SpanMode::incremental) && mode != int(SpanMode::adaptive)) continue;
                CAPTURE(file);
                CAPTURE(mode);
                CAPTURE(spp);
                RenderOptions options;
                options.width = 131, options.height = 97;
                options.span_mode = SpanMode(mode);
                options.span_tolerance = mode == int(SpanMode::adaptive) ? 0.1 : 1.0 / 64.0;
                options.spp = spp;
                options.threads = 1;
                RenderStats reference_stats;
                const Framebuffer reference = render(load_scene(testing::source_path(file)), options, reference_stats);
                for (const int threads : {2, 5}) {
                    options.threads = threads;
                    RenderStats stats;
                    const Framebuffer fb = render(load_scene(testing::source_path(file)), options, stats);
                    CHECK(fb.color == reference.color);
                    CHECK(stats.texels_fetched == reference_stats.texels_fetched);
                }
            }
        }
    }
}

TEST_CASE("texr render writes the same bytes run after run and with --repeat") {
    const std::string dir = testing::scratch_folder("same-bytes");
    const std::string scene = testing::source_path("models/demo.scene");
    const auto frame = [&](const std::string& name, const std::string& options) {
        const testing::RunResult r = testing::run_texr("render " + scene + " --size 160x120 -o " + dir + "/" + name + " " + options);
        CAPTURE(r.output);
        CHECK(r.exit_code == 0);
        return testing::read_file(dir + "/" + name);
    };
    const std::string first = frame("first.ppm", "");
    CHECK(first.size() == std::string("P6\n160 120\n255\n").size() + 160 * 120 * 3);
    CHECK(frame("second.ppm", "") == first);
    CHECK(frame("repeated.ppm", "--repeat 3") == first);
    CHECK(frame("threads.ppm", "--threads 3 --repeat 2") == first);
}

TEST_CASE("frames are byte-identical with and without AVX2's lanes (TEXR_NO_AVX2=1)") {
    // Two processes, as the choice is made once per process; every filter whose batched walk
    // works out levels of detail, on the plane and the grazing square, 2 threads.
    const std::string dir = testing::scratch_folder("avx2-lanes");
    for (const char* file : {"models/bench/plane.scene", "models/bench/grazing.scene"})
        for (const char* filter : {"trilinear", "bilinear_mip_nearest", "nearest_mip_nearest", "bilinear"}) {
            CAPTURE(file);
            CAPTURE(filter);
            std::string scene = testing::read_file(testing::source_path(file));
            const std::size_t at = scene.find("filter trilinear");
            REQUIRE(at != std::string::npos);
            scene.replace(at, std::strlen("filter trilinear"), std::string("filter ") + filter);
            const std::size_t textures = scene.find("../textures/");
            REQUIRE(textures != std::string::npos);
            scene.replace(textures, std::strlen("../textures/"), testing::source_path("models/textures/"));
            testing::write_text(dir + "/scene.txt", scene);
            const std::string render = std::string(TEXR_BINARY) + " render " + dir + "/scene.txt --size 333x211 --threads 2 -o ";
            REQUIRE(std::system((render + dir + "/default.ppm > /dev/null").c_str()) == 0);
            REQUIRE(std::system(("TEXR_NO_AVX2=1 " + render + dir + "/sse2.ppm > /dev/null").c_str()) == 0);
            const std::string a = testing::read_file(dir + "/default.ppm"), b = testing::read_file(dir + "/sse2.ppm");
            CHECK(a.size() == 333u * 211u * 3u + std::strlen("P6\n333 211\n255\n"));
            CHECK(a == b);
        }
}

TEST_CASE("clearing rows writes the background and empty depth to exactly those rows") {
    // Widths that put rows at every phase of the colour pattern and of 16-byte alignment;
    // the last makes a frame of 16.8 MB, above the 16 MB to which frames are cleared with
    // ordinary stores: it is cleared with streaming stores.
    const Color background(0.25f, 0.5f, 0.75f), marker(-1.0f, -2.0f, -3.0f);
    for (int width : {1, 2, 3, 4, 5, 7, 13, 64, 101, 116513}) {
        CAPTURE(width);
        Framebuffer fb(width, 9, marker);
        std::fill(fb.depth.begin(), fb.depth.end(), -5.0f);
        fb.clear_rows(1, 2, background);  // odd first rows: scalar heads of every length
        fb.clear_rows(3, 5, background);
        fb.clear_rows(6, 7, background);
        fb.clear_rows(8, 8, background);  // empty: nothing
        std::size_t wrong = 0;
        for (int y = 0; y < 9; ++y)
            for (int x = 0; x < width; ++x) {
                const bool cleared = y == 1 || (y >= 3 && y < 5) || y == 6;
                const std::size_t i = fb.index(x, y);
                wrong += fb.color[i] != (cleared ? background : marker);
                wrong += fb.depth[i] != (cleared ? Framebuffer::empty_depth : -5.0f);
            }
        CHECK(wrong == 0);
    }
}

TEST_CASE("texr explain records the same pixel story for 1, 2 and 3 threads") {
    // The demo's floor (a 2-triangle chunk: drawn band by band, each band by whichever worker
    // is free), its torus (1152 quads, 2304 triangles: fixed interleaved bands) and the sky.
    const Scene scene = load_scene(testing::source_path("models/demo.scene"));
    struct Probe {
        int x, y, object;  // object -1: the background
    };
    for (const Probe& probe : {Probe{100, 560, 0}, Probe{180, 250, 1}, Probe{400, 20, -1}}) {
        const int x = probe.x, y = probe.y;
        CAPTURE(x);
        CAPTURE(y);
        RenderOptions options;
        options.explain_x = x, options.explain_y = y;
        options.threads = 1;
        RenderStats stats;
        const Framebuffer reference = render(scene, options, stats);
        REQUIRE(reference.explanation);
        CHECK(reference.explanation->covered == (probe.object >= 0));
        if (probe.object >= 0) CHECK(reference.explanation->object == probe.object);
        for (int threads : {2, 3}) {
            options.threads = threads;
            const Framebuffer fb = render(scene, options, stats);
            REQUIRE(fb.explanation);
            const PixelExplanation &a = *fb.explanation, &b = *reference.explanation;
            CHECK(a.covered == b.covered);
            CHECK(a.object == b.object);
            CHECK(a.triangle == b.triangle);
            CHECK(a.depth == b.depth);
            CHECK(a.color == b.color);
            CHECK(describe(a, scene) == describe(b, scene));
        }
    }
}

namespace {

// A k x k grid of quads (2 k^2 triangles) on the ground in front of the bench plane's camera.
Mesh ground_grid(int k, double x0, double x1, double z0, double z1) {
    Mesh m;
    m.has_uv = true;
    for (int j = 0; j <= k; ++j)
        for (int i = 0; i <= k; ++i) {
            Vertex v;
            v.position = glm::vec3(float(x0 + (x1 - x0) * i / k), 0.0f, float(z0 + (z1 - z0) * j / k));
            v.uv = {4.0 * i / k, 4.0 * j / k};
            m.vertices.push_back(v);
        }
    const auto at = [&](int a, int b) { return std::uint32_t(b * (k + 1) + a); };
    for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
            m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    m.triangle_material.assign(m.triangles.size(), 0);
    return m;
}

}  // namespace

TEST_CASE("frames are byte-identical for 1, 2 and 3 threads: meshes of several chunks between tiny objects") {
    // Two 9800-triangle grids (three chunks of 4096 triangles each: setup batches, fixed bands)
    // between 2-triangle objects (balanced bands), so the chunks alternate between the two sets
    // of batches and counters several times in a frame. (The ThreadSanitizer run of
    // ./build.sh test runs this test.)
    Scene scene = load_scene(testing::source_path("models/bench/plane.scene"));
    scene.meshes = {ground_grid(70, -4.0, 0.0, -1.0, -7.0), ground_grid(1, -1.0, 1.0, -2.0, -3.0)};
    scene.objects = {Object{1, glm::dmat4(1.0), false}, Object{0, glm::dmat4(1.0), false},
                     Object{1, glm::translate(glm::dmat4(1.0), glm::dvec3(0.5, 0.01, 0.0)), false},
                     Object{0, glm::translate(glm::dmat4(1.0), glm::dvec3(3.5, 0.0, 0.0)), false},
                     Object{1, glm::translate(glm::dmat4(1.0), glm::dvec3(-0.5, 0.02, -1.0)), false}};
    RenderOptions options;
    options.width = 160, options.height = 120;
    options.threads = 1;
    RenderStats reference_stats;
    const Framebuffer reference = render(scene, options, reference_stats);
    CHECK(reference_stats.triangles_in == 2 * 9800 + 3 * 2);
    CHECK(reference_stats.pixels_shaded > 160 * 120 / 4);
    for (int threads : {2, 3}) {
        options.threads = threads;
        RenderStats stats;
        const Framebuffer fb = render(scene, options, stats);
        CHECK(fb.color == reference.color);
        CHECK(fb.depth == reference.depth);
        CHECK(stats.pixels_shaded == reference_stats.pixels_shaded);
    }
}

TEST_CASE("the pooled worker threads give the bytes of a 1-thread frame: several callers at once, and after a release") {
    const Scene scene = load_scene(testing::source_path("models/demo.scene"));
    RenderOptions options;
    options.width = 96, options.height = 72, options.threads = 1;
    RenderStats reference_stats;
    const Framebuffer reference = render(scene, options, reference_stats);
    SUBCASE("several callers at once") {
        // The renderer keeps one pool of worker threads per process: one caller's frame gets
        // it, the others start threads of their own while it is busy.
        constexpr int callers = 3, frames = 4;
        std::vector<int> same(callers, 0);
        std::vector<std::thread> threads;
        for (int c = 0; c < callers; ++c)
            threads.emplace_back([&, c] {
                RenderOptions o = options;
                o.threads = 2 + c;  // 2, 3 and 4 workers
                for (int f = 0; f < frames; ++f) {
                    RenderStats stats;
                    const Framebuffer fb = render(scene, o, stats);
                    same[std::size_t(c)] += fb.color == reference.color && fb.depth == reference.depth;
                }
            });
        for (std::thread& t : threads) t.join();
        for (int c = 0; c < callers; ++c) CHECK(same[std::size_t(c)] == frames);
    }
    SUBCASE("release_worker_threads between frames: the next frames start new threads") {
        release_worker_threads();  // with no pool made, or none left: nothing to do
        for (int round = 0; round < 3; ++round) {
            for (int threads : {2, 3}) {
                options.threads = threads;
                RenderStats stats;
                const Framebuffer fb = render(scene, options, stats);
                CHECK(fb.color == reference.color);
                CHECK(fb.depth == reference.depth);
            }
            release_worker_threads();
        }
    }
}

namespace {

// Gives this thread back its CPU set when a test ends, also when a REQUIRE fails (the other
// tests run on this thread).
struct RestoreAffinity {
    const cpu_set_t& set;
    ~RestoreAffinity() { sched_setaffinity(0, sizeof set, &set); }
};

}  // namespace

TEST_CASE("the default thread count is the number of cores this process may run on: 1 when pinned to one core") {
    // sched_getaffinity(0) is the calling thread's set, so pinning this thread is what
    // taskset -c does to a process.
    cpu_set_t original;
    REQUIRE(sched_getaffinity(0, sizeof original, &original) == 0);
    const RestoreAffinity restore{original};
    const int allowed = CPU_COUNT(&original);
    CHECK(usable_cores() == allowed);
    CHECK(usable_cores() <= int(std::max(1u, std::thread::hardware_concurrency())));
    std::vector<int> cpus;
    for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu)
        if (CPU_ISSET(cpu, &original)) cpus.push_back(cpu);
    for (std::size_t keep = 1; keep <= std::min<std::size_t>(2, cpus.size()); ++keep) {
        cpu_set_t pinned;
        CPU_ZERO(&pinned);
        for (std::size_t i = 0; i < keep; ++i) CPU_SET(cpus[i], &pinned);
        REQUIRE(sched_setaffinity(0, sizeof pinned, &pinned) == 0);
        CHECK(usable_cores() == int(keep));
    }
}

TEST_CASE("the pool's threads follow the caller's cores: a pool grown while pinned to one core is unpinned with it") {
    // The threads a 3-thread frame drawn pinned to one core starts (the pool's two), after a
    // frame drawn with the thread's own cores again: each may run on all of those cores. (A
    // thread keeps the affinity of the thread that started it.) Threads there before (a
    // sanitizer's own, started with the first thread) are left out.
    cpu_set_t original;
    REQUIRE(sched_getaffinity(0, sizeof original, &original) == 0);
    const RestoreAffinity restore{original};
    if (CPU_COUNT(&original) < 2) {
        MESSAGE("skipped: this thread may run on one core only");
        return;
    }
    const Scene scene = load_scene(testing::source_path("models/demo.scene"));
    RenderOptions options;
    options.width = 64, options.height = 48, options.threads = 3;
    RenderStats stats;
    release_worker_threads();  // a pool made from here on
    std::thread([] {}).join();
    const auto thread_ids = [] {
        std::vector<pid_t> ids;
        for (const auto& task : std::filesystem::directory_iterator("/proc/self/task"))
            ids.push_back(pid_t(std::stol(task.path().filename().string())));
        return ids;
    };
    const std::vector<pid_t> before = thread_ids();
    int first = 0;
    while (!CPU_ISSET(first, &original)) ++first;
    cpu_set_t pinned;
    CPU_ZERO(&pinned);
    CPU_SET(first, &pinned);
    REQUIRE(sched_setaffinity(0, sizeof pinned, &pinned) == 0);
    const Framebuffer reference = render(scene, options, stats);
    REQUIRE(sched_setaffinity(0, sizeof original, &original) == 0);
    const Framebuffer unpinned = render(scene, options, stats);
    CHECK(unpinned.color == reference.color);
    int threads = 0;
    for (const pid_t tid : thread_ids()) {
        if (std::find(before.begin(), before.end(), tid) != before.end()) continue;
        cpu_set_t set;
        REQUIRE(sched_getaffinity(tid, sizeof set, &set) == 0);
        CAPTURE(tid);
        CHECK(CPU_EQUAL(&set, &original));
        ++threads;
    }
    CHECK(threads == 2);  // the pool's two
    release_worker_threads();
}

TEST_CASE("a frame drawn into a reused framebuffer is the frame render returns") {
    // The framebuffer first holds another scene's frame, larger and with every instrument on,
    // then a smaller one; each frame drawn into it must be the bytes a fresh render gives,
    // with no instrument left over from the frame before.
    const Scene demo = load_scene(testing::source_path("models/demo.scene"));
    const Scene grazing = load_scene(testing::source_path("models/bench/grazing.scene"));
    RenderOptions instrumented;
    instrumented.width = 120, instrumented.height = 90, instrumented.threads = 2;
    instrumented.count_coverage = instrumented.capture_uv = true;
    instrumented.explain_x = 60, instrumented.explain_y = 45;
    RenderOptions plain;
    plain.width = 97, plain.height = 61, plain.threads = 3;
    Framebuffer reused(0, 0, Framebuffer::Uncleared{});
    struct Step {
        const Scene* scene;
        const RenderOptions* options;
    };
    for (const Step step : {Step{&demo, &instrumented}, Step{&grazing, &plain}, Step{&demo, &plain}, Step{&grazing, &instrumented}}) {
        RenderStats fresh_stats, reused_stats;
        const Framebuffer fresh = render(*step.scene, *step.options, fresh_stats);
        render(*step.scene, *step.options, reused_stats, reused);
        CHECK(reused.width == step.options->width);
        CHECK(reused.height == step.options->height);
        CHECK(reused.color == fresh.color);
        CHECK(reused.depth == fresh.depth);
        CHECK(reused.coverage == fresh.coverage);
        CHECK(reused.coverage.size() == (step.options->count_coverage ? reused.color.size() : 0));
        REQUIRE(reused.uv.size() == fresh.uv.size());
        for (std::size_t i = 0; i < reused.uv.size(); ++i)  // (NaN where no pixel was drawn)
            CHECK(std::memcmp(&reused.uv[i], &fresh.uv[i], sizeof(glm::dvec2)) == 0);
        CHECK(bool(reused.explanation) == (step.options->explain_x >= 0));
        if (reused.explanation) {
            CHECK(reused.explanation->covered == fresh.explanation->covered);
            CHECK(reused.explanation->triangle == fresh.explanation->triangle);
            CHECK(reused.explanation->color == fresh.explanation->color);
        }
        CHECK(reused_stats.pixels_shaded == fresh_stats.pixels_shaded);
    }
}
