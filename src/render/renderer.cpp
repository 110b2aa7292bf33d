// The frame, top to bottom (docs/design.md, "One frame"): vertex stage -> homogeneous clipping ->
// viewport and 1/256-pixel snapping -> triangle setup (edge functions, homography, planes)
// (setup_stage.h) -> scanline walk -> shading -> framebuffer (scanline.h). This file runs
// the two stages on worker threads.
#include "texr/render/renderer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "setup_stage.h"
#include "scanline.h"

namespace texr {

void RenderStats::add_counters(const RenderStats& o) {
    triangles_in += o.triangles_in;
    triangles_clipped += o.triangles_clipped;
    triangles_culled += o.triangles_culled;
    triangles_dropped += o.triangles_dropped;
    triangles_set_up += o.triangles_set_up;
    spans += o.spans;
    pixels_shaded += o.pixels_shaded;
    texels_fetched += o.texels_fetched;
}

glm::dmat4 view_matrix(const Camera& camera) { return glm::lookAtRH(camera.eye, camera.target, camera.up); }

glm::dmat4 projection_matrix(const Camera& camera, double aspect) {
    return glm::perspectiveRH_NO(glm::radians(camera.fov_y_degrees), aspect, camera.near, camera.far);
}

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Stage two, per worker: the span walk of prepared pieces over the rows a RowSet names.
class RasterStage {
public:
    RasterStage(const Scene& scene, const std::vector<Needs>& needs, const RenderOptions& options, Framebuffer& fb,
                RenderStats& stats)
        : scene_(scene), needs_(needs), options_(options), fb_(fb), stats_(stats),
          u_scratch_(std::size_t(fb.width)), v_scratch_(std::size_t(fb.width)) {
        for (const Material& m : scene.materials) finite_.push_back(shading_stays_finite(scene, m));
        avx2_lanes_ = avx2_lanes_available();
    }

    void draw(const PreparedPiece& p, const RowSet& rows) {
        if (rows.first_owned(p.s.first_row) > p.s.last_row) return;  // none of its rows are in the set
        const Material& material = scene_.materials[std::size_t(p.material)];
        PixelExplanation* explain = fb_.explanation && rows.owns(fb_.explanation->y) ? fb_.explanation.get() : nullptr;
        const DrawContext d{scene_, material, material.texture >= 0 ? &scene_.textures[std::size_t(material.texture)] : nullptr,
                            std::max(1, options_.spp), options_.span_mode, options_.span_tolerance,
                            u_scratch_.data(), v_scratch_.data(), explain, p.object, p.material, p.triangle, p.clipped,
                            finite_[std::size_t(p.material)] != 0, avx2_lanes_};
        walk_table[needs_[std::size_t(p.material)]](d, p.s, rows, fb_, stats_);
    }

private:
    const Scene& scene_;
    const std::vector<Needs>& needs_;
    const RenderOptions& options_;
    Framebuffer& fb_;
    RenderStats& stats_;
    std::vector<double> u_scratch_, v_scratch_;
    std::vector<char> finite_;  // per material: shading_stays_finite
    bool avx2_lanes_ = false;
};

// Waiting for other workers: spin for up to spin_microseconds, checking `done` (the others
// are usually close behind), then sleep. The spin is long because waking a sleeper is slow
// on a VM (its idle virtual core must be woken by the host): the 1M-triangle terrain meets
// a barrier every 4096 triangles, 245 a frame, and with a spin of 4000 loads (a few
// microseconds) two threads took 105 ms a frame against one thread's 92; spinning up to 200
// microseconds or more, 51 ms (1920x1080, this 2-core VM).
//
// A spinner keeps a core, so it spins only while the workers of every frame running in the
// process (frame_workers) fit on the cores (spin_cores): with more, spinning would
// only keep a late worker off a core. Two callers drawing 2-thread terrain frames at once
// on 2 cores took 225-243 ms a frame with spinning waiters, 102-114 ms with waiters that
// sleep at once; pinned to one core (taskset -c 0), 2 threads took 237-239 against 107 ms.
constexpr int spin_microseconds = 500;

std::atomic<int> frame_workers{0};

// The cores the thread that started the latest frame may run on (usable_cores, read once a
// frame by the caller, so that the waiters of a frame usually compare with the same number;
// a frame started by another caller meanwhile changes only whether they spin).
std::atomic<int> spin_cores{1};

// Counts `count` workers in frame_workers until it ends (or until they are taken off one by
// one as they finish).
class FrameWorkers {
public:
    explicit FrameWorkers(int count) : count_(count) { frame_workers.fetch_add(count_, std::memory_order_acq_rel); }
    ~FrameWorkers() { frame_workers.fetch_sub(count_, std::memory_order_acq_rel); }
    FrameWorkers(const FrameWorkers&) = delete;
    FrameWorkers& operator=(const FrameWorkers&) = delete;

private:
    const int count_;
};

// Spins until done() or until may_spin() turns false or the time is up; returns done().
template <class Done, class MaySpin>
bool spin_until(Done done, MaySpin may_spin) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(spin_microseconds);
    while (may_spin()) {
        for (int spin = 0; spin < 64; ++spin) {
            if (done()) return true;
#if defined(__x86_64__) || defined(__i386__)
            __builtin_ia32_pause();  // a spin-loop hint: less power, and the other hyperthread runs
#endif
        }
        if (std::chrono::steady_clock::now() >= until) break;
    }
    return done();
}

// Another process running on the same cores makes spinning a loss even when this process's
// workers fit on them: a spinner keeps a core that the late worker, or the other process,
// could use. Two texr processes each drawing 2-thread terrain frames on 2 cores took 241-248
// ms a frame (126-128 ms with this), against 107-109 ms for their 1-thread frames. A worker
// that finds it has waited for a core (the run-queue delay the kernel keeps for each
// thread, in /proc/thread-self/schedstat) for more than contended_wait since its last look
// (looks are 1 to 2 contended_check apart) stops every waiter of the process from spinning
// for the next spin_pause. (Two other signals were measured and dropped: a spin that ran its
// whole time, which a worker slow to wake from sleep also causes, so the pauses chained; and
// any rise in the involuntary context switches, which a lone process also shows before 1-5%
// of its waits. docs/benchmark-history.md has the numbers.)
constexpr auto contended_check = std::chrono::milliseconds(1);
constexpr long long contended_wait_ns = 200000;  // 0.2 ms
constexpr auto spin_pause = std::chrono::milliseconds(20);
std::atomic<std::int64_t> spin_paused_until{0};  // steady_clock ticks

bool spin_paused() {
    return std::chrono::steady_clock::now().time_since_epoch().count() < spin_paused_until.load(std::memory_order_relaxed);
}

// The calling thread's run-queue delay so far, in ns; -1 where the kernel does not say.
// (The file is opened once per thread, and again in a child of fork, whose inherited
// descriptor would name the parent's thread.)
class RunDelay {
public:
    RunDelay() = default;
    ~RunDelay() {
        if (fd_ >= 0) ::close(fd_);
    }
    RunDelay(const RunDelay&) = delete;
    RunDelay& operator=(const RunDelay&) = delete;
    long long read() {
        if (owner_ != ::getpid()) {
            if (fd_ >= 0) ::close(fd_);
            fd_ = ::open("/proc/thread-self/schedstat", O_RDONLY | O_CLOEXEC);
            owner_ = ::getpid();
        }
        if (fd_ < 0) return -1;
        char text[128];
        const ssize_t n = ::pread(fd_, text, sizeof text - 1, 0);
        if (n <= 0) return -1;
        text[n] = '\0';
        long long on_cpu = 0, waiting = 0;  // "<ns on a core> <ns runnable, waiting for one> <slices>"
        return std::sscanf(text, "%lld %lld", &on_cpu, &waiting) == 2 ? waiting : -1;
    }

private:
    int fd_ = -1;
    pid_t owner_ = 0;  // the process that opened fd_ (0: none yet)
};

// Called by a worker as it starts to wait.
void note_contention() {
    thread_local RunDelay delay;
    thread_local long long last = -1;
    thread_local std::chrono::steady_clock::time_point last_look{};
    const auto now = std::chrono::steady_clock::now();
    if (now - last_look < contended_check) return;
    const long long waited = delay.read();
    if (waited < 0) return;
    // Only a recent look is compared with: over a longer gap (between frames, or while the
    // caller did other work) a lone process's threads also wait now and then.
    if (last >= 0 && now - last_look <= 2 * contended_check && waited - last > contended_wait_ns)
        spin_paused_until.store((now + spin_pause).time_since_epoch().count(), std::memory_order_relaxed);
    last = waited, last_look = now;
}

// A worker of a running frame spins while the frames' workers fit on the cores and no pause
// is on.
template <class Done>
bool spin_until(Done done) {
    note_contention();
    return spin_until(done, [] {
        return frame_workers.load(std::memory_order_acquire) <= spin_cores.load(std::memory_order_relaxed) && !spin_paused();
    });
}

// All workers wait here until every one has arrived: they spin, then sleep on a condition
// variable, so that a worker whose core was taken by another process is not kept waiting
// by spinners for long.
class Barrier {
public:
    explicit Barrier(int count) : count_(count) {}
    struct Abandoned {};

    void wait() {
        if (count_ == 1) return;
        const int generation = generation_.load(std::memory_order_acquire);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (abandoned_.load(std::memory_order_relaxed)) throw Abandoned{};
            if (++arrived_ == count_) {  // the last to arrive releases the others
                arrived_ = 0;
                generation_.store(generation + 1, std::memory_order_release);
                woken_.notify_all();
                return;
            }
        }
        const auto released = [&] {
            return generation_.load(std::memory_order_acquire) != generation || abandoned_.load(std::memory_order_acquire);
        };
        if (!spin_until(released)) {
            std::unique_lock<std::mutex> lock(mutex_);
            woken_.wait(lock, released);
        }
        if (generation_.load(std::memory_order_acquire) == generation) throw Abandoned{};
    }

    // A worker failed: release everyone waiting (they stop with Abandoned).
    void abandon() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            abandoned_.store(true, std::memory_order_release);
        }
        woken_.notify_all();
    }

private:
    const int count_;
    std::mutex mutex_;
    std::condition_variable woken_;
    int arrived_ = 0;
    std::atomic<bool> abandoned_{false};
    std::atomic<int> generation_{0};
};

// Worker threads kept from frame to frame. Starting a thread for each frame cost its first
// worker about 0.2 ms on this VM (waking the idle core): with the pool the 1 -> 2 thread
// speed-up of the 1024x768 plane went from 1.71-1.74x to 1.79-1.81x (nearest) and from
// 1.79-1.80x to 1.84x (bilinear), in alternated runs of texr bench threads. A pool thread
// waits for the next frame's job spinning, then asleep, if it worked in the last job (see
// loop); a spare thread sleeps at once. The pool is made
// when a frame first needs it, and lives until release_worker_threads (or the process) ends
// it. A child of fork that did not release it first gets a pool of its own (the parent's
// threads are not in the child).
class WorkerPool {
public:
    // The pool of this process, or nullptr when another frame is using it (then the caller
    // starts threads of its own). Release it with done().
    static WorkerPool* acquire() {
        std::lock_guard<std::mutex> lock(made());
        WorkerPool*& pool = current();
        if (!pool || pool->owner_ != ::getpid()) pool = new WorkerPool;  // (a child's inherited pool is left alone)
        bool expected = false;
        return pool->busy_.compare_exchange_strong(expected, true) ? pool : nullptr;
    }
    void done() { busy_.store(false, std::memory_order_release); }

    // Ends the pool's threads and frees it, unless a frame is using it.
    static void end() {
        std::lock_guard<std::mutex> lock(made());
        WorkerPool*& pool = current();
        bool expected = false;
        if (!pool || pool->owner_ != ::getpid() || !pool->busy_.compare_exchange_strong(expected, true)) return;
        {
            std::lock_guard<std::mutex> state(pool->mutex_);
            pool->stopping_ = true;
            pool->generation_.fetch_add(1, std::memory_order_release);
        }
        pool->woken_.notify_all();
        for (std::thread& t : pool->threads_) t.join();
        delete pool;
        pool = nullptr;
    }

    // Runs job(1) .. job(count - 1) on pool threads while the caller runs job(0); returns when
    // every one has returned. `job` must not throw. Throws (before running anything) if a
    // thread cannot be started.
    template <class Job>
    void run(int count, Job& job) {
        follow_caller_affinity();
        while (int(threads_.size()) < count - 1) {  // (a new thread inherits the caller's CPUs)
            const int index = int(threads_.size()) + 1;
            const unsigned current = generation_.load(std::memory_order_acquire);  // the jobs before it are not its
            threads_.emplace_back([this, index, current, count] { loop(index, current, count); });
        }
        const Task task = [](void* j, int w) { (*static_cast<Job*>(j))(w); };
        {
            std::lock_guard<std::mutex> lock(mutex_);
            task_ = task, job_ = &job, count_ = count;
            remaining_.store(count - 1, std::memory_order_relaxed);
            // The pool threads are counted before they can see the job, so the count never
            // dips below the workers running; each takes itself off when its part is done,
            // and the caller when all are.
            frame_workers.fetch_add(count - 1, std::memory_order_acq_rel);
            generation_.fetch_add(1, std::memory_order_release);
        }
        woken_.notify_all();
        const FrameWorkers caller(1);
        job(0);
        if (spin_until([&] { return remaining_.load(std::memory_order_acquire) == 0; })) return;
        std::unique_lock<std::mutex> lock(mutex_);
        finished_.wait(lock, [&] { return remaining_.load(std::memory_order_acquire) == 0; });
    }

private:
    using Task = void (*)(void*, int);
    WorkerPool() : owner_(::getpid()) {}
    static std::mutex& made() {
        static std::mutex m;
        return m;
    }
    static WorkerPool*& current() {
        static WorkerPool* pool = nullptr;
        return pool;
    }

    // `seen` is the job before this thread's first; `last_count` the count of workers that
    // job will have (the thread is started for it).
    void loop(int index, unsigned seen, int last_count) {
        bool needed = true;  // whether this thread worked in the last job
        for (;;) {
            // Waiting for the next job, a thread spins (frames often come back to back) only
            // if it worked in the last job, that job's workers fitted on the cores, and the
            // frames running now leave a core free. (Spare threads of a pool once grown to
            // 16 spinning after every 2-thread frame made those frames 6.8 ms, not 1.9.)
            const auto next = [&] { return generation_.load(std::memory_order_acquire) != seen; };
            const auto may_spin = [&] {
                const int cores = spin_cores.load(std::memory_order_relaxed);
                return needed && last_count <= cores && frame_workers.load(std::memory_order_acquire) < cores && !spin_paused();
            };
            if (needed) note_contention();
            if (!spin_until(next, may_spin)) {
                std::unique_lock<std::mutex> lock(mutex_);
                woken_.wait(lock, next);
            }
            Task task;
            void* job;
            int count;
            {
                std::lock_guard<std::mutex> lock(mutex_);
                if (stopping_) return;
                seen = generation_.load(std::memory_order_acquire);
                task = task_, job = job_, count = count_;
            }
            needed = index < count, last_count = count;
            if (!needed) continue;
            task(job, index);
            frame_workers.fetch_sub(1, std::memory_order_acq_rel);
            if (remaining_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
                std::lock_guard<std::mutex> lock(mutex_);  // (so the caller cannot miss the notification)
                finished_.notify_all();
            }
        }
    }

    // The pool's threads run on the CPUs of the caller drawing with them: a thread keeps the
    // CPU affinity of the thread that started it, so a pool grown by a caller pinned to one
    // core would otherwise draw a later, unpinned caller's frames on that one core, its
    // workers spinning against each other. The threads are moved when a caller's set differs
    // from the one they were given (a failure to move them costs only speed).
    void follow_caller_affinity() {
        cpu_set_t set;
        if (sched_getaffinity(0, sizeof set, &set) != 0) return;
        if (affinity_known_ && CPU_EQUAL(&set, &affinity_)) return;
        for (std::thread& t : threads_) pthread_setaffinity_np(t.native_handle(), sizeof set, &set);
        affinity_ = set, affinity_known_ = true;
    }

    const pid_t owner_;
    cpu_set_t affinity_;  // (touched only by the caller holding busy_)
    bool affinity_known_ = false;
    std::atomic<bool> busy_{false};
    std::vector<std::thread> threads_;  // (touched only by the caller holding busy_)
    std::mutex mutex_;
    std::condition_variable woken_, finished_;
    Task task_ = nullptr;  // the current job, under mutex_
    void* job_ = nullptr;
    int count_ = 0;
    bool stopping_ = false;  // (under mutex_) end the threads
    std::atomic<unsigned> generation_{0};
    std::atomic<int> remaining_{0};
};

// What one worker writes while the others run, on cache lines of its own (two workers'
// vector ends and counters on one line made every push_back and every count a cache miss
// for the other core: setup ran 1.4x slower on two threads than on one): its counters, and
// the prepared pieces of one batch of triangles.
struct alignas(64) WorkerSlot {
    RenderStats counts;
};
struct alignas(64) PreparedBatch {
    std::vector<PreparedPiece> pieces;
};

// Triangles are prepared and drawn in chunks of this many: small enough that the prepared
// pieces stay in cache between the two stages. A chunk is prepared in batches of
// setup_batch triangles, each taken by whichever worker is free.
constexpr std::size_t chunk_triangles = 4096;
constexpr std::size_t setup_batch = 256;

// A chunk of at most this many pieces (large triangles, where the pixels are the work) is
// drawn band by band, each band of rows taken by whichever worker is free, so that a worker
// whose core is slower, or shared with another program, draws fewer bands instead of
// holding up the frame. Larger chunks keep each worker's fixed, interleaved bands: looking
// at every piece once per band would cost more than the balance gains.
constexpr std::size_t balanced_pieces = 64;

}  // namespace

void release_worker_threads() { WorkerPool::end(); }

int usable_cores() {
    // The cores the calling thread may run on (its CPU affinity, which it inherits from the
    // thread that started it: taskset, a container's cpuset), which can be fewer than the
    // machine's: hardware_concurrency counts them all.
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
    return std::max(1, int(std::thread::hardware_concurrency()));
}

Framebuffer render(const Scene& scene, const RenderOptions& options, RenderStats& stats) {
    Framebuffer fb(0, 0, Framebuffer::Uncleared{});
    render(scene, options, stats, fb);
    return fb;
}

void render(const Scene& scene, const RenderOptions& options, RenderStats& stats, Framebuffer& fb) {
    const int width = options.width > 0 ? options.width : scene.width;
    const int height = options.height > 0 ? options.height : scene.height;
    fb.resize_uncleared(width, height);  // each worker clears its own rows
    fb.coverage.clear(), fb.uv.clear(), fb.world_read.clear(), fb.explanation.reset();
    if (options.count_coverage) fb.coverage.assign(fb.color.size(), 0);
    if (options.capture_uv) fb.uv.assign(fb.color.size(), glm::dvec2(std::nan("")));
    if (options.capture_uv) fb.world_read.assign(fb.color.size(), glm::dvec3(std::nan("")));
    if (options.explain_x >= 0 && options.explain_y >= 0 && options.explain_x < width && options.explain_y < height) {
        fb.explanation = std::make_shared<PixelExplanation>();
        fb.explanation->x = options.explain_x, fb.explanation->y = options.explain_y;
        fb.explanation->width = width, fb.explanation->height = height;
    }
    std::vector<Needs> needs;
    for (const Material& m : scene.materials) needs.push_back(needs_of(m, scene));
    const glm::dmat4 view_projection = projection_matrix(scene.camera, double(width) / double(height)) * view_matrix(scene.camera);
    const GuardBand band = guard_band_for(width, height);

    // Room for every object's transformed vertices, and only for what its materials need.
    std::vector<TransformedMesh> transformed(scene.objects.size());
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const Mesh& mesh = scene.meshes[std::size_t(scene.objects[i].mesh)];
        Needs mesh_needs = 0;
        for (int m : mesh.triangle_material) mesh_needs |= needs[std::size_t(m)];
        transformed[i].clip.resize(mesh.vertices.size());
        transformed[i].code.resize(mesh.vertices.size());
        if (mesh_needs & need_world_position) transformed[i].world.resize(mesh.vertices.size());
        if (mesh_needs & need_normal) transformed[i].normal.resize(mesh.vertices.size());
    }

    // Every worker takes an equal share of the vertices; batches of triangles to set up go to
    // whichever worker is free; each worker owns interleaved bands of rows for the span walk
    // (or, for a chunk of few pieces, takes bands as it becomes free: balanced_pieces). Either
    // way one worker draws all of a band's pixels in a chunk, in submission order (the
    // batches' pieces in triangle order), so the frame is the same bytes for any number of
    // workers.
    const int cores = usable_cores();
    spin_cores.store(cores, std::memory_order_relaxed);
    const int workers = std::min(options.threads > 0 ? options.threads : cores, std::max(1, height / RowSet::band_rows));
    std::vector<WorkerSlot> slots(static_cast<std::size_t>(workers));
    Barrier barrier(workers);
    const int band_count = (height + RowSet::band_rows - 1) / RowSet::band_rows;
    // Chunks alternate between two sets of batches and counters, so that one barrier per chunk
    // suffices: a worker sets up chunk c + 1 (into the other set) while others still draw
    // chunk c, and draws chunk c + 1 only when every worker has set it up, which each does
    // after drawing chunk c.
    std::vector<PreparedBatch> batches[2] = {std::vector<PreparedBatch>(chunk_triangles / setup_batch),
                                             std::vector<PreparedBatch>(chunk_triangles / setup_batch)};
    std::atomic<std::size_t> next_batch[2] = {0, 0};  // the chunk's next batch of triangles to set up
    std::atomic<int> next_band[2] = {0, 0};           // a balanced chunk's next band to draw
    double clear_seconds = 0.0, vertex_seconds = 0.0;  // worker 0's
    const auto start = Clock::now();
    auto work = [&](int w) {
        const RowSet rows{w, workers};
        std::uint64_t background_texels = 0;  // an environment map's, read for the background
        for (int y = rows.first_owned(0); y < height; y = rows.next_owned(y + RowSet::band_rows - 1)) {
            const int last = std::min(height, y + RowSet::band_rows);
            fb.clear_rows(y, last, scene.background);
            // An environment map is the background: each pixel sees it along its own ray.
            if (scene.environment >= 0) {
                const Texture& map = scene.textures[std::size_t(scene.environment)];
                for (int row = y; row < last; ++row)
                    for (int x = 0; x < width; ++x)
                        fb.color[fb.index(x, row)] =
                            Color(environment_value(map, pixel_ray(scene.camera, width, height, x, row), background_texels));
            }
        }
        if (w == 0) clear_seconds = seconds_since(start);
        const auto share = [&](std::size_t first, std::size_t last, int k) { return first + (last - first) * std::size_t(k) / std::size_t(workers); };
        for (std::size_t i = 0; i < scene.objects.size(); ++i) {
            const Mesh& mesh = scene.meshes[std::size_t(scene.objects[i].mesh)];
            transform(mesh, scene.objects[i], view_projection, band, share(0, mesh.vertices.size(), w),
                      share(0, mesh.vertices.size(), w + 1), transformed[i]);
        }
        barrier.wait();
        if (w == 0) vertex_seconds = seconds_since(start);
        WorkerSlot& slot = slots[std::size_t(w)];
        slot.counts.texels_fetched += background_texels;
        SetupStage setup(scene, needs, options, fb, band, slot.counts);
        RasterStage raster(scene, needs, options, fb, slot.counts);
        std::size_t chunk = 0;
        for (std::size_t i = 0; i < scene.objects.size(); ++i) {
            const std::size_t n = scene.meshes[std::size_t(scene.objects[i].mesh)].triangles.size();
            for (std::size_t first = 0; first < n; first += chunk_triangles, ++chunk) {
                const std::size_t last = std::min(n, first + chunk_triangles);
                const std::size_t set = chunk % 2, batch_count = (last - first + setup_batch - 1) / setup_batch;
                std::vector<PreparedBatch>& chunk_batches = batches[set];
                for (std::size_t b; (b = next_batch[set].fetch_add(1, std::memory_order_relaxed)) < batch_count;) {
                    std::vector<PreparedPiece>& out = chunk_batches[b].pieces;
                    out.clear();
                    setup.prepare(int(i), transformed[i], first + b * setup_batch, std::min(last, first + (b + 1) * setup_batch), out);
                }
                barrier.wait();  // every batch of this chunk is prepared, and the previous chunk drawn
                if (w == 0) {
                    // Nobody takes from these two counters again before the next barrier: this
                    // chunk's batches are all taken, and the previous chunk's bands all drawn.
                    next_batch[set].store(0, std::memory_order_relaxed);
                    next_band[1 - set].store(0, std::memory_order_relaxed);
                }
                std::size_t pieces = 0;
                for (std::size_t b = 0; b < batch_count; ++b) pieces += chunk_batches[b].pieces.size();
                const auto draw_chunk = [&](const RowSet& rows_of_worker) {
                    for (std::size_t b = 0; b < batch_count; ++b)
                        for (const PreparedPiece& piece : chunk_batches[b].pieces) raster.draw(piece, rows_of_worker);
                };
                if (workers > 1 && pieces <= balanced_pieces) {
                    // One band at a time: RowSet{b, band_count} holds band b alone.
                    for (int b; (b = next_band[set].fetch_add(1, std::memory_order_relaxed)) < band_count;)
                        draw_chunk(RowSet{b, band_count});
                } else {
                    draw_chunk(RowSet{w, workers});
                }
            }
        }
    };
    // An exception in a worker (out of memory while building mip levels, say) must reach the
    // caller, not terminate the program; the other workers must not wait for it forever.
    std::vector<std::exception_ptr> failures(static_cast<std::size_t>(workers));
    auto guarded = [&](int w) {
        try {
            work(w);
        } catch (const Barrier::Abandoned&) {
            // another worker failed; its exception is the one reported
        } catch (...) {
            failures[std::size_t(w)] = std::current_exception();
            barrier.abandon();
        }
    };
    if (workers == 1) {
        guarded(0);
    } else if (WorkerPool* pool = WorkerPool::acquire()) {
        struct Release {
            WorkerPool* pool;
            ~Release() { pool->done(); }
        } release{pool};
        pool->run(workers, guarded);  // (a thread that cannot be started throws before any work)
    } else {  // another frame is using the pool: threads of this frame's own
        const FrameWorkers counted(workers);
        std::vector<std::thread> threads;
        threads.reserve(std::size_t(workers - 1));
        try {
            for (int t = 1; t < workers; ++t) threads.emplace_back(guarded, t);
        } catch (...) {  // a thread could not be started: release and join the others, then report
            barrier.abandon();
            for (std::thread& t : threads) t.join();
            throw;
        }
        guarded(0);
        for (std::thread& t : threads) t.join();
    }
    for (const std::exception_ptr& e : failures)
        if (e) std::rethrow_exception(e);
    for (const WorkerSlot& slot : slots) stats.add_counters(slot.counts);
    stats.workers = workers;
    stats.seconds_clear += clear_seconds;
    stats.seconds_vertex += vertex_seconds - clear_seconds;
    stats.seconds_raster += seconds_since(start) - vertex_seconds;
}

}  // namespace texr
