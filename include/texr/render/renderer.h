// One frame: vertex stage, clipping, triangle setup, scanline walk, shading (docs/design.md, "One frame").
#pragma once
#include <string>
#include <vector>

#include "texr/raster/span_modes.h"
#include "texr/render/framebuffer.h"
#include "texr/render/stats.h"
#include "texr/scene/scene.h"

namespace texr {

struct RenderOptions {
    int width = 0, height = 0;  // 0: the scene's size
    // Texture ground truth: spp x spp samples per pixel at the centres of equal sub-pixel
    // cells (a regular grid, no jitter), each a bilinear lookup in the base level at its own
    // exact (u, v), box-filtered. 1 = the textures' own filters.
    int spp = 1;
    // Worker threads; 0 = one per core the calling thread may use (usable_cores). The frame is the same bytes for every count.
    int threads = 0;
    // How (u, v) are computed along spans (raster/span_modes.h) and, for `adaptive`, the
    // largest error allowed in texels.
    SpanMode span_mode = SpanMode::incremental;
    double span_tolerance = 1.0 / 64.0;
    bool count_coverage = false;  // fill Framebuffer::coverage (tests)
    bool capture_uv = false;      // fill Framebuffer::uv with each visible pixel's (u, v) (benchmarks), and world_read
    int explain_x = -1, explain_y = -1;  // texr explain: record this pixel's story in Framebuffer::explanation
};

Framebuffer render(const Scene& scene, const RenderOptions& options, RenderStats& stats);
// The same frame, drawn into `frame`, whose buffers are reused (resized to the frame's size;
// its coverage, (u, v) and explanation are replaced as `options` asks): for drawing frame
// after frame. The result is the same bytes as render's.
void render(const Scene& scene, const RenderOptions& options, RenderStats& stats, Framebuffer& frame);

// The renderer keeps its worker threads from frame to frame. This ends them (unless a frame
// is being drawn); the next frame starts new ones. For a caller about to fork: a child of a
// process with other threads may not safely start threads of its own.
void release_worker_threads();

// The cores the calling thread may run on (its CPU affinity, inherited from the thread that
// started it: taskset, a container's cpuset), at least 1. The default thread count, read
// when each frame starts.
int usable_cores();

// Camera matrices for a frame of the given aspect ratio (OpenGL conventions: right-handed,
// y up, looking down -z, clip z in [-w, w]).
glm::dmat4 view_matrix(const Camera& camera);
glm::dmat4 projection_matrix(const Camera& camera, double aspect);

}  // namespace texr
