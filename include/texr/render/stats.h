// Per-frame counters and stage times (texr render --stats).
#pragma once
#include <cstdint>
#include <string>

namespace texr {

struct RenderStats {
    std::uint64_t triangles_in = 0;       // triangles submitted
    std::uint64_t triangles_clipped = 0;  // needed clipping against a plane
    std::uint64_t triangles_culled = 0;   // back-facing, or no pixel centre in its box: no setup
    std::uint64_t triangles_dropped = 0;  // NaN/Inf vertices or zero area
    std::uint64_t triangles_set_up = 0;   // edge functions and planes computed
    std::uint64_t spans = 0;              // non-empty row spans walked
    std::uint64_t pixels_shaded = 0;      // fragments that passed the depth test
    std::uint64_t texels_fetched = 0;
    double seconds_clear = 0.0;           // the frame's colour and depth set to "nothing here"
    double seconds_vertex = 0.0;          // object -> clip for every vertex
    double seconds_raster = 0.0;          // clipping, setup, span walk and shading
    int workers = 0;                      // worker threads of the last frame: --threads (default: the
                                          // cores), at most one per 8 rows

    void add_counters(const RenderStats& other);
};

}  // namespace texr
