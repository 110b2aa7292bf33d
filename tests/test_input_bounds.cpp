// Every bound docs/scene-format.md and the help text give, tried on both sides: the value at
// the bound is read, the one just past it refused with its line. (A mutation-testing round
// found these checks untested: turning `<` into `<=`, or dropping a check, passed the suite.)
#include <doctest/doctest.h>

#include <sstream>
#include <string>
#include <vector>

#include "helpers.h"
#include "texr/core/color.h"
#include "texr/io/frame_writer.h"
#include "texr/render/renderer.h"
#include "texr/scene/obj_mesh.h"
#include "texr/scene/parser.h"

using namespace texr;
using namespace texr::testing;

namespace {

const std::string triangle = "triangle v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1\n";

// The message parse_scene gives for `text` (read as the file `path`), or "" if it reads it.
std::string refusal(const std::string& text, const std::string& path = "b.scene") {
    std::istringstream in(text);
    try {
        parse_scene(in, path);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

Scene parsed(const std::string& text, const std::string& path = "b.scene") {
    std::istringstream in(text);
    return parse_scene(in, path);
}

// Whether `message` starts with "file:line: " and holds `words`.
bool refused_at(const std::string& message, const std::string& at, const std::string& words) {
    return message.rfind(at, 0) == 0 && message.find(words) != std::string::npos;
}

std::string checker() { return source_path("models/textures/checker.png"); }
std::string texture_line() { return "texture t file " + checker(); }

}  // namespace

TEST_CASE("scene bounds: frame size, colours, camera, texture options and transforms, at and past each bound") {
    // size: whole numbers from 1 to 16384 a side, at most 64 Mpixel, and nothing after them.
    for (const char* good : {"size 1 1", "size 16384 1", "size 1 16384", "size 8192 8192", "size 16384 4096"}) {
        CAPTURE(good);
        CHECK(refusal(std::string(good) + "\n" + triangle) == "");
    }
    const Scene largest = parsed("size 16384 4096\n" + triangle);
    CHECK(largest.width == 16384);
    CHECK(largest.height == 4096);
    for (const char* bad : {"size 0 4", "size 4 0", "size 16385 1", "size 1 16385", "size 8193 8192", "size 4.5 4", "size 4 4.5"}) {
        CAPTURE(bad);
        CHECK(refused_at(refusal(std::string(bad) + "\n" + triangle), "b.scene:1: ", "image size must be whole numbers from 1 to 16384"));
    }
    CHECK(refused_at(refusal("size 4 4 4\n" + triangle), "b.scene:1: ", "unexpected '4' at the end of 'size'"));
    // Colours from 0 to 10000, each channel.
    for (const char* bad : {"background -1 0 0", "background 0 -1 0", "background 0 0 -1"}) {
        CAPTURE(bad);
        CHECK(refused_at(refusal(std::string(bad) + "\n" + triangle), "b.scene:1: ", "background colour must not be negative"));
    }
    CHECK(refusal("background 0 0 10000\n" + triangle) == "");
    // Numbers up to the float maximum are read; a vertex at 3.4028234663852886e38 (the float
    // maximum exactly) is kept.
    CHECK(refusal("triangle v 3.4028234663852886e38 0 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1\n") == "");
    CHECK(refused_at(refusal("triangle v 3.4028236e38 0 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1\n"), "b.scene:1: ", "beyond a float's range"));
    // Camera: 0 < near < far, an eye and target neither too close nor too far apart.
    CHECK(refused_at(refusal("camera near 1 far 1\n" + triangle), "b.scene:1: ", "camera needs 0 < near < far"));
    CHECK(refusal("camera near 1 far 1.0001\n" + triangle) == "");
    CHECK(refused_at(refusal("camera far 5 \\\n  near 10\n" + triangle), "b.scene:2: ", "camera needs 0 < near < far"));  // at near, the later word
    CHECK(refused_at(refusal("camera eye 0 0 0 target 1e-300 0 0\n" + triangle), "b.scene:1: ", "too close together or too far apart"));
    CHECK(refused_at(refusal("camera eye 0 0 0 target 1e200 0 0\n" + triangle), "b.scene:1: ", "too close together or too far apart"));
    // Texture options: B and C in [-10, 10] (kept as given: B then C), max_anisotropy in
    // [1, 64], a border alpha in [0, 1], and a file.
    const std::string texture = "texture t file " + checker();
    const Scene cubic = parsed(texture + " filter bicubic cubic 10 -10\n" + triangle);
    CHECK(cubic.textures[0].sampler.cubic_b == 10.0f);
    CHECK(cubic.textures[0].sampler.cubic_c == -10.0f);
    CHECK(parsed(texture + " filter bicubic cubic 1 0\n" + triangle).textures[0].sampler.cubic_b == 1.0f);
    for (const char* bad : {" cubic 10.5 0", " cubic 0 11", " cubic -11 0", " cubic 0 -10.5"}) {
        CAPTURE(bad);
        CHECK(refused_at(refusal(texture + " filter bicubic" + bad + "\n" + triangle), "b.scene:1: ", "the cubic's B and C must be between -10 and 10"));
    }
    CHECK(parsed(texture + " filter ewa max_anisotropy 1\n" + triangle).textures[0].sampler.max_anisotropy == 1.0f);
    CHECK(parsed(texture + " filter ewa max_anisotropy 64\n" + triangle).textures[0].sampler.max_anisotropy == 64.0f);
    for (const char* bad : {" max_anisotropy 0.5", " max_anisotropy 0.999", " max_anisotropy 65", " max_anisotropy 64.5"}) {
        CAPTURE(bad);
        CHECK(refused_at(refusal(texture + " filter ewa" + bad + "\n" + triangle), "b.scene:1: ", "max_anisotropy must be between 1 and 64"));
    }
    CHECK(parsed(texture + " wrap border border 0 0 0 0\n" + triangle).textures[0].sampler.border.w == 0.0f);
    CHECK(parsed(texture + " wrap border border 0 0 0 1\n" + triangle).textures[0].sampler.border.w == 1.0f);
    CHECK(refused_at(refusal(texture + " wrap border border 0 0 0 1.01\n" + triangle), "b.scene:1: ", "the border alpha must be between 0 and 1"));
    CHECK(refused_at(refusal(texture + " wrap_v clamp wrap repeat\n" + triangle), "b.scene:1: ", "'wrap' sets both wrap_u and wrap_v"));
    // Node registration: mip levels of their own for each border colour where either axis is
    // border (their ends read through it), shared where the settings are the same.
    for (const char* wraps : {" wrap_u clamp wrap_v border", " wrap_u border wrap_v clamp"}) {
        CAPTURE(wraps);
        const std::string node = " registration node filter trilinear" + std::string(wraps);
        const Scene two = parsed("texture a file " + checker() + node + " border 1 0 0 1\ntexture b file " + checker() + node +
                                 " border 0 0 1 1\ntexture c file " + checker() + node + " border 0 0 1 1\n" + triangle);
        REQUIRE(two.textures[0].mipmap);
        CHECK(two.textures[0].mipmap != two.textures[1].mipmap);
        CHECK(two.textures[1].mipmap == two.textures[2].mipmap);
    }
    CHECK(refused_at(refusal("texture t filter nearest\n" + triangle), "b.scene:1: ", "texture 't' needs 'file PATH'"));
    // Directions and transforms that have none: a zero light direction, rotation axis or
    // scale factor (any of the three).
    CHECK(refused_at(refusal("light directional 0 0 0\n" + triangle), "b.scene:1: ", "light direction must not be zero"));
    CHECK(refused_at(refusal("triangle rotate 90 0 0 0 v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1\n"), "b.scene:1: ", "rotation axis must not be zero"));
    for (const char* bad : {"scale 0 1 1", "scale 1 0 1", "scale 1 1 0", "scale 0"}) {
        CAPTURE(bad);
        CHECK(refused_at(refusal("triangle " + std::string(bad) + " v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1\n"), "b.scene:1: ",
                         "scale factors must not be zero"));
    }
    // A triangle of 4 vertices, said at once.
    CHECK(refused_at(refusal("triangle v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1 v 1 1 0 1 1\n"), "b.scene:1: ", "triangle has more than 3 vertices"));
}

TEST_CASE("scene lines: continued commands keep their words' lines, comments and blanks before a continuing backslash") {
    // A '\\' followed by blanks, or by blanks and a comment, still continues the line.
    for (const char* first : {"size 4 \\  # the width; the height follows\n", "size 4 \\\t\n", "size 4 \\ \t \n"}) {
        CAPTURE(first);
        const Scene s = parsed(std::string(first) + "  4\n" + triangle);
        CHECK(s.width == 4);
        CHECK(s.height == 4);
    }
    // A setting given twice names the line the first began on; an option given twice in one
    // continued command, the line of its first word.
    CHECK(refused_at(refusal("camera eye 0 0 3 \\\n  target 0 0 0\ncamera fov 50\n" + triangle), "b.scene:3: ",
                     "'camera' is given a second time (first on line 1)"));
    CHECK(refused_at(refusal("size 4 4\ncamera eye 0 0 3 \\\n   fov 50 \\\n   fov 60\n" + triangle), "b.scene:4: ",
                     "'fov' is given a second time in this 'camera' command (first on line 3)"));
    // Normals on some vertices only: told at the first vertex without one.
    CHECK(refused_at(refusal("triangle v -1 -1 0 0 0 n 0 0 1 \\\n  v 1 -1 0 1 0 n 0 0 1 \\\n  v 0 1 0 0 1 \\\n  cull none\n"), "b.scene:3: ",
                     "triangle has a normal 'n' on 2 of its 3 vertices"));
    // A mesh's source is the line of its command.
    const std::string dir = scratch_folder("bounds-mesh-line");
    write_text(dir + "/plain.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
    const Scene s = parsed("size 4 4\n\nmesh plain.obj\n", dir + "/m.scene");
    REQUIRE(s.meshes.size() == 1);
    CHECK(s.meshes[0].source == dir + "/m.scene:3");
}

TEST_CASE("computed normals of faces whose windings cancel are +z, not NaN, in a quad and in an OBJ") {
    // A quad whose two halves (split along v0-v2) have opposite windings and equal areas:
    // (v0, v1, v2) faces +z, (v0, v2, v3) -z. At v0 and v2 the summed face normals are 0,
    // which has no direction: they take +z; v1 and v3 their own triangle's.
    const Scene s = parsed("quad v -1 0 0 0 0 v 0 -1 0 0 0 v 1 0 0 0 0 v 0.5 -1 0 0 0\n");
    const std::vector<Vertex>& corners = s.meshes[0].vertices;
    REQUIRE(corners.size() == 4);
    CHECK(corners[0].normal == glm::vec3(0.0f, 0.0f, 1.0f));
    CHECK(corners[1].normal == glm::vec3(0.0f, 0.0f, 1.0f));
    CHECK(corners[2].normal == glm::vec3(0.0f, 0.0f, 1.0f));
    CHECK(corners[3].normal == glm::vec3(0.0f, 0.0f, -1.0f));
    // In an OBJ: position 1 is on a counter-clockwise and a clockwise face of equal areas.
    const std::string dir = scratch_folder("bounds-cancel");
    write_text(dir + "/c.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nf 1 2 3\nf 1 5 4\n");
    const Mesh mesh = load_obj(dir + "/c.obj", [](const ObjMaterialInfo&) { return 0; });
    for (const Vertex& v : mesh.vertices)
        if (v.position == glm::vec3(0.0f)) CHECK(v.normal == glm::vec3(0.0f, 0.0f, 1.0f));
}

TEST_CASE("OBJ materials: usemtl picks the scene material of its name, faces without usemtl the default grey") {
    const std::string dir = scratch_folder("bounds-usemtl");
    write_text(dir + "/red.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    write_text(dir + "/plain.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
    const auto centre = [&](const std::string& text) {
        const Scene scene = parsed("size 8 8\ncamera eye 0 0 3\n" + text, dir + "/s.scene");
        RenderStats stats;
        const Framebuffer fb = render(scene, RenderOptions{}, stats);
        return fb.color[fb.index(4, 4)];
    };
    // No .mtl file describes red: the scene's material of that name is used.
    CHECK(centre("material red color 1 0 0\nmesh red.obj\n") == Color(1.0f, 0.0f, 0.0f));
    // A scene material named "" is not the default material of faces without usemtl.
    const Color grey = centre("material \"\" color 1 0 0\nmesh plain.obj\n");
    CHECK(grey.x == doctest::Approx(srgb_to_linear(0.8f)));
    CHECK(grey.y == doctest::Approx(srgb_to_linear(0.8f)));
}

TEST_CASE("OBJ bounds: numbers up to the float maximum, the first vt, faces without vt, mtllib names") {
    // (OBJ lines refused at their bounds are rows of test_cli_errors' table of bad OBJ lines)
    const std::string dir = scratch_folder("bounds-obj");
    const std::string three = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\n";
    write_text(dir + "/max.obj", "v 3.4028234663852886e38 0 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
    CHECK_NOTHROW(load_obj(dir + "/max.obj", [](const ObjMaterialInfo&) { return 0; }));
    // Some faces without vt under a textured material.
    write_text(dir + "/mixed.obj", three + "v 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\nf 2 4 3\n");
    CHECK(refused_at(refusal(texture_line() + "\nmaterial m texture t\nmesh mixed.obj material m\n", dir + "/s.scene"), dir + "/s.scene:3: ",
                     "has faces without texture coordinates (vt)"));
    // The first vt is index 1 (tinyobjloader's 0): its numbers are the corner's (u, v).
    write_text(dir + "/uv.obj", three + "vt 0.25 0.75\nvt 0.5 0.5\nf 1/1 2/2 3/1\n");
    const Mesh uv = load_obj(dir + "/uv.obj", [](const ObjMaterialInfo&) { return 0; });
    CHECK(uv.has_uv);
    for (const Vertex& v : uv.vertices) CHECK(v.uv == (v.position.x == 1.0f ? glm::dvec2(0.5, 0.5) : glm::dvec2(0.25, 0.75)));
    // mtllib: a tab before the name, a line with no name (nothing to read), and a file an
    // earlier line loaded, after which the next name is read.
    write_text(dir + "/red.mtl", "newmtl red\nKd 1 0 0\n");
    write_text(dir + "/blue.mtl", "newmtl blue\nKd 0 0 1\n");
    Color diffuse;
    const auto resolve = [&](const ObjMaterialInfo& info) {
        diffuse = info.diffuse;
        return 0;
    };
    write_text(dir + "/tab.obj", "mtllib\tred.mtl\nmtllib\n" + three + "usemtl red\nf 1 2 3\n");
    load_obj(dir + "/tab.obj", resolve);
    CHECK(diffuse == Color(1.0f, 0.0f, 0.0f));
    write_text(dir + "/twice.obj", "mtllib red.mtl\nmtllib red.mtl blue.mtl\n" + three + "usemtl blue\nf 1 2 3\n");
    const Mesh twice = load_obj(dir + "/twice.obj", resolve);
    CHECK(diffuse == Color(0.0f, 0.0f, 1.0f));
    CHECK(twice.material_files == std::vector<std::string>{dir + "/red.mtl", dir + "/blue.mtl"});
    // An OBJ in a sub-folder with an empty mtllib line reads as one without it.
    std::system(("mkdir -p '" + dir + "/sub'").c_str());
    write_text(dir + "/sub/m.obj", "mtllib\n" + three + "f 1 2 3\n");
    CHECK(load_obj(dir + "/sub/m.obj", [](const ObjMaterialInfo&) { return 0; }).triangles.size() == 1);
}

TEST_CASE("command-line bounds and forms: --span-tolerance, the default output name, explain's pixel, help") {
    const std::string dir = scratch_folder("bounds-cli");
    write_text(dir + "/s.scene", "size 4 4\ncamera eye 0 0 3\n" + triangle);
    const std::string scene = dir + "/s.scene -o " + dir + "/o.png";
    // --span-tolerance: above 0, at most 1000, a number and nothing after it.
    CHECK(run_texr("render " + scene + " --span adaptive --span-tolerance 1000").exit_code == 0);
    CHECK(run_texr("render " + scene + " --span adaptive --span-tolerance 1e-9").exit_code == 0);
    for (const char* bad : {"0", "1000.5", "0.5x", "-1"}) {
        CAPTURE(bad);
        CHECK(run_texr("render " + scene + " --span adaptive --span-tolerance " + bad).exit_code == 2);
    }
    // -o with no name says so.
    const RunResult empty = run_texr("render " + dir + "/s.scene -o ''");
    CHECK(empty.exit_code == 2);
    CHECK(empty.output.find("-o needs a file name") != std::string::npos);
    // The default output is out/<scene name>.png: the name is all before the last dot, and a
    // name that is all extension keeps it. out/ may exist already.
    write_text(dir + "/a.b.scene", "size 4 4\ncamera eye 0 0 3\n" + triangle);
    write_text(dir + "/.scene", "size 4 4\ncamera eye 0 0 3\n" + triangle);
    const std::string in_dir = "cd '" + dir + "' && " + std::string(TEXR_BINARY) + " render ";
    CHECK(std::system((in_dir + "a.b.scene > log.txt 2>&1").c_str()) == 0);
    CHECK(file_exists(dir + "/out/a.b.png"));
    CHECK(std::system((in_dir + ".scene > log.txt 2>&1").c_str()) == 0);
    CHECK(file_exists(dir + "/out/.scene.png"));
    CHECK_FALSE(file_exists(dir + "/out/.png"));
    // One frame says "frame time"; --repeat, the median; --stats of one frame has no mean.
    RunResult r = run_texr("render " + scene + " --stats");
    CHECK(r.output.find("\nframe time ") != std::string::npos);
    CHECK(r.output.find("median") == std::string::npos);
    CHECK(r.output.find("the mean over") == std::string::npos);
    r = run_texr("render " + scene + " --repeat 3 --stats");
    CHECK(r.output.find("median frame time") != std::string::npos);
    CHECK(r.output.find("the mean over 3 frames") != std::string::npos);
    // explain: a negative pixel index is out of range, not an option; --size widens the range.
    r = run_texr("explain " + dir + "/s.scene -1 0");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("X must be a pixel index from 0 to 3, got '-1'") != std::string::npos);
    CHECK(run_texr("explain " + dir + "/s.scene 10 0 --size 16x16").exit_code == 0);
    CHECK(run_texr("explain " + dir + "/s.scene 10 0").exit_code == 2);
    // No command: the help on stderr, exit 2; `texr help`: exit 0.
    r = run_texr("");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("usage") != std::string::npos);
    r = run_texr("help");
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("usage") != std::string::npos);
}

TEST_CASE("--spp, --span and --span-tolerance reach the renderer: the CLI's frame is the library's with those options") {
    // The receding checker plane (models/plane.scene at 320x240), where each option changes pixels.
    const std::string dir = scratch_folder("bounds-options");
    const std::string plane = "size 320 240\ncamera eye 0 1 0 target 0 0.75 -4 fov 60 near 0.05 far 1000\ntexture t file " + checker() +
                              " filter bilinear\nmaterial m texture t\n"
                              "quad material m v -500 0 10 0 0 v 500 0 10 250 0 v 500 0 -990 250 250 v -500 0 -990 0 250\n";
    write_text(dir + "/p.scene", plane);
    struct Run {
        std::string arguments;
        RenderOptions options;
    };
    RenderOptions spp, loose;
    spp.spp = 4;
    loose.span_mode = SpanMode::adaptive;
    loose.span_tolerance = 1000.0;
    const Scene scene = load_scene(dir + "/p.scene");
    RenderStats stats;
    const std::vector<std::uint8_t> plain = encode_frame(render(scene, RenderOptions{}, stats), FrameFormat::ppm);
    for (const Run& run : {Run{"--spp 4", spp}, Run{"--spp=4", spp}, Run{"--span adaptive --span-tolerance 1000", loose}}) {
        CAPTURE(run.arguments);
        REQUIRE(run_texr("render " + dir + "/p.scene -o " + dir + "/o.ppm " + run.arguments).exit_code == 0);
        const std::string cli = read_file(dir + "/o.ppm");
        const std::vector<std::uint8_t> library = encode_frame(render(scene, run.options, stats), FrameFormat::ppm);
        CHECK(cli == std::string(library.begin(), library.end()));
        CHECK(library != plain);  // (the option changes the frame)
    }
}
