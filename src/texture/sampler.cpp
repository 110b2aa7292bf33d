// Filter names as the scene format and the benchmarks write them.
#include "texr/texture/sampler.h"

namespace texr {

namespace {
const char* const filter_names[filter_count] = {"nearest",   "bilinear", "bicubic",     "nearest_mip_nearest",
                                                "bilinear_mip_nearest", "trilinear", "anisotropic", "ewa"};
}

const char* filter_name(Filter f) { return filter_names[int(f)]; }

bool parse_filter(const std::string& name, Filter& out) {
    for (int i = 0; i < filter_count; ++i)
        if (name == filter_names[i]) {
            out = Filter(i);
            return true;
        }
    return false;
}

}  // namespace texr
