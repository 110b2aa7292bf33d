// Targets checked against a bench run (see include/texr/bench/targets.h).
#include "texr/bench/targets.h"

#include <cstdio>
#include <utility>

#include "common.h"

namespace texr::bench {

namespace {

Target checked(std::string benchmark, std::string goal, std::string conditions, double value, const std::string& unit,
               int digits, bool met) {
    std::string measured;
    if (digits >= 0) {
        measured = fixed(value, digits);
    } else {  // significant digits
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, "%.*g", -digits, value);
        measured = buffer;
    }
    if (!unit.empty()) measured += (unit[0] == 'x' ? "" : " ") + unit;  // "1.25x", "59.8 Mpx/s"
    return {std::move(benchmark), std::move(goal), std::move(conditions), measured, met, {}};
}

}  // namespace

Target at_least(std::string benchmark, std::string goal, std::string conditions, double value, double threshold,
                const std::string& unit, int digits) {
    return checked(std::move(benchmark), std::move(goal), std::move(conditions), value, unit, digits, value >= threshold);
}

Target at_most(std::string benchmark, std::string goal, std::string conditions, double value, double threshold,
               const std::string& unit, int digits) {
    return checked(std::move(benchmark), std::move(goal), std::move(conditions), value, unit, digits, value <= threshold);
}

void measured_as_asked(Target& t, bool as_asked, const std::string& why) {
    if (as_asked) return;
    t.met = false;
    t.not_measured = why;
}

const char* target_status(const Target& t) { return t.met ? "met" : t.not_measured.empty() ? "no" : "n/a"; }

int targets_met(const std::vector<Target>& targets) {
    int met = 0;
    for (const Target& t : targets) met += t.met ? 1 : 0;
    return met;
}

int targets_not_measured(const std::vector<Target>& targets) {
    int count = 0;
    for (const Target& t : targets) count += t.not_measured.empty() ? 0 : 1;
    return count;
}

std::string targets_markdown(const std::vector<Target>& targets) {
    std::string md = "| benchmark | target | measured in this run | conditions | met |\n|---|---|---:|---|---|\n";
    for (const Target& t : targets) {
        const std::string met = t.met ? "yes" : t.not_measured.empty() ? "no" : "not measured: " + t.not_measured;
        md += "| " + t.benchmark + " | " + t.goal + " | " + t.measured + " | " + t.conditions + " | " + met + " |\n";
    }
    md += "\n" + std::to_string(targets_met(targets)) + " of " + std::to_string(targets.size()) + " targets met";
    if (const int not_measured = targets_not_measured(targets)) md += " (" + std::to_string(not_measured) + " not measured as the issues ask)";
    md += ". Times depend on the machine and on what else runs on it; the targets are the issues' "
          "(1024x768 frames; filters on 1 thread, threads on 2).\n";
    return md;
}

}  // namespace texr::bench
