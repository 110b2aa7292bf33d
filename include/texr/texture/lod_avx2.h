// The batched span walk's second pass with AVX2's four doubles, where the CPU has AVX2
// (checked once, at run time: texr's build targets baseline x86-64, and this one function is
// compiled for AVX2 besides). Measured on the receding plane, 1 thread, alternated runs:
// trilinear 5.91-5.99 -> 5.13-5.17 ms against SSE2's two doubles (level_of_detail_lanes).
#pragma once
#include "texr/raster/homography.h"

namespace texr {

// Whether the AVX2 lanes may run: the CPU has AVX2 (and the build is for x86-64 with g++ or
// clang), and the environment does not set TEXR_NO_AVX2 to anything but "" or "0" (which
// leaves SSE2's lanes, for the same bytes). Decided once per process. (The span walk uses
// them where it has SSE2 too: not in a build without it.)
bool avx2_lanes_available();

// For pixels k = 0, 4, 8, ... while k + 3 < n: inv_q = 1 / q[k], (u, v) times inv_q when
// `stepped` (u' and v' in, u and v out), q[k] replaced by inv_q, and lambda[k] the level of
// detail of the exact derivatives on a width x height base level: the operations of
// level_of_detail_lanes (minify.h), four pixels at a time, so the same bits. Returns the
// number of pixels done (a multiple of 4); the caller does the rest.
int levels_of_detail_avx2(const TextureHomography& h, int width, int height, bool stepped, int n, double* q, double* u,
                          double* v, double* lambda);

}  // namespace texr
