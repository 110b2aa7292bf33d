// How an image texture is read: reconstruction filter, wrap per axis, border colour and
// registration (where texel centres sit in [0, 1]).
//   cell (default, OpenGL): texel i has its centre at (i + 1/2) / n
//   node (the lecture's bilinear slide): texel i sits at i / (n - 1)
#pragma once
#include "texr/core/color.h"
#include "texr/texture/wrap.h"

namespace texr {

enum class Filter { nearest, bilinear };
enum class Registration { cell, node };

struct Sampler {
    Filter filter = Filter::bilinear;
    Wrap wrap_u = Wrap::repeat;
    Wrap wrap_v = Wrap::repeat;
    Color4 border{0.0f, 0.0f, 0.0f, 1.0f};
    Registration registration = Registration::cell;
};

// Texels each lookup of this filter reads (for the --stats counters).
inline int texels_per_lookup(Filter filter) { return filter == Filter::nearest ? 1 : 4; }

}  // namespace texr
