// SVG scatter plot (see include/texr/bench/plot.h).
#include "texr/bench/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace texr {

namespace {

std::string coordinate(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.1f", v);
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

struct Box {
    double x0, y0, x1, y1;
    double overlap(const Box& o) const {
        const double w = std::min(x1, o.x1) - std::max(x0, o.x0), h = std::min(y1, o.y1) - std::max(y0, o.y0);
        return w > 0.0 && h > 0.0 ? w * h : 0.0;
    }
};

// A label's box with its text anchored at (x, y) (the baseline), anchor -1 start, 0 middle,
// +1 end.
Box label_box(const std::string& text, double x, double y, int anchor) {
    const double w = plot_label_char_width * double(text.size());
    const double x0 = anchor < 0 ? x : anchor == 0 ? x - w / 2 : x - w;
    return {x0, y - 10.0, x0 + w, y + 3.0};
}

}  // namespace

std::vector<double> axis_ticks(double lo, double hi, bool log) {
    std::vector<double> ticks;
    if (!(lo < hi) || !std::isfinite(lo) || !std::isfinite(hi) || (log && !(lo > 0.0))) return ticks;
    if (!log) {
        const double raw = (hi - lo) / 6.0, magnitude = std::pow(10.0, std::floor(std::log10(raw)));
        double step = 10.0 * magnitude;
        for (double m : {1.0, 2.0, 5.0})
            if (m * magnitude >= raw) {
                step = m * magnitude;
                break;
            }
        // (at most a dozen; a range a few roundings wide at a large value gives none). The top
        // tick may be a rounding above hi, by a billionth of a step: a slack relative to hi
        // would take a whole step more at large values (1e12 to 1e12 + 6 gave 1e12 + 7).
        if (!(step >= 1e-13 * std::max(std::fabs(lo), std::fabs(hi)))) return ticks;  // (ticks a few hundred roundings apart at least)
        const double first = std::ceil(lo / step), count = std::floor(hi / step + 1e-9) - first;
        if (!(count >= 0.0 && count <= 12.0)) return ticks;
        for (int k = 0; k <= int(count); ++k) ticks.push_back((first + k) * step == 0.0 ? 0.0 : (first + k) * step);
        return ticks;
    }
    const int first = int(std::floor(std::log10(lo))), last = int(std::ceil(std::log10(hi)));
    const auto inside = [&](double v) { return v >= lo * (1.0 - 1e-12) && v <= hi * (1.0 + 1e-12); };
    // (1 to 9 times: a range within a decade or so, such as about a single value, where the
    // others give at most one tick; 1.5 to 4 gave none)
    for (const std::vector<double>& mantissas :
         {std::vector<double>{1, 2, 5}, std::vector<double>{1, 3}, std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8, 9}}) {
        ticks.clear();
        for (int e = first; e <= last; ++e)
            for (double m : mantissas)
                if (inside(m * std::pow(10.0, e))) ticks.push_back(m * std::pow(10.0, e));
        if (ticks.size() <= 8 && ticks.size() >= 2) return ticks;
    }
    for (int every = 1;; ++every) {  // powers of ten whose exponent is a multiple of `every`
        ticks.clear();
        for (int e = first; e <= last; ++e)
            if (e % every == 0 && inside(std::pow(10.0, e))) ticks.push_back(std::pow(10.0, e));
        if (ticks.size() <= 8) return ticks;
    }
}

namespace {
bool exponent_form(double v) {
    const double a = std::fabs(v);
    return a != 0.0 && (a >= 1e5 || a < 1e-3);
}
std::string tick_text_in(double v, bool exponent) {
    char buffer[48];
    const double a = std::fabs(v);
    if (a != 0.0 && exponent) {
        int e = int(std::floor(std::log10(a)));
        double m = v / std::pow(10.0, e);
        // (rounding to 3 digits may carry into the next power: 9.995 and up print as 10)
        if (std::fabs(m) >= 9.995) m /= 10.0, ++e;
        std::snprintf(buffer, sizeof buffer, "%.3ge%d", m, e);
        return buffer;
    }
    std::snprintf(buffer, sizeof buffer, "%.6g", v);
    return buffer;
}
}  // namespace

std::string tick_text(double v) { return tick_text_in(v, exponent_form(v)); }

std::vector<std::string> tick_texts(const std::vector<double>& ticks) {
    const bool exponent = std::any_of(ticks.begin(), ticks.end(), exponent_form);
    std::vector<std::string> texts;
    for (const double t : ticks) texts.push_back(tick_text_in(t, exponent));
    return texts;
}

std::string scatter_svg(const PlotAxes& axes, const std::vector<PlotPoint>& points) {
    const double width = 900, height = 560, left = 100, right = 230, top = 50, bottom = 70;
    const auto fx = [&](double x) { return axes.log_x ? std::log10(std::max(x, 1e-300)) : x; };
    const auto fy = [&](double y) { return axes.log_y ? std::log10(std::max(y, 1e-300)) : y; };
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    const auto shown = [&](const PlotPoint& p) { return std::isfinite(p.x) && std::isfinite(p.y); };
    for (const auto& p : points) {
        if (!shown(p)) continue;
        x0 = std::min(x0, fx(p.x)), x1 = std::max(x1, fx(p.x));
        y0 = std::min(y0, fy(p.y)), y1 = std::max(y1, fy(p.y));
    }
    const auto mark_shown = [&](const PlotMark& m) { return std::isfinite(m.y) && (!axes.log_y || m.y > 0.0); };
    for (const PlotMark& m : axes.marks)
        if (mark_shown(m)) y0 = std::min(y0, fy(m.y)), y1 = std::max(y1, fy(m.y));
    if (x0 > x1) x0 = 0, x1 = 1;
    if (y0 > y1) y0 = 0, y1 = 1;
    // Margins: 5% of the range each side (on a log axis a quarter of a decade at least, so
    // that a single value still gets ticks either side).
    const double xpad = std::max(0.05 * (x1 - x0), axes.log_x ? 0.25 : 0.05), ypad = std::max(0.08 * (y1 - y0), axes.log_y ? 0.25 : 0.5);
    x0 -= xpad, x1 += xpad, y0 -= ypad, y1 += ypad;
    // (a log axis reaching 1e-300, where values of 0 are put, stays where 10^x is a double)
    if (axes.log_x) x0 = std::max(x0, -300.0);
    if (axes.log_y) y0 = std::max(y0, -300.0);
    const double plot_w = width - left - right, plot_h = height - top - bottom;
    const auto px = [&](double axis) { return left + (axis - x0) / (x1 - x0) * plot_w; };  // axis units -> pixels
    const auto py = [&](double axis) { return top + (y1 - axis) / (y1 - y0) * plot_h; };
    const auto sx = [&](double x) { return px(fx(x)); };
    const auto sy = [&](double y) { return py(fy(y)); };

    std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + coordinate(width) + "\" height=\"" +
                      coordinate(height) + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    svg += "<text x=\"" + coordinate(width / 2) + "\" y=\"28\" text-anchor=\"middle\" font-size=\"16\">" + escape(axes.title) + "</text>\n";
    // Grid lines and ticks at round values.
    const auto to_data = [](double axis, bool log) { return log ? std::pow(10.0, axis) : axis; };
    const std::vector<double> y_ticks = axis_ticks(to_data(y0, axes.log_y), to_data(y1, axes.log_y), axes.log_y);
    const std::vector<std::string> y_texts = tick_texts(y_ticks);
    for (std::size_t i = 0; i < y_ticks.size(); ++i) {
        const double y = sy(y_ticks[i]);
        svg += "<line x1=\"" + coordinate(left) + "\" x2=\"" + coordinate(left + plot_w) + "\" y1=\"" + coordinate(y) + "\" y2=\"" +
               coordinate(y) + "\" stroke=\"#ddd\"/>\n";
        svg += "<text x=\"" + coordinate(left - 6) + "\" y=\"" + coordinate(y + 4) + "\" text-anchor=\"end\">" + y_texts[i] + "</text>\n";
    }
    const std::vector<double> x_ticks = axis_ticks(to_data(x0, axes.log_x), to_data(x1, axes.log_x), axes.log_x);
    const std::vector<std::string> x_texts = tick_texts(x_ticks);
    for (std::size_t i = 0; i < x_ticks.size(); ++i) {
        const double x = sx(x_ticks[i]);
        svg += "<line x1=\"" + coordinate(x) + "\" x2=\"" + coordinate(x) + "\" y1=\"" + coordinate(top) + "\" y2=\"" +
               coordinate(top + plot_h) + "\" stroke=\"#ddd\"/>\n";
        svg += "<text x=\"" + coordinate(x) + "\" y=\"" + coordinate(top + plot_h + 18) + "\" text-anchor=\"middle\">" + x_texts[i] +
               "</text>\n";
    }
    svg += "<rect x=\"" + coordinate(left) + "\" y=\"" + coordinate(top) + "\" width=\"" + coordinate(plot_w) + "\" height=\"" +
           coordinate(plot_h) + "\" fill=\"none\" stroke=\"black\"/>\n";
    svg += "<text x=\"" + coordinate(left + plot_w / 2) + "\" y=\"" + coordinate(height - 20) + "\" text-anchor=\"middle\">" +
           escape(axes.x_label) + (axes.log_x ? " (log scale)" : "") + "</text>\n";
    svg += "<text transform=\"translate(18," + coordinate(top + plot_h / 2) + ") rotate(-90)\" text-anchor=\"middle\">" +
           escape(axes.y_label) + (axes.log_y ? " (log scale)" : "") + "</text>\n";

    // What labels must keep clear of: every point, the reference lines' labels, labels placed.
    std::vector<Box> taken;
    for (const auto& p : points)
        if (shown(p)) taken.push_back({sx(p.x) - 6, sy(p.y) - 6, sx(p.x) + 6, sy(p.y) + 6});
    for (const PlotMark& m : axes.marks) {
        if (!mark_shown(m)) continue;
        const double y = sy(m.y);
        svg += "<line x1=\"" + coordinate(left) + "\" x2=\"" + coordinate(left + plot_w) + "\" y1=\"" + coordinate(y) + "\" y2=\"" +
               coordinate(y) + "\" stroke=\"#555\" stroke-dasharray=\"6 4\"/>\n";
        const double lx = left + plot_w - 4, ly = y - 4;
        svg += "<text class=\"mark\" x=\"" + coordinate(lx) + "\" y=\"" + coordinate(ly) + "\" text-anchor=\"end\" fill=\"#555\">" +
               escape(m.label) + "</text>\n";
        taken.push_back(label_box(m.label, lx, ly, 1));
        taken.push_back({left, y - 1.5, left + plot_w, y + 1.5});  // (text across the line is harder to read)
    }

    const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf"};
    std::map<std::string, int> series;
    for (const auto& p : points) series.emplace(p.series, int(series.size()));
    // Lines joining each series' points in order of x.
    if (axes.connect)
        for (const auto& [name, index] : series) {
            std::vector<const PlotPoint*> line;
            for (const auto& p : points)
                if (p.series == name && shown(p)) line.push_back(&p);
            std::stable_sort(line.begin(), line.end(), [](const PlotPoint* a, const PlotPoint* b) { return a->x < b->x; });
            if (line.size() < 2) continue;
            std::string path;
            for (const PlotPoint* p : line) path += (path.empty() ? "M" : " L") + coordinate(sx(p->x)) + " " + coordinate(sy(p->y));
            // The line, as small boxes every few pixels along it, for labels to keep clear of.
            for (std::size_t k = 1; k < line.size(); ++k) {
                const double ax = sx(line[k - 1]->x), ay = sy(line[k - 1]->y), bx = sx(line[k]->x), by = sy(line[k]->y);
                const int steps = int(std::hypot(bx - ax, by - ay) / 4.0) + 1;
                for (int i = 0; i <= steps; ++i) {
                    const double t = double(i) / steps, x = ax + t * (bx - ax), y = ay + t * (by - ay);
                    taken.push_back({x - 1.5, y - 1.5, x + 1.5, y + 1.5});
                }
            }
            svg += "<path d=\"" + path + "\" fill=\"none\" stroke=\"" + colours[index % 6] + "\" stroke-width=\"1.5\"/>\n";
        }
    for (const auto& p : points) {
        if (!shown(p)) continue;
        svg += "<circle cx=\"" + coordinate(sx(p.x)) + "\" cy=\"" + coordinate(sy(p.y)) + "\" r=\"5\" fill=\"" + colours[series[p.series] % 6] +
               "\"/>\n";
    }
    // Labels, in the order of the points: the first place around the point (nearest first)
    // that overlaps nothing taken and stays in the plot, else the nearest of least overlap.
    struct Place {
        double dx, dy;
        int anchor;
    };
    static const Place places[] = {
        {8, -5, -1}, {8, 14, -1}, {-8, -5, 1}, {-8, 14, 1}, {0, -10, 0}, {0, 21, 0},           // beside the point
        {10, -18, -1}, {10, 27, -1}, {-10, -18, 1}, {-10, 27, 1}, {0, -24, 0}, {0, 35, 0},     // one line further
        {14, -32, -1}, {14, 41, -1}, {-14, -32, 1}, {-14, 41, 1}, {0, -38, 0}, {0, 49, 0},     // two lines further
    };
    const Box plot_area{left + 1, top + 1, left + plot_w - 1, top + plot_h - 1};
    for (const auto& p : points) {
        if (!shown(p)) continue;
        const double x = sx(p.x), y = sy(p.y);
        double best_cost = 1e300;
        std::size_t best = 0;
        for (std::size_t k = 0; k < std::size(places); ++k) {
            const Box b = label_box(p.label, x + places[k].dx, y + places[k].dy, places[k].anchor);
            double cost = 0.0;
            for (const Box& t : taken) cost += b.overlap(t);
            const double area = (b.x1 - b.x0) * (b.y1 - b.y0);
            cost += area - b.overlap(plot_area);  // the part outside the plot
            if (cost < best_cost) best_cost = cost, best = k;
            if (cost == 0.0) break;
        }
        const Place& at = places[best];
        const double lx = x + at.dx, ly = y + at.dy;
        const Box b = label_box(p.label, lx, ly, at.anchor);
        taken.push_back(b);
        const char* colour = colours[series[p.series] % 6];
        if (best >= 6) {  // not adjacent: a thin line from the point to the label's nearest edge
            const double ex = std::clamp(x, b.x0, b.x1), ey = std::clamp(y, b.y0, b.y1);
            svg += "<line x1=\"" + coordinate(x) + "\" y1=\"" + coordinate(y) + "\" x2=\"" + coordinate(ex) + "\" y2=\"" + coordinate(ey) +
                   "\" stroke=\"" + colour + "\" stroke-width=\"0.7\"/>\n";
        }
        svg += "<text class=\"label\" x=\"" + coordinate(lx) + "\" y=\"" + coordinate(ly) + "\" text-anchor=\"" +
               (at.anchor < 0 ? "start" : at.anchor == 0 ? "middle" : "end") + "\" fill=\"" + colour + "\">" + escape(p.label) + "</text>\n";
    }
    // The legend, right of the plot.
    int row = 0;
    for (const auto& [name, index] : series) {
        const double y = top + 10 + 20 * row++;
        svg += "<circle cx=\"" + coordinate(width - right + 20) + "\" cy=\"" + coordinate(y) + "\" r=\"5\" fill=\"" + colours[index % 6] + "\"/>\n";
        svg += "<text x=\"" + coordinate(width - right + 30) + "\" y=\"" + coordinate(y + 4) + "\">" + escape(name) + "</text>\n";
    }
    svg += "</svg>\n";
    return svg;
}

}  // namespace texr
