// The benchmark plots: round tick values, and labels that can be read.
#include <doctest/doctest.h>

#include <cmath>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "texr/bench/plot.h"

using namespace texr;

namespace {
void check_ticks(const std::vector<double>& got, const std::vector<double>& expected) {
    REQUIRE(got.size() == expected.size());
    for (std::size_t i = 0; i < got.size(); ++i) CHECK(got[i] == doctest::Approx(expected[i]).epsilon(1e-12));
}
}  // namespace

TEST_CASE("plot ticks: 1, 2 and 5 times powers of ten, at most eight on a log axis") {
    // A log axis from 3.07 to 244 ms: 5, 10, 20, 50, 100, 200.
    check_ticks(axis_ticks(3.07, 244.0, true), {5, 10, 20, 50, 100, 200});
    // From 4e-14 to 4.5e6 (21 powers of ten): every third power, 7 ticks.
    check_ticks(axis_ticks(4.15e-14, 4.51e6, true), {1e-12, 1e-9, 1e-6, 1e-3, 1, 1e3, 1e6});
    // Three powers of ten: 1, 2 and 5 times each would be 10; 1 and 3 times, 7.
    check_ticks(axis_ticks(0.9, 1100.0, true), {1, 3, 10, 30, 100, 300, 1000});
    // Linear: (41 - 15) / 6 = 4.3 rounds up to a step of 5; (1 - 0) / 6 to 0.2.
    check_ticks(axis_ticks(15.0, 41.0, false), {15, 20, 25, 30, 35, 40});
    check_ticks(axis_ticks(0.0, 1.0, false), {0, 0.2, 0.4, 0.6, 0.8, 1.0});
    CHECK(axis_ticks(2.0, 1.0, false).empty());
    // No ticks where none can be told apart or counted (these looped for ever or overflowed
    // an int: found in review).
    CHECK(axis_ticks(0.0, 1.0, true).empty());
    CHECK(axis_ticks(1.0, INFINITY, true).empty());
    CHECK(axis_ticks(1e17, 1e17 + 32, false).empty());
}

TEST_CASE("plot tick texts are short: plain between 1e-3 and 1e5, powers of ten beyond") {
    CHECK(tick_text(0.0) == "0");
    CHECK(tick_text(0.2) == "0.2");
    CHECK(tick_text(0.6000000000000001) == "0.6");
    CHECK(tick_text(0.001) == "0.001");
    CHECK(tick_text(200.0) == "200");
    CHECK(tick_text(20000.0) == "20000");
    CHECK(tick_text(1e5) == "1e5");
    CHECK(tick_text(3e5) == "3e5");
    CHECK(tick_text(1e-12) == "1e-12");
    CHECK(tick_text(2e-5) == "2e-5");
    CHECK(tick_text(-2e6) == "-2e6");
    // An axis's ticks share one form: all in the exponent form where one of them needs it.
    CHECK(tick_texts({10000.0, 20000.0, 50000.0, 1e5, 2e5}) == std::vector<std::string>{"1e4", "2e4", "5e4", "1e5", "2e5"});
    CHECK(tick_texts({0.0, 0.0005, 0.001}) == std::vector<std::string>{"0", "5e-4", "1e-3"});
    CHECK(tick_texts({200.0, 500.0, 1000.0}) == std::vector<std::string>{"200", "500", "1000"});
}

TEST_CASE("plot labels overlap no other label or point and stay inside the plot") {
    // Two series of crowded points (the filters benchmark's layout: pairs a few pixels apart)
    // and a reference line among them.
    const char* names[] = {"nearest", "bilinear", "bicubic", "nearest_mip_nearest", "bilinear_mip_nearest", "trilinear", "anisotropic", "ewa"};
    const double ms[2][8] = {{0.52, 0.75, 5.1, 0.98, 1.25, 1.7, 13.0, 18.0}, {2.1, 2.8, 9.5, 1.02, 1.4, 2.05, 14.5, 19.0}};
    const double db[2][8] = {{14.6, 16.8, 15.9, 21.9, 23.4, 23.7, 28.3, 27.7}, {14.8, 17.0, 16.0, 21.9, 24.5, 25.0, 32.7, 32.6}};
    std::vector<PlotPoint> points;
    for (int s = 0; s < 2; ++s)
        for (int k = 0; k < 8; ++k) points.push_back({s == 0 ? "plane" : "grazing", names[k], ms[s][k], db[s][k]});
    PlotAxes axes;
    axes.title = "t", axes.x_label = "ms", axes.y_label = "dB";
    axes.marks = {{29.5, "trilinear's target on the plane, 29.5 dB"}};
    const std::string svg = scatter_svg(axes, points);

    // The plot area and the circles (the legend's circles lie right of the plot area).
    std::smatch m;
    REQUIRE(std::regex_search(svg, m, std::regex("<rect x=\"([-0-9.]+)\" y=\"([-0-9.]+)\" width=\"([-0-9.]+)\" height=\"([-0-9.]+)\" fill=\"none\"")));
    const double left = std::stod(m[1]), top = std::stod(m[2]), right = left + std::stod(m[3]), bottom = top + std::stod(m[4]);
    struct Box {
        double x0, y0, x1, y1;
    };
    std::vector<Box> circles, labels;
    const std::regex circle("<circle cx=\"([-0-9.]+)\" cy=\"([-0-9.]+)\" r=\"5\"");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), circle); it != std::sregex_iterator(); ++it) {
        const double x = std::stod((*it)[1]), y = std::stod((*it)[2]);
        if (x < right) circles.push_back({x - 5, y - 5, x + 5, y + 5});
    }
    CHECK(circles.size() == points.size());
    // Label boxes: 12-pixel text from 10 above the baseline to 3 below, plot_label_char_width
    // per character, placed by its anchor.
    const std::regex label("<text class=\"label\" x=\"([-0-9.]+)\" y=\"([-0-9.]+)\" text-anchor=\"(start|middle|end)\" fill=\"[^\"]+\">([^<]+)</text>");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), label); it != std::sregex_iterator(); ++it) {
        const double x = std::stod((*it)[1]), y = std::stod((*it)[2]), w = plot_label_char_width * double((*it)[4].length());
        const std::string anchor = (*it)[3];
        const double x0 = anchor == "start" ? x : anchor == "middle" ? x - w / 2 : x - w;
        labels.push_back({x0, y - 10, x0 + w, y + 3});
    }
    REQUIRE(labels.size() == points.size());
    const auto overlap = [](const Box& a, const Box& b) { return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1; };
    for (std::size_t i = 0; i < labels.size(); ++i) {
        CAPTURE(i);
        CHECK(labels[i].x0 >= left);
        CHECK(labels[i].x1 <= right);
        CHECK(labels[i].y0 >= top);
        CHECK(labels[i].y1 <= bottom);
        for (std::size_t j = 0; j < labels.size(); ++j) CHECK_FALSE((i != j && overlap(labels[i], labels[j])));
        for (const Box& c : circles) CHECK_FALSE(overlap(labels[i], c));
        // Near its own point: within 60 pixels.
        const Box& c = circles[i];
        const double cx = (c.x0 + c.x1) / 2, cy = (c.y0 + c.y1) / 2;
        const double dx = std::max({labels[i].x0 - cx, cx - labels[i].x1, 0.0}), dy = std::max({labels[i].y0 - cy, cy - labels[i].y1, 0.0});
        CHECK(std::hypot(dx, dy) <= 60.0);
    }
}

TEST_CASE("plots of a 0 on a log axis, or of values a few roundings apart, are drawn") {
    // A maximum error of 0 sits at 1e-300 on a log axis; the axis stops there (it ran past
    // where 10^x is a double, and the ticks looped for ever).
    PlotAxes axes;
    axes.title = "t", axes.x_label = "x", axes.y_label = "y", axes.log_y = true;
    axes.marks = {{INFINITY, "inf"}, {0.0, "zero"}, {1.0 / 64.0, "tolerance"}};
    std::string svg = scatter_svg(axes, {{"a", "zero", 1.0, 0.0}, {"a", "one", 2.0, 1.0}});
    CHECK(svg.find("</svg>") != std::string::npos);
    CHECK(svg.find(">tolerance<") != std::string::npos);
    CHECK(svg.find(">inf<") == std::string::npos);
    CHECK(svg.find("nan") == std::string::npos);
    axes.log_y = false;
    svg = scatter_svg(axes, {{"a", "p", 1.0, 1e17}, {"a", "q", 2.0, 1e17 + 16}});
    CHECK(svg.find("</svg>") != std::string::npos);
}

TEST_CASE("plot ticks at their edges: equal ends, steps of ten, ranges about one value, large values, tick texts that carry") {
    // lo must be below hi.
    CHECK(axis_ticks(1.0, 1.0, true).empty());
    CHECK(axis_ticks(1.0, 1.0, false).empty());
    // (3 - -0.5) / 6 = 0.583: no 1, 2 or 5 times 0.1 reaches it, so the step is 1, from the
    // first multiple at or above -0.5.
    check_ticks(axis_ticks(-0.5, 3.0, false), {0, 1, 2, 3});
    // (6 - 0) / 6 = 1 exactly: a step of 1, seven ticks.
    check_ticks(axis_ticks(0.0, 6.0, false), {0, 1, 2, 3, 4, 5, 6});
    // At 1e12 a step of 1: seven ticks, none past hi.
    check_ticks(axis_ticks(1e12, 1e12 + 6, false), {1e12, 1e12 + 1, 1e12 + 2, 1e12 + 3, 1e12 + 4, 1e12 + 5, 1e12 + 6});
    // A log axis whose lo is a rounding above 1e-5 still has its tick there.
    check_ticks(axis_ticks(1.0000000000000006e-5, 7e-5, true), {1e-5, 2e-5, 5e-5});
    // A log axis about one value (2, widened to 1.5 .. 4): 1 to 9 times, as 1, 2, 5 and 1, 3
    // give one tick each.
    check_ticks(axis_ticks(1.5, 4.0, true), {2, 3, 4});
    // A mantissa that rounds to 10 in 3 digits carries into the next power (9.996e7 read
    // "10e7").
    CHECK(tick_text(9.9996e7) == "1e8");
    CHECK(tick_text(9.996e7) == "1e8");
    CHECK(tick_text(9.994e7) == "9.99e7");
}

TEST_CASE("plot geometry: points at their values (larger y higher), NaN points left out, marks inside, lines in order of x") {
    PlotAxes axes;
    axes.title = "t", axes.x_label = "x", axes.y_label = "y", axes.log_x = false, axes.log_y = false, axes.connect = true;
    axes.marks = {{50.0, "target"}};
    // Out of order in x, one NaN: three points drawn, a mark above them all.
    const std::string svg = scatter_svg(axes, {{"a", "p3", 3.0, 30.0}, {"a", "p1", 1.0, 10.0}, {"a", "nan", 4.0, NAN}, {"a", "p2", 2.0, 20.0}});
    // The plot area is 100 .. 670 across and 50 .. 490 down; the legend's circles are right of it.
    const std::regex circle("<circle cx=\"([-0-9.]+)\" cy=\"([-0-9.]+)\"");
    std::vector<std::pair<double, double>> drawn;
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), circle); it != std::sregex_iterator(); ++it)
        if (std::stod((*it)[1]) < 670.0) drawn.emplace_back(std::stod((*it)[1]), std::stod((*it)[2]));
    REQUIRE(drawn.size() == 3);  // p3, p1, p2 in the order given
    CHECK(svg.find("nan") == std::string::npos);  // (the NaN point is left out, not drawn at "nan")
    const auto [x3, y3] = drawn[0];
    const auto [x1, y1] = drawn[1];
    const auto [x2, y2] = drawn[2];
    // x to the right and y upwards, linearly: equal steps of value are equal steps on screen.
    CHECK(x1 < x2);
    CHECK(x2 < x3);
    CHECK(y1 > y2);
    CHECK(y2 > y3);
    CHECK(x2 - x1 == doctest::Approx(x3 - x2).epsilon(0.01));
    CHECK(y1 - y2 == doctest::Approx(y2 - y3).epsilon(0.01));
    // The mark at 50, above every point, is inside the plot area and above them.
    const std::regex mark("<line x1=\"[-0-9.]+\" x2=\"[-0-9.]+\" y1=\"([-0-9.]+)\" y2=\"[-0-9.]+\" stroke=\"#555\" stroke-dasharray");
    std::smatch m;
    REQUIRE(std::regex_search(svg, m, mark));
    const double mark_y = std::stod(m[1]);
    CHECK(mark_y >= 50.0);
    CHECK(mark_y < y3);
    // 50 is as far above 30 as 30 above 10: the same screen distance.
    CHECK(y3 - mark_y == doctest::Approx(y1 - y3).epsilon(0.01));
    // The series' line goes through the points in order of x.
    const std::size_t path = svg.find("<path d=\"M");
    REQUIRE(path != std::string::npos);
    std::istringstream d(svg.substr(path + 10, svg.find('"', path + 10) - path - 10));
    std::vector<double> xs;
    double x = 0, y = 0;
    std::string step;
    d >> x >> y;
    xs.push_back(x);
    while (d >> step >> y) xs.push_back(std::stod(step.substr(1)));
    REQUIRE(xs.size() == 3);
    CHECK(xs[0] == doctest::Approx(x1).epsilon(0.001));
    CHECK(xs[1] == doctest::Approx(x2).epsilon(0.001));
    CHECK(xs[2] == doctest::Approx(x3).epsilon(0.001));
}

namespace {
struct Drawn {
    double x, y;
};
// The centres of the circles drawn for points (left of the legend, which starts at x = 680).
std::vector<Drawn> point_circles(const std::string& svg) {
    std::vector<Drawn> drawn;
    const std::regex circle("<circle cx=\"([-0-9.]+)\" cy=\"([-0-9.]+)\" r=\"5\"");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), circle); it != std::sregex_iterator(); ++it)
        if (std::stod((*it)[1]) < 680.0) drawn.push_back({std::stod((*it)[1]), std::stod((*it)[2])});
    return drawn;
}
// The y axis's tick texts (right-aligned at x = 94, left of the plot area).
std::vector<std::string> y_tick_texts(const std::string& svg) {
    std::vector<std::string> texts;
    const std::regex tick("<text x=\"94.0\" y=\"[-0-9.]+\" text-anchor=\"end\">([^<]+)</text>");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), tick); it != std::sregex_iterator(); ++it) texts.push_back((*it)[1]);
    return texts;
}
}  // namespace

TEST_CASE("plot margins: 5% of a linear x range each side, a quarter decade at least on a log axis, which stops at 1e-300") {
    // The plot area is 570 pixels wide (100 .. 670) and 440 high (50 .. 490).
    PlotAxes axes;
    axes.title = "t", axes.x_label = "x", axes.y_label = "y", axes.log_x = false, axes.log_y = true;
    std::string svg = scatter_svg(axes, {{"a", "p1", 1.0, 1.2}, {"a", "p2", 3.0, 1.9}, {"b", "q1", 2.0, 1.5}});
    std::vector<Drawn> drawn = point_circles(svg);
    REQUIRE(drawn.size() == 3);
    // x from 1 to 3, 0.1 of margin each side: 570 * 0.1 / 2.2 pixels from the plot's edges.
    CHECK(drawn[0].x - 100.0 == doctest::Approx(570.0 * 0.1 / 2.2).epsilon(0.005));
    CHECK(670.0 - drawn[1].x == doctest::Approx(570.0 * 0.1 / 2.2).epsilon(0.005));
    // log10 y from log10(1.2) to log10(1.9), less than a decade: a quarter decade each side.
    const double decades = 0.5 + std::log10(1.9 / 1.2);
    CHECK(490.0 - drawn[0].y == doctest::Approx(440.0 * 0.25 / decades).epsilon(0.005));
    CHECK(drawn[1].y - 50.0 == doctest::Approx(440.0 * 0.25 / decades).epsilon(0.005));
    // ... which takes in 1 and 2, ticked.
    CHECK(y_tick_texts(svg) == std::vector<std::string>{"1", "2"});

    // An error of 0 is drawn at the axis's floor, 1e-300 (the plot area's bottom edge), and the
    // axis has ticks up to the largest value; a mark at 0, which a log axis cannot show, is
    // not drawn.
    axes.log_x = true;
    axes.marks = {{1.0 / 64.0, "tolerance"}, {0.0, "zero mark"}};
    svg = scatter_svg(axes, {{"s", "exact", 1.0, 1e-12}, {"s", "affine", 0.9, 0.19}, {"t", "zero", 1.05, 0.0}});
    drawn = point_circles(svg);
    REQUIRE(drawn.size() == 3);
    CHECK(drawn[2].y == doctest::Approx(490.0));
    // From 1e-300 to 0.19, and 8% of that range above: 1e-12 lies 12 + log10(0.19) decades
    // below the largest value, and 0.08 (300 + log10(0.19)) more below the top.
    CHECK(drawn[0].y - 50.0 == doctest::Approx(440.0 * (std::log10(0.19) + 0.08 * (300.0 + std::log10(0.19)) + 12.0) /
                                               (1.08 * (300.0 + std::log10(0.19)))).epsilon(0.005));
    const std::vector<std::string> ticks = y_tick_texts(svg);
    CHECK(ticks.size() >= 2);
    CHECK(svg.find(">tolerance<") != std::string::npos);
    CHECK(svg.find("zero mark") == std::string::npos);
}

TEST_CASE("plot labels: one too wide for the plot goes to the nearest place of least overlap, and labels set apart get a leader line") {
    PlotAxes axes;
    axes.title = "t", axes.x_label = "x", axes.y_label = "y", axes.log_x = false;
    // 150 characters, wider than the plot: every place sticks out of it, least where the label
    // is centred on its point; of those places the nearest is just above it.
    std::string svg = scatter_svg(axes, {{"a", std::string(150, 'w'), 2.0, 5.0}, {"a", "b", 1.0, 4.0}, {"a", "c", 3.0, 6.0}});
    std::vector<Drawn> drawn = point_circles(svg);
    REQUIRE(drawn.size() == 3);
    std::smatch m;
    REQUIRE(std::regex_search(svg, m, std::regex("<text class=\"label\" x=\"([-0-9.]+)\" y=\"([-0-9.]+)\" text-anchor=\"([a-z]+)\"[^>]*>w{150}<")));
    CHECK(std::stod(m[1]) == doctest::Approx(drawn[0].x));
    CHECK(std::stod(m[2]) == doctest::Approx(drawn[0].y - 10.0));
    CHECK(m[3] == "middle");
    CHECK(svg.find("stroke-width=\"0.7\"") == std::string::npos);  // (no leader line)

    // A crowd of 14 labels about one place: those that could not be put beside their point
    // (a label's box more than 13 pixels from it; beside, at most 11) have a line from the
    // point to the box, and the others none.
    std::vector<PlotPoint> points;
    for (int i = 0; i < 14; ++i)
        points.push_back({"s" + std::to_string(i % 3), "label number " + std::to_string(i), 1.0 + 0.01 * i, 5.0 + 0.02 * (i % 5)});
    points.push_back({"far", "far", 3.0, 9.0});
    svg = scatter_svg(axes, points);
    drawn = point_circles(svg);
    REQUIRE(drawn.size() == points.size());
    std::vector<Drawn> line_starts;
    const std::regex line("<line x1=\"([-0-9.]+)\" y1=\"([-0-9.]+)\" x2=\"[-0-9.]+\" y2=\"[-0-9.]+\" stroke=\"[^\"]+\" stroke-width=\"0.7\"");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), line); it != std::sregex_iterator(); ++it)
        line_starts.push_back({std::stod((*it)[1]), std::stod((*it)[2])});
    const std::regex label("<text class=\"label\" x=\"([-0-9.]+)\" y=\"([-0-9.]+)\" text-anchor=\"(start|middle|end)\" fill=\"[^\"]+\">([^<]+)</text>");
    std::size_t i = 0, apart = 0;
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), label); it != std::sregex_iterator(); ++it, ++i) {
        REQUIRE(i < drawn.size());
        CAPTURE((*it)[4]);
        const double x = std::stod((*it)[1]), y = std::stod((*it)[2]), w = plot_label_char_width * double((*it)[4].length());
        const std::string anchor = (*it)[3];
        const double x0 = anchor == "start" ? x : anchor == "middle" ? x - w / 2 : x - w;
        const double dx = std::max({x0 - drawn[i].x, drawn[i].x - (x0 + w), 0.0});
        const double dy = std::max({(y - 10.0) - drawn[i].y, drawn[i].y - (y + 3.0), 0.0});
        const bool far = std::hypot(dx, dy) > 13.0;
        apart += far;
        bool has_line = false;
        for (const Drawn& s : line_starts) has_line = has_line || (s.x == doctest::Approx(drawn[i].x) && s.y == doctest::Approx(drawn[i].y));
        CHECK(has_line == far);
    }
    CHECK(i == points.size());
    CHECK(apart >= 3);  // (the crowd does push some away)
    CHECK(line_starts.size() == apart);
}
