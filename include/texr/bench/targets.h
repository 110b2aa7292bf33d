// The speed, memory and quality targets of the issues, checked against a bench run's own
// numbers: texr bench prints every checked target and writes them to targets.md (README,
// "Benchmarks").
#pragma once
#include <string>
#include <vector>

namespace texr::bench {

struct Target {
    std::string benchmark;   // filters, threads, spans or scale
    std::string goal;        // what is asked, e.g. "plane, bilinear: covered pixels >= 120 Mpx/s"
    std::string conditions;  // how this run measured it, e.g. "1024x768, 1 thread"
    std::string measured;    // e.g. "59.8 Mpx/s"
    bool met = false;
    // Non-empty when the run did not measure what the target asks (a smaller frame, another
    // thread count, --quick): why. Such a target is neither met nor missed.
    std::string not_measured;
};

// value >= threshold (at_least) or value <= threshold (at_most); NaN is never met. `measured`
// is the value with `digits` decimals (or -digits significant digits when negative) and the unit.
Target at_least(std::string benchmark, std::string goal, std::string conditions, double value, double threshold,
                const std::string& unit, int digits);
Target at_most(std::string benchmark, std::string goal, std::string conditions, double value, double threshold,
               const std::string& unit, int digits);

// Marks t as not measured (with `why`) unless the run measured it as the target asks.
void measured_as_asked(Target& t, bool as_asked, const std::string& why);
// "met", "no" or "n/a" (not measured).
const char* target_status(const Target& t);

int targets_met(const std::vector<Target>& targets);
int targets_not_measured(const std::vector<Target>& targets);
// A Markdown table of the targets and a line counting those met.
std::string targets_markdown(const std::vector<Target>& targets);

}  // namespace texr::bench
