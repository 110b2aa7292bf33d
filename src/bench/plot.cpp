// SVG scatter plot (see include/texr/bench/plot.h).
#include "texr/bench/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace texr {

namespace {

std::string number(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.3g", v);
    return buffer;
}

std::string escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else if (c == '&') out += "&amp;";
        else out += c;
    }
    return out;
}

}  // namespace

std::string scatter_svg(const PlotAxes& axes, const std::vector<PlotPoint>& points) {
    const double width = 900, height = 560, left = 100, right = 230, top = 50, bottom = 70;
    const auto fx = [&](double x) { return axes.log_x ? std::log10(std::max(x, 1e-12)) : x; };
    const auto fy = [&](double y) { return axes.log_y ? std::log10(std::max(y, 1e-12)) : y; };
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const auto& p : points) {
        if (!std::isfinite(p.y)) continue;
        x0 = std::min(x0, fx(p.x)), x1 = std::max(x1, fx(p.x));
        y0 = std::min(y0, fy(p.y)), y1 = std::max(y1, fy(p.y));
    }
    if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    const double xpad = std::max(0.05 * (x1 - x0), 0.05), ypad = std::max(0.08 * (y1 - y0), 0.5);
    x0 -= xpad, x1 += xpad, y0 -= ypad, y1 += ypad;
    const double plot_w = width - left - right, plot_h = height - top - bottom;
    const auto sx = [&](double x) { return left + (fx(x) - x0) / (x1 - x0) * plot_w; };
    const auto sy = [&](double y) { return top + (y1 - fy(y)) / (y1 - y0) * plot_h; };
    const auto sy_axis = [&](double y) { return top + (y1 - y) / (y1 - y0) * plot_h; };

    std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + number(width) + "\" height=\"" +
                      number(height) + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    svg += "<text x=\"" + number(width / 2) + "\" y=\"28\" text-anchor=\"middle\" font-size=\"16\">" + escape(axes.title) + "</text>\n";
    // Axes and ticks.
    svg += "<rect x=\"" + number(left) + "\" y=\"" + number(top) + "\" width=\"" + number(plot_w) + "\" height=\"" +
           number(plot_h) + "\" fill=\"none\" stroke=\"black\"/>\n";
    for (int k = 0; k <= 5; ++k) {
        const double y = y0 + (y1 - y0) * k / 5.0;
        svg += "<line x1=\"" + number(left) + "\" x2=\"" + number(left + plot_w) + "\" y1=\"" + number(sy_axis(y)) + "\" y2=\"" +
               number(sy_axis(y)) + "\" stroke=\"#ddd\"/>\n";
        svg += "<text x=\"" + number(left - 6) + "\" y=\"" + number(sy_axis(y) + 4) + "\" text-anchor=\"end\">" +
               number(axes.log_y ? std::pow(10.0, y) : y) + "</text>\n";
        const double xv = x0 + (x1 - x0) * k / 5.0;
        const double shown = axes.log_x ? std::pow(10.0, xv) : xv;
        const double px = left + plot_w * k / 5.0;
        svg += "<line x1=\"" + number(px) + "\" x2=\"" + number(px) + "\" y1=\"" + number(top) + "\" y2=\"" +
               number(top + plot_h) + "\" stroke=\"#ddd\"/>\n";
        svg += "<text x=\"" + number(px) + "\" y=\"" + number(top + plot_h + 18) + "\" text-anchor=\"middle\">" + number(shown) + "</text>\n";
    }
    svg += "<text x=\"" + number(left + plot_w / 2) + "\" y=\"" + number(height - 20) + "\" text-anchor=\"middle\">" +
           escape(axes.x_label) + (axes.log_x ? " (log scale)" : "") + "</text>\n";
    svg += "<text transform=\"translate(18," + number(top + plot_h / 2) + ") rotate(-90)\" text-anchor=\"middle\">" +
           escape(axes.y_label) + (axes.log_y ? " (log scale)" : "") + "</text>\n";
    // Points, one colour per series.
    const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf"};
    std::map<std::string, int> series;
    for (const auto& p : points) series.emplace(p.series, int(series.size()));
    for (const auto& p : points) {
        if (!std::isfinite(p.y)) continue;
        const char* colour = colours[series[p.series] % 6];
        svg += "<circle cx=\"" + number(sx(p.x)) + "\" cy=\"" + number(sy(p.y)) + "\" r=\"5\" fill=\"" + colour + "\"/>\n";
        svg += "<text x=\"" + number(sx(p.x) + 7) + "\" y=\"" + number(sy(p.y) - 6) + "\" fill=\"" + colour + "\">" +
               escape(p.label) + "</text>\n";
    }
    int row = 0;
    for (const auto& [name, index] : series) {
        const double y = top + 10 + 20 * row++;
        svg += "<circle cx=\"" + number(width - right + 20) + "\" cy=\"" + number(y) + "\" r=\"5\" fill=\"" + colours[index % 6] + "\"/>\n";
        svg += "<text x=\"" + number(width - right + 30) + "\" y=\"" + number(y + 4) + "\">" + escape(name) + "</text>\n";
    }
    svg += "</svg>\n";
    return svg;
}

}  // namespace texr
