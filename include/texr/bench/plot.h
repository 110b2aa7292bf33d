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

struct PlotAxes {
    std::string title, x_label, y_label;
    bool log_x = true;
    bool log_y = false;
};

std::string scatter_svg(const PlotAxes& axes, const std::vector<PlotPoint>& points);

}  // namespace texr
