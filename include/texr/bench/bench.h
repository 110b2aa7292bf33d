// texr bench: benchmarks that measure run time against error (README, "Benchmarks").
#pragma once
#include <string>
#include <vector>

namespace texr {

// Runs `texr bench [NAME] [options]`; returns the exit status. Throws InputError on bad
// scenes and std::invalid_argument on bad options (exit 2).
int run_bench(const std::vector<std::string>& args);

extern const char* bench_help;

}  // namespace texr
