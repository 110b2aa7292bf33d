// A small SVG scatter plot for benchmark results: one labelled point per measurement,
// one colour per series. Written by texr; no plotting library.
#pragma once
#include <string>
#include <vector>

namespace texr {

struct PlotPoint {
    std::string series, label;
    double x, y;
};

// A horizontal reference line (a target or a tolerance), labelled at its right end.
struct PlotMark {
    double y;
    std::string label;
};

struct PlotAxes {
    std::string title, x_label, y_label;
    bool log_x = true;
    bool log_y = false;
    bool connect = false;  // join each series' points in order of x: how a quantity grows
    std::vector<PlotMark> marks;
};

// Tick values for an axis over [lo, hi] (data values, lo < hi; both > 0 on a log axis): on a
// linear axis multiples of 1, 2 or 5 times a power of ten, about six of them; on a log axis
// 1, 2 and 5 times the powers of ten within it, or fewer (1 and 3, then every power of ten,
// then every second, third, ... power) so that there are at most eight, and where those give
// fewer than two, 1 to 9 times (a range about a single value: 1.5 to 4 gives 2, 3, 4).
std::vector<double> axis_ticks(double lo, double hi, bool log);
// A tick's text: "0.02", "200", "20000"; from 10^5 on and below 10^-3 as "2e5", "1e-12".
std::string tick_text(double v);
// An axis's tick texts: as tick_text, but all in the "2e4" form (0 stays "0") where one of
// them takes it, so that an axis does not read "20000, 50000, 1e5".
std::vector<std::string> tick_texts(const std::vector<double>& ticks);

// Labels are 12-pixel text: about this wide per character, for placing them apart.
constexpr double plot_label_char_width = 7.0;

// The plot. Each point's label is put beside it where it overlaps no other label or point
// and stays inside the plot area (the first such place of several, nearest first; failing
// that, the place of least overlap), with a thin line to its point when it is not adjacent.
std::string scatter_svg(const PlotAxes& axes, const std::vector<PlotPoint>& points);

}  // namespace texr
