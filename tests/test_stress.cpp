// Numerical stress: extreme w, far-away vertices, slivers, NaN/Inf, large and degenerate
// texture coordinates, a million random triangles, and closed meshes covered exactly once.
// Every expectation here is a property (finite, convex, counted, even) or a closed form.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>

#include "helpers.h"
#include "texr/render/renderer.h"
#include "texr/scene/parser.h"

using namespace texr;

namespace {

Vertex vertex(double x, double y, double z, double u = 0, double v = 0, Color color = Color(1.0f)) {
    Vertex out;
    out.position = glm::vec3(float(x), float(y), float(z));
    out.uv = {u, v};
    out.color = color;
    return out;
}

std::shared_ptr<MipMap> noise_texture(int width, int height, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<std::uint8_t> rgba(std::size_t(width) * std::size_t(height) * 4);
    for (auto& b : rgba) b = std::uint8_t(rng() % 256);
    return std::make_shared<MipMap>(std::make_shared<Image>(Image::ldr(width, height, ColorSpace::srgb, rgba)));
}

void add_texture(Scene& scene, Filter filter, Wrap wrap = Wrap::repeat) {
    Texture t;
    t.name = "noise";
    // Not square, so that a path that confused the width with the height would draw another
    // frame than the pixel-by-pixel walk does.
    t.mipmap = noise_texture(128, 32, 3);
    t.image = std::shared_ptr<const Image>(t.mipmap, &t.mipmap->base());
    t.sampler.filter = filter;
    t.sampler.wrap_u = t.sampler.wrap_v = wrap;
    scene.textures.push_back(t);
    Material m;
    m.texture = int(scene.textures.size()) - 1;
    m.color = Color(0.9f, 0.35f, 0.6f);  // (not white: shading must multiply by it on every path)
    scene.materials.push_back(m);
}

struct FrameCheck {
    bool finite = true, depth_in_range = true, colour_in_unit_range = true;
    int drawn = 0;
};

FrameCheck check_frame(const Framebuffer& fb) {
    FrameCheck c;
    for (std::size_t i = 0; i < fb.color.size(); ++i) {
        const Color& col = fb.color[i];
        for (int k = 0; k < 3; ++k) {
            c.finite = c.finite && std::isfinite(col[k]);
            c.colour_in_unit_range = c.colour_in_unit_range && col[k] >= -1e-4f && col[k] <= 1.0f + 1e-4f;
        }
        c.depth_in_range = c.depth_in_range && (!fb.drawn(i) || (fb.depth[i] >= 0.0f && fb.depth[i] <= 1.0f));
        c.drawn += fb.drawn(i);
    }
    return c;
}

}  // namespace

TEST_CASE("stress: triangles crossing the camera plane with w from 1e-9 to 1e9") {
    for (int e = -9; e <= 9; ++e) {
        CAPTURE(e);
        const double w = std::pow(10.0, e);
        Scene scene = testing::camera_scene(64, 48, {0, 0, 0}, {0, 0, -1}, 90.0, 1e-10, 1e10);
        Material m;
        m.vertex_colors = true;
        scene.materials.push_back(m);
        // One vertex at depth w, one behind the camera, one at depth 2; colours in [0, 1].
        testing::add_triangle(scene, {vertex(0.3 * w, -0.2 * w, -w, 0, 0, {1, 0, 0}), vertex(-1, -1, 1, 0, 0, {0, 1, 0}),
                                      vertex(2, 1.5, -2, 0, 0, {0, 0, 1})}, 0);
        testing::add_triangle(scene, {vertex(-w, -w, -w, 0, 0, {1, 1, 0}), vertex(w, -w, -w, 0, 0, {0, 1, 1}),
                                      vertex(0, 0.5, -0.5, 0, 0, {1, 0, 1})}, 0);
        RenderStats stats;
        const Framebuffer fb = render(scene, {}, stats);
        const FrameCheck c = check_frame(fb);
        CHECK(c.finite);
        CHECK(c.depth_in_range);
        CHECK(c.colour_in_unit_range);  // perspective-correct colours are convex combinations
        CHECK(c.drawn > 0);
    }
}

TEST_CASE("stress: vertices 1e7 pixels outside the screen still cover every pixel exactly once") {
    // A square at depth 1 facing the camera (90 degree view, 64 px): x_ndc = X, so X = 3e5
    // is 9.6e6 pixels right of the screen. Red grows linearly with X across the square.
    Scene scene = testing::camera_scene(64, 64, {0, 0, 0}, {0, 0, -1}, 90.0, 0.1, 100.0);
    Material m;
    m.vertex_colors = true;
    scene.materials.push_back(m);
    const double r = 3e5;
    const Vertex a = vertex(-r, -r, -1, 0, 0, {0, 0, 0}), b = vertex(r, -r, -1, 0, 0, {1, 0, 0});
    const Vertex c = vertex(r, r, -1, 0, 0, {1, 0, 0}), d = vertex(-r, r, -1, 0, 0, {0, 0, 0});
    testing::add_triangle(scene, {a, b, c}, 0);
    testing::add_triangle(scene, {a, c, d}, 0);
    RenderOptions options;
    options.count_coverage = true;
    RenderStats stats;
    const Framebuffer fb = render(scene, options, stats);
    double worst = 0.0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            REQUIRE(fb.coverage[fb.index(x, y)] == 1);
            const double world_x = (x + 0.5) / 32.0 - 1.0;
            const double expected = (world_x + r) / (2 * r);  // about 0.5, varying by 1e-6
            worst = std::max(worst, std::fabs(fb.color[fb.index(x, y)].x - expected));
        }
    CHECK(worst < 1e-5);
    CHECK(stats.triangles_clipped == 2);
}

TEST_CASE("stress: slivers below 1e-6 px^2 and zero-area triangles draw nothing wrong") {
    Scene scene = testing::camera_scene(64, 64, {0, 0, 0}, {0, 0, -1}, 90.0, 0.1, 100.0);
    scene.materials.push_back(Material{});
    // Slivers near the origin, where float coordinates are fine enough: a base of about 10
    // pixels (0.3 units at 32 px per unit) and heights of 1e-9 .. 1e-8 units, i.e. areas of
    // 5e-7 .. 5e-6 px^2 before snapping, at several angles.
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), height(1e-9, 1e-8);
    int slivers = 0;
    for (int k = 0; k < 200; ++k, ++slivers) {
        const double a = angle(rng), h = height(rng);
        const double cx = 0.15 * std::cos(a), cy = 0.15 * std::sin(a), nx = -std::sin(a) * h, ny = std::cos(a) * h;
        testing::add_triangle(scene, {vertex(-cx, -cy, -1), vertex(cx, cy, -1), vertex(nx, ny, -1)}, 0);
    }
    testing::add_triangle(scene, {vertex(-0.5, -0.3, -1), vertex(0.5, -0.3, -1), vertex(0.6, -0.3, -1)}, 0);  // collinear
    testing::add_triangle(scene, {vertex(0.2, 0.2, -1), vertex(0.2, 0.2, -1), vertex(0.2, 0.2, -1)}, 0);     // a point
    RenderOptions options;
    options.count_coverage = true;
    RenderStats stats;
    const Framebuffer fb = render(scene, options, stats);
    // Snapped to 1/256 pixel, each sliver either collapses (dropped) or becomes at most a
    // 1/256-pixel-high triangle, which covers a pixel centre only if one lies on its edge.
    CHECK(stats.triangles_in == std::uint64_t(slivers + 2));
    CHECK(stats.triangles_dropped >= 2);
    CHECK(stats.triangles_dropped + stats.triangles_set_up + stats.triangles_culled == stats.triangles_in);
    int covered = 0;
    for (auto n : fb.coverage) covered += n;
    CHECK(covered <= 10 * int(stats.triangles_set_up));  // a few centres on an edge at most, never a blob
    CHECK(check_frame(fb).finite);
}

TEST_CASE("a triangle whose bounding box holds no pixel centre is culled before setup") {
    // 64x64 pixels, 90 degree field of view, triangles at z = -1: pixel (px, py) is the point
    // (px / 32 - 1, 1 - py / 32). Pixel centres are at k + 1/2.
    const auto at = [](double px, double py) { return vertex(px / 32 - 1, 1 - py / 32, -1); };
    for (const bool holds_centre : {false, true}) {
        Scene scene = testing::camera_scene(64, 64, {0, 0, 0}, {0, 0, -1}, 90.0, 0.1, 100.0);
        scene.materials.push_back(Material{});
        // Its box [10.6, 11.4] x [10.1, 11.9] holds the centres of rows 10 and 11 but of no
        // column. Moved right by half a pixel, its box [11.1, 11.9] x [10.1, 11.9] holds
        // those of column 11, rows 10 and 11: at y = 10.5 the triangle spans x from 11.19 to
        // 11.81, at y = 11.5 from 11.41 to 11.59, so it covers both.
        const double o = holds_centre ? 0.5 : 0.0;
        testing::add_triangle(scene, {at(10.6 + o, 10.1), at(11.0 + o, 11.9), at(11.4 + o, 10.1)}, 0);
        RenderStats stats;
        const Framebuffer fb = render(scene, {}, stats);
        CHECK(stats.triangles_culled == (holds_centre ? 0u : 1u));
        CHECK(stats.triangles_set_up == (holds_centre ? 1u : 0u));
        CHECK(stats.pixels_shaded == (holds_centre ? 2u : 0u));
        if (holds_centre) CHECK((fb.drawn(fb.index(11, 10)) && fb.drawn(fb.index(11, 11))));
    }
}

TEST_CASE("stress: NaN and Inf vertices are dropped and counted, never drawn") {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    Scene scene = testing::camera_scene(32, 32, {0, 0, 0}, {0, 0, -1}, 90.0, 0.1, 100.0);
    scene.materials.push_back(Material{});
    testing::add_triangle(scene, {vertex(nan, 0, -1), vertex(1, 0, -1), vertex(0, 1, -1)}, 0);
    testing::add_triangle(scene, {vertex(-1, -1, -1), vertex(inf, 0, -1), vertex(0, 1, -1)}, 0);
    testing::add_triangle(scene, {vertex(-1, -1, -1), vertex(1, -1, -1), vertex(0, -1, -inf)}, 0);
    RenderStats stats;
    const Framebuffer fb = render(scene, {}, stats);
    CHECK(stats.triangles_dropped == 3);
    CHECK(check_frame(fb).drawn == 0);
    CHECK(check_frame(fb).finite);
}

TEST_CASE("stress: UVs offset by 1e5 render the same as offset 0 (re-based per triangle)") {
    // Stated tolerance: 1e-6 in linear colour. Re-basing by whole periods makes the setup
    // identical, so in practice the frames match exactly.
    for (Wrap wrap : {Wrap::repeat, Wrap::mirror}) {
        Framebuffer frames[2] = {Framebuffer(1, 1, Color(0.0f)), Framebuffer(1, 1, Color(0.0f))};
        for (int k = 0; k < 2; ++k) {
            const double offset = k == 0 ? 0.0 : 1e5;
            Scene scene = testing::camera_scene(96, 64, {0, 1, 2}, {0, 0, -3}, 60.0, 0.1, 100.0);
            add_texture(scene, Filter::trilinear, wrap);
            testing::add_triangle(scene, {vertex(-3, 0, 0, offset, offset), vertex(3, 0, 0, offset + 6, offset),
                                          vertex(3, 0, -20, offset + 6, offset + 40)}, 0);
            RenderStats stats;
            frames[k] = render(scene, {}, stats);
        }
        float worst = 0.0f;
        for (std::size_t i = 0; i < frames[0].color.size(); ++i)
            worst = std::max(worst, glm::length(frames[0].color[i] - frames[1].color[i]));
        CHECK(worst <= 1e-6f);
        CHECK(check_frame(frames[0]).drawn > 1000);
    }
}

TEST_CASE("stress: UVs offset by 1e5 and 1e6 in an OBJ file render the same as offset 0") {
    // The same tolerance as above. A float keeps 100000.1 only to 1/128 (100000.1015625), so
    // an OBJ's UVs must be read as doubles, as a scene file's are, for the texture not to
    // shift by up to a fifth of a texel here (the frames differed by up to 206 levels of 255
    // in a review's trial, 2026-11-30).
    const std::string dir = testing::scratch_folder("obj-uv-offset");
    for (const Filter filter : {Filter::bilinear, Filter::trilinear}) {
        Framebuffer frames[3] = {Framebuffer(1, 1, Color(0.0f)), Framebuffer(1, 1, Color(0.0f)), Framebuffer(1, 1, Color(0.0f))};
        for (int k = 0; k < 3; ++k) {
            const double offset = k == 0 ? 0.0 : k == 1 ? 1e5 : 1e6;
            const auto vt = [&](double u, double v) {  // ("vt 100000.1 100000.2")
                char line[64];
                std::snprintf(line, sizeof line, "vt %.1f %.1f\n", offset + u, offset + v);
                return std::string(line);
            };
            testing::write_text(dir + "/quad.obj", "v -50 0 10\nv 50 0 10\nv 50 0 -90\nv -50 0 -90\n" + vt(0.1, 0.2) + vt(25.1, 0.2) +
                                                       vt(25.1, 25.2) + vt(0.1, 25.2) + "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
            testing::write_text(dir + "/scene.txt", "size 128 128\ncamera eye 0 1 0 target 0 0.75 -4 fov 60 near 0.05 far 1000\n"
                                                    "texture t file " + testing::source_path("models/textures/uvgrid.png") +
                                                    " filter " + filter_name(filter) + "\nmaterial m texture t\nmesh quad.obj material m\n");
            RenderStats stats;
            frames[k] = render(load_scene(dir + "/scene.txt"), {}, stats);
        }
        for (int k = 1; k < 3; ++k) {
            float worst = 0.0f;
            for (std::size_t i = 0; i < frames[0].color.size(); ++i)
                worst = std::max(worst, glm::length(frames[0].color[i] - frames[k].color[i]));
            CAPTURE(k);
            CHECK(worst <= 1e-6f);
        }
        CHECK(check_frame(frames[0]).drawn > 4000);
    }
}

TEST_CASE("stress: down to the smallest field of view, 1e-6 degrees, a floor the eye looks at fills the frame") {
    // The eye looks at a point of a floor 1000 wide, from 4 away, 3.6 degrees below the
    // horizon: at a field of view of a degree or less the floor covers every pixel (it did not
    // at 1e-17 degrees, where a review's floor vanished).
    for (const std::string fov : {"1", "1e-3", "1e-6"}) {
        CAPTURE(fov);
        std::istringstream in(std::string("size 64 64\ncamera eye 0.01 1 0 target 0.013 0.75 -4 up 0 1 0 fov ") + fov +
                              " near 0.05 far 1000\nmaterial m color 1 0 0\n"
                              "quad material m v -500 0 10 0 0 v 500 0 10 1 0 v 500 0 -990 1 1 v -500 0 -990 0 1\n");
        const Scene scene = parse_scene(in, "fov.scene");
        RenderStats stats;
        const Framebuffer fb = render(scene, {}, stats);
        CHECK(stats.pixels_shaded == 64u * 64u);
        CHECK(check_frame(fb).finite);
    }
}

TEST_CASE("stress: degenerate UVs and huge UV gradients stay finite and bounded") {
    for (Filter filter : {Filter::nearest, Filter::bilinear, Filter::bicubic, Filter::trilinear, Filter::anisotropic, Filter::ewa}) {
        CAPTURE(filter_name(filter));
        Scene scene = testing::camera_scene(48, 32, {0, 0, 0}, {0, 0, -1}, 90.0, 0.1, 100.0);
        add_texture(scene, filter);
        // Collinear, coincident, and a 1e6-texel span over a few pixels.
        testing::add_triangle(scene, {vertex(-1, -1, -2, 0, 0), vertex(0, -1, -2, 1, 1), vertex(-1, 0, -2, 3, 3)}, 0);
        testing::add_triangle(scene, {vertex(0, 0, -2, 0.3, 0.7), vertex(1, 0, -2, 0.3, 0.7), vertex(0, 1, -2, 0.3, 0.7)}, 0);
        testing::add_triangle(scene, {vertex(-1, 0, -3, 0, 0), vertex(-0.5, 0, -3, 1e6, 0), vertex(-1, 0.5, -30, 0, 1e6)}, 0);
        RenderStats stats;
        const Framebuffer fb = render(scene, {}, stats);
        const FrameCheck c = check_frame(fb);
        CHECK(c.finite);
        if (filter != Filter::bicubic) CHECK(c.colour_in_unit_range);  // Catmull-Rom may overshoot
        CHECK(c.drawn > 40);
        // Anisotropy is clamped at 16: at most 16 trilinear probes (8 texels each), and the
        // EWA ellipse at most 16 x 1 texels plus its rim, on two levels.
        CHECK(double(stats.texels_fetched) / double(stats.pixels_shaded) <= 16 * 8);
    }
}

TEST_CASE("stress: u from -1.7e308 to 1.7e308 across a quad: the span modes read what the exact mode reads") {
    // Between a sub-span's two ends u differs by more than the largest double, so a line
    // between them would be inf or NaN (u[b] - u[a] overflows), and the adaptive mode's
    // curvature bound 2 |dq/dx| |K| can be 0 x inf = NaN. Both quads keep each row at one
    // depth (one faces the camera; the other, with v from -1.7e308 to 1.7e308 too, leans back
    // 70 degrees about x), so u is linear along every row and every mode, exact up to
    // rounding, must draw the exact mode's frame. With clamp, u far below 0 reads the first
    // column and far above 1 the last.
    const double big = 1.7e308;
    for (const bool leaning : {false, true}) {
        CAPTURE(leaning);
        Scene scene = testing::camera_scene(256, 192, {0, 0, 3}, {0, 0, 0}, 45.0, 0.01, 100.0);
        add_texture(scene, Filter::nearest, Wrap::clamp);
        const double v_low = leaning ? -big : 0.0, v_high = leaning ? big : 1.0;
        const double lean = 70.0 * 3.14159265358979 / 180.0;
        const auto at = [&](double x, double y, double u, double v) {  // (x, y, 0), turned about x
            return leaning ? vertex(x, y * std::cos(lean), -y * std::sin(lean), u, v) : vertex(x, y, 0.0, u, v);
        };
        testing::add_triangle(scene, {at(-1, -1, -big, v_low), at(1, -1, big, v_low), at(1, 1, big, v_high)}, 0);
        testing::add_triangle(scene, {at(-1, -1, -big, v_low), at(1, 1, big, v_high), at(-1, 1, -big, v_high)}, 0);
        RenderOptions options;
        options.span_mode = SpanMode::exact;
        RenderStats stats;
        const Framebuffer exact = render(scene, options, stats);
        const FrameCheck c = check_frame(exact);
        CHECK(c.finite);
        CHECK(c.drawn > 3000);
        for (const SpanMode mode : {SpanMode::incremental, SpanMode::affine8, SpanMode::affine16, SpanMode::affine32, SpanMode::adaptive}) {
            CAPTURE(std::string(span_mode_name(mode)));
            options.span_mode = mode;
            const Framebuffer fb = render(scene, options, stats);
            int differ = 0;
            for (std::size_t i = 0; i < fb.color.size(); ++i) differ += fb.color[i] != exact.color[i];
            CHECK(differ == 0);
        }
    }
}

TEST_CASE("stress: a million random triangles leave no NaN, nothing outside [0, 1] depth") {
    std::uint64_t triangles = 0;
    for (std::uint64_t seed = 0; seed < 50; ++seed) {
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<double> unit(-1.0, 1.0);
        Scene scene = testing::camera_scene(40, 30, {0, 0, 0}, {0, 0, -1}, 70.0, 0.01, 1000.0);
        add_texture(scene, seed % 2 ? Filter::trilinear : Filter::bilinear);
        Mesh mesh;
        mesh.has_uv = true;
        for (int t = 0; t < 20000; ++t) {
            // Scales from 1e-4 to 1e4 and positions around and behind the camera.
            const double scale = std::pow(10.0, 4.0 * unit(rng));
            const glm::dvec3 centre(3 * unit(rng), 3 * unit(rng), -4 * (unit(rng) + 0.9));
            for (int k = 0; k < 3; ++k) {
                const glm::dvec3 p = centre + scale * glm::dvec3(unit(rng), unit(rng), unit(rng));
                mesh.vertices.push_back(vertex(p.x, p.y, p.z, 100 * unit(rng), 100 * unit(rng)));
            }
            const auto base = std::uint32_t(mesh.vertices.size() - 3);
            mesh.triangles.push_back({base, base + 1, base + 2});
            mesh.triangle_material.push_back(0);
        }
        scene.meshes.push_back(mesh);
        scene.objects.push_back(Object{0, glm::dmat4(1.0), false});
        RenderStats stats;
        RenderOptions options;
        options.threads = 2;
        const Framebuffer fb = render(scene, options, stats);
        const FrameCheck c = check_frame(fb);
        REQUIRE(c.finite);
        REQUIRE(c.depth_in_range);
        REQUIRE(c.colour_in_unit_range);
        REQUIRE(stats.triangles_in == 20000);
        triangles += stats.triangles_in;
    }
    CHECK(triangles == 1000000);
}

namespace {

// A closed, convex ellipsoid: rings of quads and a fan at each pole, outward winding.
Mesh ellipsoid(int rings, int segments) {
    Mesh m;
    m.vertices.push_back(vertex(0, 1, 0));   // north pole
    m.vertices.push_back(vertex(0, -1, 0));  // south pole
    for (int r = 1; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segments;
            m.vertices.push_back(vertex(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi)));
        }
    auto at = [&](int r, int s) { return std::uint32_t(2 + (r - 1) * segments + (s % segments)); };
    for (int s = 0; s < segments; ++s) {
        m.triangles.push_back({0, at(1, s), at(1, s + 1)});
        m.triangles.push_back({1, at(rings - 1, s + 1), at(rings - 1, s)});
        for (int r = 1; r + 1 < rings; ++r) {
            m.triangles.push_back({at(r, s), at(r + 1, s), at(r + 1, s + 1)});
            m.triangles.push_back({at(r, s), at(r + 1, s + 1), at(r, s + 1)});
        }
    }
    m.triangle_material.assign(m.triangles.size(), 0);
    return m;
}

}  // namespace

TEST_CASE("stress: a closed mesh covers every covered pixel exactly once (front faces) and twice (all faces)") {
    std::mt19937_64 rng(77);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int trial = 0; trial < 40; ++trial) {
        Scene scene = testing::camera_scene(80, 60, {0, 0, 0}, {0, 0, -1}, 60.0, 0.1, 100.0);
        scene.materials.push_back(Material{});
        scene.meshes.push_back(ellipsoid(7 + trial % 13, 5 + trial % 17));
        Object o;
        o.mesh = 0;
        o.transform = glm::translate(glm::dmat4(1.0), glm::dvec3(unit(rng), unit(rng), -4.0 + unit(rng))) *
                      glm::rotate(glm::dmat4(1.0), 3.0 * unit(rng), glm::normalize(glm::dvec3(unit(rng), unit(rng), 1.0))) *
                      glm::scale(glm::dmat4(1.0), glm::dvec3(1.0 + 0.5 * unit(rng), 1.0 + 0.5 * unit(rng), 1.0 + 0.5 * unit(rng)));
        RenderOptions options;
        options.count_coverage = true;
        RenderStats stats;
        o.cull_back = false;
        scene.objects = {o};
        const Framebuffer all = render(scene, options, stats);
        o.cull_back = true;
        scene.objects = {o};
        const Framebuffer front = render(scene, options, stats);
        int covered = 0;
        for (std::size_t i = 0; i < all.coverage.size(); ++i) {
            REQUIRE(front.coverage[i] <= 1);
            REQUIRE(all.coverage[i] == 2 * front.coverage[i]);
            covered += front.coverage[i];
        }
        CHECK(covered > 100);
    }
}

// The filters that have short paths, and span modes of every kind (stepped, precomputed
// exactly, interpolated, adaptive, affine) for comparing them with the general path.
constexpr Filter short_path_filters[] = {Filter::nearest, Filter::bilinear, Filter::nearest_mip_nearest,
                                         Filter::bilinear_mip_nearest, Filter::trilinear};
constexpr SpanMode compared_span_modes[] = {SpanMode::incremental, SpanMode::exact, SpanMode::adaptive, SpanMode::affine16,
                                            SpanMode::affine};

// Renders the scene as given (short texture paths where they apply) and with (u, v)
// captured, which forces the general path on every pixel; checks that the two agree.
struct FrameAndStats {
    Framebuffer fb;
    RenderStats stats;
};
FrameAndStats check_short_paths_equal_general(const Scene& scene, RenderOptions options) {
    RenderStats stats, general_stats;
    Framebuffer fb = render(scene, options, stats);
    options.capture_uv = true;
    const Framebuffer general = render(scene, options, general_stats);
    CHECK(fb.color == general.color);
    CHECK(fb.depth == general.depth);
    CHECK(stats.texels_fetched == general_stats.texels_fetched);
    CHECK(stats.pixels_shaded == general_stats.pixels_shaded);
    return {std::move(fb), stats};
}

TEST_CASE("stress: the short texture paths read what the general path reads, up to and beyond 1e15 texels") {
    // A 64x64 power-of-two texture with repeat takes the short paths, which check a span's
    // coordinates once (not each pixel) and hand a span beyond 1e15 texels to the general
    // path. Capturing (u, v) forces the general path everywhere: the frames must be equal.
    for (Filter filter : short_path_filters) {
        for (SpanMode mode : compared_span_modes) {
            CAPTURE(filter_name(filter));
            CAPTURE(int(mode));
            Scene scene = testing::camera_scene(96, 64, {0, 1, 2}, {0, 0, -3}, 60.0, 0.1, 100.0);
            add_texture(scene, filter);
            // UVs across 1e14 periods (6.4e15 texels) on one triangle, 10 on the other.
            testing::add_triangle(scene, {vertex(-3, 0, 0, 0, 0), vertex(0, 0, 0, 1e14, 0), vertex(0, 0, -20, 1e14, 3e13)}, 0);
            testing::add_triangle(scene, {vertex(0, 0, 0, 0, 0), vertex(3, 0, 0, 10, 0), vertex(3, 0, -20, 10, 10)}, 0);
            RenderOptions options;
            options.span_mode = mode;
            const Framebuffer fb = check_short_paths_equal_general(scene, options).fb;
            CHECK(check_frame(fb).drawn > 1000);
        }
    }
}

TEST_CASE("stress: the short paths and the general path agree on spans just short of and just past 1e15 texels") {
    // The short paths take a span only when every (u, v) is below the limit, 1e15 texels
    // (1.5625e13 periods of this 64-texel texture); past it the general path reads no
    // fraction. A square 60 units wide seen from 5 units above: one coordinate goes from 0
    // to 4 along each row, the other from 0 to 1.15 times the limit down the square (UVs are
    // re-based per triangle, so only their range counts). The camera looks at where the
    // limit is reached, so that about nine rows lie in each per cent above the limit: a
    // limit checked a per cent too high (or a bound on the coordinates a per cent too low)
    // sends those rows the wrong way. In every span mode, the large coordinate on u, then v.
    constexpr double limit_periods = 1e15 / 64.0;
    const double far_end = 1.15 * limit_periods;
    const double z_limit = 30.0 - 60.0 / 1.15;  // where the large coordinate reaches the limit
    for (Filter filter : short_path_filters) {
        for (SpanMode mode : compared_span_modes) {
            for (bool large_u : {true, false}) {
                CAPTURE(filter_name(filter));
                CAPTURE(int(mode));
                CAPTURE(large_u);
                Scene scene = testing::camera_scene(96, 96, {0, 5, z_limit}, {0, 0, z_limit - 0.001}, 60.0, 0.1, 100.0);
                add_texture(scene, filter);
                const auto corner = [&](double x, double z) {
                    const double small = (x + 30.0) * (4.0 / 60.0), large = z > 0 ? 0.0 : far_end;
                    return large_u ? vertex(x, 0, z, large, small) : vertex(x, 0, z, small, large);
                };
                testing::add_triangle(scene, {corner(-30, 30), corner(30, 30), corner(30, -30)}, 0);
                testing::add_triangle(scene, {corner(-30, 30), corner(30, -30), corner(-30, -30)}, 0);
                RenderOptions options;
                options.span_mode = mode;
                const Framebuffer fb = check_short_paths_equal_general(scene, options).fb;
                CHECK(check_frame(fb).drawn == 96 * 96);
            }
        }
    }
}

TEST_CASE("the batched span walk of the short paths gives the pixel-by-pixel walk's frame") {
    // The short paths (but nearest) walk a span in batches of pixels: depth tests first, then
    // coordinates and levels, then lookups. Spans here are longer than a batch, pixels in the
    // middle of batches fail the depth test behind an occluder drawn first, and one material
    // is lit (normals interpolated per pixel). Capturing (u, v) forces the general path, which
    // walks pixel by pixel: the frames must be equal.
    for (Filter filter : short_path_filters) {
        for (SpanMode mode : compared_span_modes) {
            CAPTURE(filter_name(filter));
            CAPTURE(int(mode));
            Scene scene = testing::camera_scene(331, 97, {0, 1, 2}, {0, 0.5, -3}, 60.0, 0.1, 100.0);
            add_texture(scene, filter);
            Material lit = scene.materials[0];
            lit.lighting = Lighting::lambert;
            scene.materials.push_back(lit);
            scene.ambient = Color(0.1f);
            scene.lights.push_back(Light{Light::Kind::directional, glm::dvec3(0.3, -1.0, -0.5), Color(0.9f)});
            auto lit_vertex = [](double x, double y, double z, double u, double v, glm::vec3 normal) {
                Vertex out = vertex(x, y, z, u, v);
                out.normal = normal;
                return out;
            };
            // The occluder, near the camera, first; then a receding floor (unlit) and a lit
            // wall behind, both wider than the frame.
            testing::add_triangle(scene, {lit_vertex(-0.2, 0.4, 0.5, 0, 0, {0, 1, 0}), lit_vertex(0.3, 0.4, 0.5, 2, 0, {1, 0, 0}),
                                          lit_vertex(0.0, 1.2, 0.5, 1, 2, {0, 0, 1})},
                                  1);
            for (int m = 0; m < 2; ++m) {
                const double z = m == 0 ? 0.0 : -6.0;
                auto corner = [&](double x, double depth, double u, double v) {
                    return m == 0 ? lit_vertex(x, 0, depth, u, v, {0, 1, 0}) : lit_vertex(x, -depth, z, u, v, {0.5f * float(x), 1, 1});
                };
                testing::add_triangle(scene, {corner(-30, 1, 0, 0), corner(30, 1, 40, 0), corner(30, -30, 40, 40)}, m);
                testing::add_triangle(scene, {corner(-30, 1, 0, 0), corner(30, -30, 40, 40), corner(-30, -30, 0, 40)}, m);
                scene.meshes[scene.meshes.size() - 1].has_normals = scene.meshes[scene.meshes.size() - 2].has_normals = true;
            }
            scene.meshes[0].has_normals = true;
            RenderOptions options;
            options.span_mode = mode;
            options.count_coverage = true;
            const auto [fb, stats] = check_short_paths_equal_general(scene, options);
            // Pixels failed the depth test (covered more often than shaded), and most are drawn.
            std::uint64_t covered = 0;
            for (std::uint16_t c : fb.coverage) covered += c;
            CHECK(covered > stats.pixels_shaded + 1000);
            CHECK(check_frame(fb).drawn > 331 * 97 * 3 / 4);
        }
    }
}
