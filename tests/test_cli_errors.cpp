// Bad input, tried as a user would: through the texr binary. Each case must give one clear
// message (file:line where there is one), a non-zero exit, and no output file.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <sstream>
#include <tuple>

#include <stb_image_write.h>
#include <zlib.h>

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "helpers.h"
#include "texr/core/color.h"
#include "texr/core/text_line.h"
#include "texr/io/frame_writer.h"
#include "texr/render/renderer.h"
#include "texr/scene/parser.h"
#include "texr/texture/image.h"

using namespace texr::testing;

namespace {

const std::string good_scene =
    "size 32 24\n"
    "camera eye 0 0 3 target 0 0 0\n"
    "material red color 1 0 0\n"
    "triangle material red v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n";

// stb_image_write's callback that appends what it writes to the std::string `out`.
void append_to_string(void* out, void* data, int size) { static_cast<std::string*>(out)->append(static_cast<char*>(data), std::size_t(size)); }

// An 8 x 8 JPEG from stb_image_write at quality 90 (4:2:0), its bytes k * step.
std::string small_jpeg(unsigned step) {
    unsigned char rgb[8 * 8 * 3];
    for (std::size_t i = 0; i < sizeof rgb; ++i) rgb[i] = static_cast<unsigned char>(step * i);
    std::string jpeg;
    REQUIRE(stbi_write_jpg_to_func(append_to_string, &jpeg, 8, 8, 3, rgb, 90));
    return jpeg;
}

// A PNG chunk: its data's length (big-endian), type, data and CRC (zlib's crc32 of type and data).
std::string png_chunk(const std::string& type, const std::string& data) {
    std::string c;
    const auto put32 = [&](std::uint32_t v) {
        for (int k = 3; k >= 0; --k) c += char((v >> (8 * k)) & 255);
    };
    put32(std::uint32_t(data.size()));
    c += type + data;
    put32(std::uint32_t(crc32(crc32(0, nullptr, 0), reinterpret_cast<const Bytef*>(c.data() + 4), uInt(c.size() - 4))));
    return c;
}

// Writes `bytes` to dir/name and renders good_scene with a quad textured by it into
// dir/out.png (a run over 60 s fails: a hang is an error).
RunResult render_texture_file(const std::string& dir, const std::string& name, const std::string& bytes) {
    std::ofstream(dir + "/" + name, std::ios::binary) << bytes;
    write_text(dir + "/scene.txt", "texture t file " + name + "\nmaterial m texture t\n"
                                   "quad material m v -1 -1 0 0 0 v 1 -1 0 1 0 v 1 1 0 1 1 v -1 1 0 0 1\n" + good_scene);
    return run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png", 60);
}

struct Case {
    std::string scene;
    std::string expected_message;
};

// Writes `scene` into a fresh folder, renders it to out.png there, and checks the failure.
void expect_failure(const std::string& name, const std::string& scene, const std::string& expected) {
    const std::string dir = scratch_folder(name);
    write_text(dir + "/scene.txt", scene);
    const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find(expected) != std::string::npos);
    CHECK(r.output.find("texr: ") == 0);  // one message, starting with the program's name
    CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
    CHECK_FALSE(file_exists(dir + "/out.png"));
}

// The name of the material `texr explain` finds at pixel (x, y) of DIR/scene.txt, or its
// whole output when it names none.
std::string explained_material(const std::string& dir, int x, int y) {
    const std::string out = run_texr("explain " + dir + "/scene.txt " + std::to_string(x) + " " + std::to_string(y)).output;
    const std::string mark = ", material '";
    const std::size_t at = out.find(mark);
    if (at == std::string::npos) return out;
    const std::size_t first = at + mark.size();
    return out.substr(first, out.find('\'', first) - first);
}

// The hidden temporary files (.texr-*) in `dir`, removed too with remove = true.
int temporary_files(const std::string& dir, bool remove = false) {
    int count = 0;
    if (DIR* listing = ::opendir(dir.c_str())) {
        while (const dirent* entry = ::readdir(listing))
            if (std::strncmp(entry->d_name, ".texr-", 6) == 0) {
                ++count;
                if (remove) std::remove((dir + "/" + entry->d_name).c_str());
            }
        ::closedir(listing);
    }
    return count;
}

// Sets the signal's action to the default and unblocks it (in a child, before it installs
// texr's handler or runs texr, which installs it only over the default action).
void default_signal_action(int signal_number) {
    ::signal(signal_number, SIG_DFL);
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, signal_number);
    ::sigprocmask(SIG_UNBLOCK, &set, nullptr);
}

// Waits for process `child`, sending it `signal_number` the first time `writing()` is true
// (and SIGKILL after 60 s). Returns the wait status, and whether the signal was sent.
template <class Writing>
std::pair<int, bool> wait_stopping_write(pid_t child, int signal_number, Writing writing) {
    int status = 0;
    bool sent = false;
    const auto start = std::chrono::steady_clock::now();
    while (::waitpid(child, &status, WNOHANG) == 0) {
        if (!sent && writing()) {
            sent = true;
            ::kill(child, signal_number);
        }
        if (std::chrono::steady_clock::now() - start > std::chrono::seconds(60)) ::kill(child, SIGKILL);
        std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    return {status, sent};
}

}  // namespace

TEST_CASE("a good scene renders and writes the file") {
    const std::string dir = scratch_folder("good");
    write_text(dir + "/scene.txt", good_scene);
    const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.ppm");
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    REQUIRE(file_exists(dir + "/out.ppm"));
    std::ifstream in(dir + "/out.ppm", std::ios::binary);
    std::string magic;
    int w = 0, h = 0, max = 0;
    in >> magic >> w >> h >> max;
    CHECK(magic == "P6");
    CHECK(w == 32);
    CHECK(h == 24);
    CHECK(max == 255);
}

TEST_CASE("bad scene lines name file:line and what was expected") {
    expect_failure("malformed", "camera eye 0 1\n" + good_scene, "scene.txt:1: expected 3 numbers for eye");
    // The frame's settings once each.
    expect_failure("camera-twice", good_scene + "camera fov 30\n", "scene.txt:5: 'camera' is given a second time (first on line 2)");
    expect_failure("size-twice", "size 8 8\n" + good_scene, "scene.txt:2: 'size' is given a second time (first on line 1)");
    expect_failure("background-twice", "background 1 0 0\nbackground 0 0 1\n" + good_scene,
                   "scene.txt:2: 'background' is given a second time (first on line 1)");
    expect_failure("ambient-twice", "ambient 0.1 0.1 0.1\n" + good_scene + "ambient 0.2 0.2 0.2\n",
                   "scene.txt:6: 'ambient' is given a second time (first on line 1)");
    // A name defined twice: the message names the first definition's line.
    expect_failure("material-twice", good_scene + "material red color 0 1 0\n",
                   "scene.txt:5: material 'red' is defined a second time (first on line 3)");
    expect_failure("texture-twice",
                   "texture t file " + source_path("models/textures/checker.png") + "\n\ntexture t file " +
                       source_path("models/textures/checker.png") + "\n" + good_scene,
                   "scene.txt:3: texture 't' is defined a second time (first on line 1)");
    expect_failure("fov-180", "camera fov 180\n" + good_scene, "scene.txt:1: fov must be at least 1e-6 degrees and below 180, got 180");
    expect_failure("fov-tiny", "camera fov 9.9e-7\n" + good_scene, "scene.txt:1: fov must be at least 1e-6 degrees and below 180, got 9.9e-07");
    expect_failure("fov-just-below", "camera fov 9.9999999e-7\n" + good_scene, "below 180, got 9.9999999e-07");  // (not 1e-06)
    // An option once per command: of two values the last would silently win. (translate,
    // rotate and scale compose, and v, n, c give vertices: those repeat.)
    const std::string textured = "texture t file " + source_path("models/textures/checker.png");
    expect_failure("fov-twice", "camera fov 50 fov 70\n" + good_scene,
                   "scene.txt:1: 'fov' is given a second time in this 'camera' command (first on line 1): give it once");
    expect_failure("filter-twice", textured + " filter nearest filter ewa\n" + good_scene,
                   "scene.txt:1: 'filter' is given a second time in this 'texture' command (first on line 1)");
    expect_failure("color-twice", good_scene + "material m color 1 0 0 \\\n  color 0 1 0\n",
                   "scene.txt:6: 'color' is given a second time in this 'material' command (first on line 5)");
    expect_failure("light-color-twice", good_scene + "light directional 0 -1 0 color 1 1 1 color 1 0 0\n",
                   "scene.txt:5: 'color' is given a second time in this 'light' command (first on line 5)");
    expect_failure("object-material-twice", good_scene + "triangle material red material red v 0 0 0 0 0 v 1 0 0 1 0 v 0 1 0 0 1\n",
                   "scene.txt:5: 'material' is given a second time in this 'triangle' command");
    expect_failure("cull-twice", good_scene + "triangle cull back cull none v 0 0 0 0 0 v 1 0 0 1 0 v 0 1 0 0 1\n",
                   "scene.txt:5: 'cull' is given a second time in this 'triangle' command");
    expect_failure("wrap-and-wrap-u", textured + " wrap_u clamp wrap repeat\n" + good_scene,
                   "scene.txt:1: 'wrap' sets both wrap_u and wrap_v: give either wrap, or wrap_u and wrap_v");
    expect_failure("wrap-v-after-wrap", textured + " wrap mirror wrap_v clamp\n" + good_scene,
                   "scene.txt:1: 'wrap' sets both wrap_u and wrap_v");
    {
        const std::string dir = scratch_folder("options-that-repeat");
        write_text(dir + "/scene.txt", good_scene + textured + " wrap_u clamp wrap_v mirror\n"
                                       "quad translate 0 0 -1 translate 0.1 0 0 rotate 10 0 0 1 rotate 5 1 0 0 scale 2 scale 0.5 "
                                       "v -1 -1 0 0 0 v 1 -1 0 1 0 v 1 1 0 1 1 v -1 1 0 0 1\n");
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CAPTURE(r.output);
        CHECK(r.exit_code == 0);
    }
    expect_failure("not-a-number", "size 32 abc\n" + good_scene, "scene.txt:1: expected the height, found 'abc'");
    expect_failure("unknown-command", "size 32 24\nspheroid 1 2 3\n", "scene.txt:2: unknown command 'spheroid'");
    expect_failure("unknown-option", good_scene + "material m colour 1 0 0\n", "scene.txt:5: unknown material option 'colour'");
    // A number where an option was expected: one too many for the option before it.
    expect_failure("six-number-vertex", good_scene + "triangle v -1 0 0 0 0 0 v 1 0 0 1 0 v 0 1 0 0 1\n",
                   "scene.txt:5: unknown triangle option '0' (expected v, n, c, material, cull, translate, rotate or scale): "
                   "a number too many for 'v' before it?");
    expect_failure("four-number-eye", "camera eye 0 0 3 4 target 0 0 0\n" + good_scene,
                   "scene.txt:1: unknown camera option '4' (expected eye, target, up, fov, near or far): a number too many for 'eye' before it?");
    expect_failure("two-number-fov", "camera fov 50 60\n" + good_scene, "a number too many for 'fov' before it?");
    // Several: too many, or the name of the option they belong to left out ('target').
    expect_failure("eye-then-numbers", "camera eye 0 0 3 0 0 0\n" + good_scene,
                   "scene.txt:1: unknown camera option '0' (expected eye, target, up, fov, near or far): numbers too many for 'eye' before "
                   "them, or an option's name missing?");
    expect_failure("word-not-number", good_scene + "material m color 1 0 0 x\n", "scene.txt:5: unknown material option 'x' (expected color, texture, lighting, vertex_colors, bump, reflect, cutout, slope, slope_direction, lightmap, lightmap_repeat, projector, mapping, mapping_center, mapping_axis or mapping_size)\n");
    // 'mesh material m': the file name forgotten.
    expect_failure("mesh-without-file", good_scene + "mesh material red\n",
                   "scene.txt:5: expected an OBJ file name after 'mesh', found 'material', one of its options (mesh FILE [options])");
    {  // (a folder of that name beside the scene is no OBJ file either)
        const std::string dir = scratch_folder("mesh-without-file-folder");
        std::system(("mkdir " + dir + "/material").c_str());
        write_text(dir + "/scene.txt", good_scene + "mesh material red\n");
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CHECK(r.exit_code == 1);
        CHECK(r.output.find("expected an OBJ file name after 'mesh', found 'material'") != std::string::npos);
    }
    expect_failure("unknown-material", "triangle material nope v 0 0 0 0 0 v 1 0 0 1 0 v 0 1 0 0 1\n",
                   "scene.txt:1: unknown material 'nope'");
    expect_failure("unknown-filter", "texture t file x.png filter fancy\n", "scene.txt:1: unknown filter 'fancy'");
    expect_failure("too-few-vertices", "triangle v 0 0 0 0 0 v 1 0 0 1 0\n", "scene.txt:1: triangle needs 3 vertices");
    expect_failure("bad-camera", "camera near 5 far 1\n" + good_scene, "scene.txt:1: camera needs 0 < near < far");
    expect_failure("no-objects", "size 32 24\n", "scene has no objects");
    expect_failure("continuation", good_scene + "quad \\\n", "scene.txt:5: line ends with '\\'");
    // (told at the line whose '\\' the file's end leaves open)
    expect_failure("continuation-end", good_scene + "quad \\\n v 0 0 0 0 0 \\\n", "scene.txt:6: line ends with '\\' but the file ends there");
    // A command continued over several lines: the message names the line of the bad word.
    const std::string quad = "quad \\\n  v -1 -1 0 0 0 \\\n  v 1 -1 0 1 0 \\\n  v 1 1 0 1 1";
    expect_failure("continued-value", good_scene + quad + " \\\n  v -1 1 0 x 1\n", "scene.txt:9: expected the vertex's texture coordinate u, found 'x'");
    expect_failure("continued-option", good_scene + "material m \\\n  color 1 0 0 \\\n  colour 1 0 0\n",
                   "scene.txt:7: unknown material option 'colour'");
    expect_failure("continued-count", good_scene + quad + "\n", "scene.txt:8: quad needs 4 vertices");
    // Checks made once the whole command is read name the line of the value they refuse.
    const std::string objects = "material red color 1 0 0\ntriangle material red v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n";
    expect_failure("continued-fov", "camera eye 0 0 3 \\\n  fov 0 \\\n  near 0.1 far 10\n" + objects,
                   "scene.txt:2: fov must be at least 1e-6 degrees and below 180");
    expect_failure("continued-near-far", "camera near 5 \\\n  far 1 \\\n  fov 40\n" + objects, "scene.txt:2: camera needs 0 < near < far");
    expect_failure("continued-eye", "camera eye 0 0 3 \\\n  target 0 0 3 \\\n  fov 40\n" + objects,
                   "scene.txt:2: camera eye and target must differ");
    expect_failure("continued-up", "camera up 0 0 1 \\\n  fov 40 \\\n  eye 0 0 3 \\\n  near 1\n" + objects,
                   "scene.txt:1: camera up must not be parallel to the view direction");  // at up, which the message names
    expect_failure("continued-file", good_scene + "texture t \\\n  file nope.png \\\n  filter nearest\n",
                   "scene.txt:6: texr-test-continued-file/nope.png: cannot open image file");
    expect_failure("continued-mesh", good_scene + "mesh \\\n  nope.obj \\\n  cull back\n",
                   "scene.txt:6: texr-test-continued-mesh/nope.obj: cannot open OBJ file");
    expect_failure("continued-near", "camera near 0 \\\n  fov 40 \\\n  far 50\n" + objects, "scene.txt:1: camera needs 0 < near < far");
    expect_failure("continued-up-last", "camera eye 0 0 3 \\\n  fov 40 \\\n  up 0 0 1\n" + objects,
                   "scene.txt:3: camera up must not be parallel to the view direction");
    expect_failure("continued-normals", good_scene + quad + " n 0 0 1 \\\n  v -1 1 0 0 1 n 0 0 1\n",
                   "scene.txt:6: quad has a normal 'n' on 2 of its 4 vertices");
    expect_failure("continued-colours", good_scene + "quad v -1 -1 0 0 0 c 1 0 0 \\\n  v 1 -1 0 1 0 c 1 0 0 \\\n  v 1 1 0 1 1 \\\n  v -1 1 0 0 1 c 1 0 0\n",
                   "scene.txt:7: quad has a colour 'c' on 3 of its 4 vertices");
    // Normals and colours on every vertex of a triangle or quad, or on none.
    expect_failure("some-normals", "triangle v 0 0 0 0 0 n 0 0 1 v 1 0 0 1 0 v 0 1 0 0 1 n 0 0 1\n",
                   "scene.txt:1: triangle has a normal 'n' on 2 of its 3 vertices: give one after every vertex, or none");
    expect_failure("some-colours", "quad v 0 0 0 0 0 v 1 0 0 1 0 c 1 0 0 v 1 1 0 1 1 v 0 1 0 0 1\n",
                   "scene.txt:1: quad has a colour 'c' on 1 of its 4 vertices");
    expect_failure("two-normals", "triangle v 0 0 0 0 0 n 0 0 1 n 0 1 0 v 1 0 0 1 0 v 0 1 0 0 1\n",
                   "scene.txt:1: a second normal 'n' for one vertex");
    expect_failure("two-colours", "triangle v 0 0 0 0 0 c 1 0 0 c 0 1 0 v 1 0 0 1 0 v 0 1 0 0 1\n",
                   "scene.txt:1: a second colour 'c' for one vertex");
}

TEST_CASE("numbers a scene keeps but cannot use are refused: huge colours, float overflow, border alpha, cubic") {
    // (Found by a review: a light of colour 1e17 is infinite once linear, and infinity times a
    // zero cosine made an unlit pixel NaN, written black; 1e39 overflowed the float a vertex
    // is kept in, and the triangle was dropped without a word.)
    const std::string triangle = "triangle material red v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n";
    expect_failure("huge-light", good_scene + "light directional 0 0 1 color 1e17 1e17 1e17\n",
                   "scene.txt:5: light colour must be at most 10000");
    expect_failure("huge-ambient", "ambient 10000.5 0 0\n" + good_scene, "scene.txt:1: ambient colour must be at most 10000");
    expect_failure("huge-material", "size 32 24\nmaterial red color 0 2e4 0\n" + triangle, "scene.txt:2: material colour must be at most 10000");
    expect_failure("huge-vertex-colour", "size 32 24\nmaterial red vertex_colors on\ntriangle material red v -1 -1 0 0 0 c 1e39 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n",
                   "scene.txt:3: the vertex colour must be at most 10000");
    expect_failure("float-position", "size 32 24\nmaterial red\ntriangle material red v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 1e39 0.5 1\n",
                   "scene.txt:3: the vertex position: '1e39' is beyond a float's range (about 3.4e38)");
    expect_failure("border-alpha", "texture t file x.png wrap border border 1 1 1 -5\n" + good_scene,
                   "scene.txt:1: the border alpha must be between 0 and 1");
    expect_failure("huge-border", "texture t file x.png wrap border border 1e17 0 0 1\n" + good_scene,
                   "scene.txt:1: border colour must be at most 10000");
    expect_failure("cubic", "texture t file x.png filter bicubic cubic 1e39 0\n" + good_scene,
                   "scene.txt:1: the cubic's B and C must be between -10 and 10");
    // The largest values still render, with no NaN: a light of 10000 (about 4e9 linear) on a
    // lit triangle, and a vertex at 3e38.
    const std::string dir = scratch_folder("largest-values");
    write_text(dir + "/scene.txt", "size 16 16\ncamera eye 0 0 3\nambient 0.5 0.5 0.5\nlight directional 1 0 0 color 10000 10000 10000\n"
                                   "material red color 1 0 0 lighting lambert\n" + triangle +
                                   "triangle material red v 0 0 -3e38 0 0 v 1 0 -3e38 1 0 v 0 1 -3e38 0 1\n");
    const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.ppm");
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    texr::RenderStats stats;
    const texr::Framebuffer fb = texr::render(texr::load_scene(dir + "/scene.txt"), {}, stats);
    for (const texr::Color& c : fb.color) CHECK((std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)));
    // The triangle's centre: lit by the ambient alone (the light grazes it), sRGB 0.5 red.
    CHECK(fb.color[fb.index(8, 9)].x == doctest::Approx(texr::srgb_to_linear(0.5f)));
}

TEST_CASE("missing files are named with the scene line that refers to them") {
    expect_failure("missing-texture", "texture t file nothere.png\n" + good_scene, "scene.txt:1: ");
    expect_failure("missing-texture-name", "texture t file nothere.png\n" + good_scene, "nothere.png: cannot open image file");
    expect_failure("missing-obj", good_scene + "mesh nothere.obj\n", "nothere.obj: cannot open OBJ file");
    expect_failure("not-an-image", "texture t file scene.txt\n" + good_scene,
                   "scene.txt: not a readable image: not a format stb_image reads");
    {  // a PNG cut short: its first 20000 of 38803 bytes
        const std::string dir = scratch_folder("cut-png");
        std::ifstream in(source_path("models/textures/detail.png"), std::ios::binary);
        std::string bytes(20000, '\0');
        in.read(bytes.data(), 20000);
        std::ofstream(dir + "/cut.png", std::ios::binary) << bytes;
        write_text(dir + "/scene.txt", "texture t file cut.png\n" + good_scene);
        const RunResult cut = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CHECK(cut.exit_code == 1);
        CHECK(cut.output.find("scene.txt:1: " + dir + "/cut.png: not a readable image: the file is cut short or damaged") !=
              std::string::npos);
        // A binary PPM whose texels end early (stb_image would read it): 2x2x3 = 12 bytes
        // asked for, 5 given; with a comment in the header.
        write_text(dir + "/cut.ppm", "P6\n# two by two\n2 2\n255\nabcde");
        write_text(dir + "/scene.txt", "texture t file cut.ppm\n" + good_scene);
        const RunResult ppm = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CHECK(ppm.exit_code == 1);
        CHECK(ppm.output.find("cut.ppm: not a readable image: the file is cut short (its header asks for 12 bytes of texels, it holds 5)") !=
              std::string::npos);
        // What stb_image would misread: a size of 0 (which crashed the render), a size beyond
        // its reach, 16-bit samples, and a comment ended by CR before a short file.
        for (const auto& header_message : std::vector<std::pair<std::string, std::string>>{
                 {"P6\n0 0\n255\n", "its header gives a size of 0x0"},
                 {"P6\n3 0\n255\n", "its header gives a size of 3x0"},
                 {"P6\n4294967296 4294967296\n255\n", "its header gives a size of 4294967296x4294967296"},
                 {"P5\n2 2\n65535\n", "a 16-bit PPM/PGM (largest value 65535); texr reads 8-bit ones"},
                 {"P6\r# c\r2 2\r255\r", "the file is cut short (its header asks for 12 bytes of texels, it holds 9)"},
                 // A header that ends before its largest value: stb_image then left the texels
                 // unread, and the frame showed whatever memory held (valgrind: uninitialised).
                 {"P6\n2 2\n", "its PPM/PGM header is cut short or damaged (no largest value)"},
                 {"P6\n2 2\n#", "its PPM/PGM header is cut short or damaged (no largest value)"},  // the file ends in the comment
                 {"P5 # no numbers at all\n#", "its PPM/PGM header is cut short or damaged (no width)"},
                 {"P6\n2 2 0\n", "its PPM/PGM header gives a largest value of 0"}}) {
            // (named, not a structured binding: CAPTURE's lambda cannot capture one in C++17)
            const std::string &header = header_message.first, &message = header_message.second;
            write_text(dir + "/bad.ppm", header + std::string(9, 'x'));
            write_text(dir + "/scene.txt", "texture t file bad.ppm\n" + good_scene);
            const RunResult bad = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
            CAPTURE(header);
            CHECK(bad.exit_code == 1);
            CHECK(bad.output.find("bad.ppm: not a readable image: " + message) != std::string::npos);
        }
    }
    {  // A file of 2 GiB or more (stb_image takes an int length) is refused by its size, before
       // it is read: a sparse file of 3 GiB, which reading would have taken 10 s and 2 GB.
        const std::string dir = scratch_folder("huge-image");
        REQUIRE(std::system(("truncate -s 3G " + dir + "/huge.png").c_str()) == 0);
        write_text(dir + "/scene.txt", "texture t file huge.png\n" + good_scene);
        const RunResult huge = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CHECK(huge.exit_code == 1);
        CHECK(huge.output.find("huge.png: not a readable image: it holds 2 GiB or more, more than stb_image reads") != std::string::npos);
        std::system(("rm -f " + dir + "/huge.png").c_str());
    }
    const RunResult r = run_texr("render does-not-exist.scene -o nowhere.png");
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("does-not-exist.scene: cannot open scene file") != std::string::npos);
}

TEST_CASE("an OBJ without UVs under a textured material is refused with a clear message") {
    const std::string dir = scratch_folder("obj-no-uv");
    write_text(dir + "/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string png = source_path("models/textures/checker.png");  // an absolute path
    write_text(dir + "/scene.txt", "texture t file \"" + png + "\"\nmaterial m texture t\nmesh tri.obj material m\n");
    const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("scene.txt:3: ") != std::string::npos);
    CHECK(r.output.find("has faces without texture coordinates") != std::string::npos);
    CHECK_FALSE(file_exists(dir + "/out.png"));
    // Without a texture the same OBJ renders.
    write_text(dir + "/scene.txt", "camera eye 0 0 3\nmesh tri.obj\n");
    CHECK(run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png").exit_code == 0);

    // Faces with vt under a textured material and faces without under an untextured one: the
    // textured faces have what they need, so it renders (it was refused, naming the textured
    // material); with the materials the other way round it is refused, naming the textured
    // material of the faces without vt.
    const std::string positions = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 2 -1 0\nv 2 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
    write_text(dir + "/two.obj", positions + "usemtl grid\nf 1/1 2/2 3/3 4/4\nusemtl red\nf 2 5 6 3\n");
    write_text(dir + "/swapped.obj", positions + "usemtl red\nf 1/1 2/2 3/3 4/4\nusemtl grid\nf 2 5 6 3\n");
    const std::string materials = "texture t file \"" + png + "\"\nmaterial grid texture t\nmaterial red color 1 0 0\ncamera eye 0.5 0 4\n";
    write_text(dir + "/two.scene", materials + "mesh two.obj\n");
    RunResult two = run_texr("render " + dir + "/two.scene -o " + dir + "/two.png");
    CAPTURE(two.output);
    CHECK(two.exit_code == 0);
    CHECK(file_exists(dir + "/two.png"));
    write_text(dir + "/swapped.scene", materials + "mesh swapped.obj\n");
    two = run_texr("render " + dir + "/swapped.scene -o " + dir + "/swapped.png");
    CHECK(two.exit_code == 1);
    CHECK(two.output.find("swapped.scene:5: " + dir + "/swapped.obj has faces without texture coordinates (vt) drawn with material 'grid', "
                          "which uses texture 't'") != std::string::npos);
    // `material grid` on the mesh line draws every face with the texture: refused.
    write_text(dir + "/two.scene", materials + "mesh two.obj material grid\n");
    CHECK(run_texr("render " + dir + "/two.scene -o " + dir + "/two2.png").exit_code == 1);
}

TEST_CASE("an output path that cannot be written is refused before the scene is read or rendered") {
    const std::string dir = scratch_folder("output-first");
    write_text(dir + "/bad.txt", "size 32 24\nsphere\n");  // a scene error on line 2
    // The output's folder is checked first: its message comes, not the scene's.
    RunResult r = run_texr("render " + dir + "/bad.txt -o " + dir + "/missing/out.png");
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output == "texr: " + dir + "/missing/out.png: cannot write output file: there is no folder '" + dir + "/missing'\n");
    std::system(("mkdir -p '" + dir + "/folder.png'").c_str());
    r = run_texr("render " + dir + "/bad.txt -o " + dir + "/folder.png");
    CHECK(r.output == "texr: " + dir + "/folder.png: cannot write output file: it is a folder\n");
    // The benchmark's folder too: at once, not after the benchmarks ran.
    write_text(dir + "/file", "a file, not a folder");
    r = run_texr("bench spans --quick --out " + dir + "/file/bench");
    CHECK(r.exit_code == 1);
    CHECK(r.output == "texr: " + dir + "/file/bench: cannot make the output folder: Not a directory\n");
    r = run_texr("bench spans --quick --out " + dir + "/file");
    CHECK(r.output == "texr: " + dir + "/file: cannot make the output folder: a file of that name is in the way\n");
}

TEST_CASE("the default output goes to out/ in the current folder, which is made if missing") {
    const std::string dir = scratch_folder("default-output");
    write_text(dir + "/scene.txt", good_scene);
    const std::string command = "cd '" + dir + "' && " + std::string(TEXR_BINARY) + " render scene.txt > log.txt 2>&1";
    CHECK(std::system(command.c_str()) == 0);
    CHECK(file_exists(dir + "/out/scene.png"));
}

TEST_CASE("writing over a file keeps its permissions, and a symbolic link is written through") {
    const std::string dir = scratch_folder("replace");
    write_text(dir + "/scene.txt", good_scene);
    write_text(dir + "/frame.png", "old");
    std::system(("chmod 640 '" + dir + "/frame.png'").c_str());
    CHECK(run_texr("render " + dir + "/scene.txt -o " + dir + "/frame.png").exit_code == 0);
    struct stat info;
    REQUIRE(::stat((dir + "/frame.png").c_str(), &info) == 0);
    CHECK((info.st_mode & 0777) == 0640);
    CHECK(info.st_size > 3);
    // A link to a file in another folder: the file is replaced, the link stays a link.
    std::system(("mkdir -p '" + dir + "/frames' && echo old > '" + dir + "/frames/target.png' && ln -s frames/target.png '" + dir +
                 "/link.png'").c_str());
    CHECK(run_texr("render " + dir + "/scene.txt -o " + dir + "/link.png").exit_code == 0);
    REQUIRE(::lstat((dir + "/link.png").c_str(), &info) == 0);
    CHECK(S_ISLNK(info.st_mode));
    REQUIRE(::stat((dir + "/frames/target.png").c_str(), &info) == 0);
    CHECK(info.st_size > 4);
    CHECK(std::system(("ls -a '" + dir + "/frames' '" + dir + "' | grep -q '^\\.texr-'").c_str()) != 0);  // no temporary file left
    // A chain of links to a file not made yet: the last name is written, the links stay.
    std::system(("cd '" + dir + "' && ln -s chain2.png chain1.png && ln -s frames/new.png chain2.png").c_str());
    CHECK(run_texr("render " + dir + "/scene.txt -o " + dir + "/chain1.png").exit_code == 0);
    REQUIRE(::lstat((dir + "/chain2.png").c_str(), &info) == 0);
    CHECK(S_ISLNK(info.st_mode));
    CHECK(file_exists(dir + "/frames/new.png"));
    // Links in a loop, and a link to a pipe (which the rename would replace), are refused.
    std::system(("cd '" + dir + "' && ln -s loop.png loop.png && mkfifo pipe && ln -s pipe pipe.png").c_str());
    RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/loop.png");
    CHECK(r.output == "texr: " + dir + "/loop.png: cannot write output file: its symbolic links go round in a loop\n");
    r = run_texr("render " + dir + "/scene.txt -o " + dir + "/pipe.png");
    CHECK(r.output == "texr: " + dir + "/pipe.png: cannot write output file: its link's target " + dir + "/pipe is a device or a pipe, not a file\n");
    REQUIRE(::lstat((dir + "/pipe").c_str(), &info) == 0);
    CHECK(S_ISFIFO(info.st_mode));
}

TEST_CASE("texr explain writes nothing and needs no writable folder") {
    // explain renders without an output: a folder where render's default output or any
    // placeholder name would go is no obstacle.
    const std::string dir = scratch_folder("explain-nowrite");
    write_text(dir + "/scene.txt", good_scene);
    std::system(("mkdir -p '" + dir + "/unused.png' '" + dir + "/out/scene.png'").c_str());
    const std::string command = "cd '" + dir + "' && " + std::string(TEXR_BINARY) + " explain scene.txt 16 12 > log.txt 2>&1";
    CHECK(std::system(command.c_str()) == 0);
}

TEST_CASE("an unwritable output path fails cleanly and leaves the previous file untouched") {
    const std::string dir = scratch_folder("unwritable");
    write_text(dir + "/scene.txt", good_scene);
    write_text(dir + "/blocker", "a file, not a folder");
    RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/blocker/out.png");
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("blocker/out.png: cannot write output file") != std::string::npos);

    // A failing render must not touch an existing output file.
    write_text(dir + "/out.png", "previous frame");
    write_text(dir + "/bad.txt", "size 32 24\nsphere\n");
    r = run_texr("render " + dir + "/bad.txt -o " + dir + "/out.png");
    CHECK(r.exit_code == 1);
    std::ifstream in(dir + "/out.png");
    std::string content;
    std::getline(in, content);
    CHECK(content == "previous frame");
    // And no temporary file is left beside it.
    CHECK(run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png").exit_code == 0);
    CHECK(std::system(("ls -a '" + dir + "' | grep -q texr-").c_str()) != 0);
    // A file name of 250 characters (NAME_MAX is 255): the temporary name does not grow with it.
    const std::string long_name = dir + "/" + std::string(246, 'f') + ".png";
    r = run_texr("render " + dir + "/scene.txt -o " + long_name);
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    CHECK(file_exists(long_name));
}

TEST_CASE("command-line mistakes exit with code 2 and say what is wrong") {
    const std::string dir = scratch_folder("usage");
    write_text(dir + "/scene.txt", good_scene);
    const std::string scene = dir + "/scene.txt -o " + dir + "/out.png";
    RunResult r = run_texr("render " + scene + " --size 0x0");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("--size 0x0 is out of range") != std::string::npos);
    r = run_texr("render " + scene + " --size 100000x100000");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("out of range") != std::string::npos);
    r = run_texr("render " + scene + " --size 640");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("--size expects WxH") != std::string::npos);
    r = run_texr("render " + scene + " --fast");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("unknown option '--fast'") != std::string::npos);
    r = run_texr("render " + scene + " --repeat -3");
    CHECK(r.exit_code == 2);
    r = run_texr("render " + scene + " --span-tolerance 2000");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("at most 1000") != std::string::npos);
    // A tolerance only the adaptive mode reads: with another mode (or the default) it would
    // be ignored, so it is refused.
    for (const std::string mode : {"", " --span exact", " --span affine16"}) {
        r = run_texr("render " + scene + mode + " --span-tolerance 0.1");
        CHECK(r.exit_code == 2);
        CHECK(r.output == "texr: --span-tolerance applies to --span adaptive only (the other span modes have no tolerance)\n");
    }
    for (const std::string command : {"--threads 300", "--spp 65"}) {
        r = run_texr("render " + scene + " " + command);
        CHECK(r.output == "texr: " + command.substr(0, command.find(' ')) + " expects a whole number from 1 to " +
                              (command[2] == 't' ? "256" : "64") + ", got '" + command.substr(command.find(' ') + 1) + "'\n");
    }
    // Beyond --repeat's limit (a review found "expects a positive whole number" here).
    r = run_texr("render " + scene + " --repeat 2000000000");
    CHECK(r.exit_code == 2);
    CHECK(r.output == "texr: --repeat expects a whole number from 1 to 1000000000, got '2000000000'\n");
    // Digits alone: no sign and no white space in front (which std::stoll takes).
    for (const std::string number : {"+2", "' 2'", "'\t2'"}) {
        CAPTURE(number);
        r = run_texr("render " + scene + " --threads " + number);
        CHECK(r.exit_code == 2);
        CHECK(r.output.rfind("texr: --threads expects a whole number from 1 to 256, got ", 0) == 0);
        r = run_texr("bench --repeat " + number + " --out " + dir + "/bench");
        CHECK(r.exit_code == 2);
        CHECK(r.output.rfind("texr: --repeat expects a whole number from 1 to 1000000000, got ", 0) == 0);
        r = run_texr("explain " + dir + "/scene.txt 1 " + number);
        CHECK(r.exit_code == 2);
        CHECK(r.output.rfind("texr: Y must be a pixel index from 0 to ", 0) == 0);
    }
    // texr bench takes the same ranges as texr render, but for --spp 1 (which renders with
    // the textures' own filters: no ground truth to score them against).
    for (const char* option : {"--threads 300", "--spp 65", "--threads 0", "--spp 1"}) {
        r = run_texr(std::string("bench filters --out ") + dir + "/bench " + option);
        CAPTURE(option);
        CHECK(r.exit_code == 2);
        CHECK(r.output.find(option[2] == 's' ? "expects a whole number from 2 to 64" : "expects a whole number from 1 to 256") !=
              std::string::npos);
    }
    r = run_texr("frobnicate");
    CHECK(r.exit_code == 2);
    // What was typed is quoted as words from files are: an option, number or keyword with
    // every byte that is not printable ASCII as \xNN (so that a look-alike, such as a
    // no-break space or a multiplication sign, shows), an argument too many with its control
    // bytes and bytes that are not UTF-8 as \xNN (UTF-8 kept); likewise an unknown command.
    r = run_texr("render " + scene + " '--f\x1b[2J\xC3\xA9'");
    CHECK(r.exit_code == 2);
    CHECK(r.output == "texr: unknown option '--f\\x1B[2J\\xC3\\xA9' for 'texr render'\n");
    r = run_texr("render " + scene + " --repeat '2\xC2\xA0'");
    CHECK(r.output == "texr: --repeat expects a whole number from 1 to 1000000000, got '2\\xC2\\xA0'\n");
    r = run_texr("render " + scene + " --size '640\xC3\x97" "480'");
    CHECK(r.output.rfind("texr: --size expects WxH (for example 640x480), each side from 1 to ", 0) == 0);
    CHECK(r.output.find(", got '640\\xC3\\x97" "480'\n") != std::string::npos);
    r = run_texr("bench --repeat '1\xE2\x80\x8B' --out " + dir + "/bench");
    CHECK(r.output == "texr: --repeat expects a whole number from 1 to 1000000000, got '1\\xE2\\x80\\x8B'\n");
    r = run_texr("render " + scene + " --repeat '3\x1b[0m'");
    CHECK(r.output == "texr: --repeat expects a whole number from 1 to 1000000000, got '3\\x1B[0m'\n");
    r = run_texr("render " + scene + " '--span=exa\xC2\x9B" "ct'");
    CHECK(r.output.rfind("texr: unknown span mode 'exa\\xC2\\x9Bct' (expected ", 0) == 0);
    r = run_texr("explain " + dir + "/scene.txt 1 2 '3\x07\xff'");
    CHECK(r.output == "texr: texr explain takes SCENE X Y; '3\\x07\\xFF' is one too many\n");
    r = run_texr("explain " + dir + "/scene.txt '1\xC2\xA0' 2");
    CHECK(r.output.find(", got '1\\xC2\\xA0'\n") != std::string::npos);
    // The path a frame is written to, as `texr render` reports it.
    r = run_texr("render " + dir + "/scene.txt -o '" + dir + "/a\x1b[31m.ppm'");
    CHECK(r.exit_code == 0);
    CHECK(r.output.rfind("wrote " + dir + "/a\\x1B[31m.ppm (", 0) == 0);
    CHECK(file_exists(dir + "/a\x1b[31m.ppm"));
    r = run_texr("'frob\x1b]0;title\x07'");
    CHECK(r.exit_code == 2);
    CHECK(r.output == "texr: unknown command 'frob\\x1B]0;title\\x07' (try texr --help)\n");
    r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.jpg");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("must end in .png or .ppm") != std::string::npos);
    CHECK_FALSE(file_exists(dir + "/out.png"));
    CHECK_FALSE(file_exists(dir + "/out.jpg"));
}

TEST_CASE("texr --version names the commit it was built from") {
    // The commit as git tells it here (the test is built with texr, from the same tree, and
    // nothing edits it between the build and the test), or "unknown" where the source is not
    // the top of a git checkout or git is missing.
    const std::string source = TEXR_SOURCE_DIR;
    const auto git = [&](const std::string& arguments) {
        const std::string command = "git -C '" + source + "' -c 'safe.directory=" + source + "' -c log.showSignature=false " +
                                    arguments + " 2>/dev/null";
        std::string out;
        if (std::FILE* pipe = ::popen(command.c_str(), "r")) {
            char buffer[4096];
            while (const std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
            ::pclose(pipe);
        }
        return out;
    };
    char top[PATH_MAX], here[PATH_MAX];
    std::string shown_top = git("rev-parse --show-toplevel");
    if (!shown_top.empty() && shown_top.back() == '\n') shown_top.pop_back();
    std::string commit = "unknown";
    if (::realpath(shown_top.c_str(), top) && ::realpath(source.c_str(), here) && std::string(top) == here) {
        commit = git("log -1 --abbrev=12 --date=short '--format=%h of %cd'");
        if (!commit.empty() && commit.back() == '\n') commit.pop_back();
        if (!git("status --porcelain --untracked-files=no").empty()) commit += ", with uncommitted changes";
    }
    const RunResult r = run_texr("--version");
    CHECK(r.exit_code == 0);
    CHECK(r.output == "texr 0.1 (commit " + commit + ")\n");
}

TEST_CASE("help documents every option") {
    RunResult r = run_texr("--help");
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("render") != std::string::npos);
    r = run_texr("render --help");
    CHECK(r.exit_code == 0);
    for (const char* option : {"-o", "--output", "--size", "--repeat", "--threads", "--spp", "--span", "--span-tolerance", "--stats", "--help"})
        CHECK(r.output.find(option) != std::string::npos);
    r = run_texr("bench --help");
    CHECK(r.exit_code == 0);
    for (const char* option : {"filters", "spans", "threads", "scale", "--size", "--repeat", "--spp", "--threads", "--models", "--out", "--quick"})
        CHECK(r.output.find(option) != std::string::npos);
    r = run_texr("explain --help");
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("--size") != std::string::npos);
}

TEST_CASE("an empty frame is written, with a note that says why it is empty") {
    // The camera looks away from the triangle (at +z, the triangle is at z = 0 behind it).
    const std::string dir = scratch_folder("empty-frame");
    write_text(dir + "/scene.txt", "size 32 24\ncamera eye 0 0 3 target 0 0 6\ntriangle v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n");
    RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png --repeat 2");
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    CHECK(file_exists(dir + "/out.png"));
    CHECK(r.output.find("texr: note: no surface is in the frame, only the background (triangles in: 1; culled: 1,") != std::string::npos);
    // Facing the triangle: no note.
    write_text(dir + "/scene.txt", "size 32 24\ncamera eye 0 0 3\ntriangle v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n");
    r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
    CHECK(r.output.find("note:") == std::string::npos);
}

TEST_CASE("--stats and --repeat report counters and a median frame time") {
    const std::string dir = scratch_folder("stats");
    write_text(dir + "/scene.txt", good_scene);
    const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png --repeat 3 --stats");
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("median frame time") != std::string::npos);
    for (const char* stage : {"time load", "time clear", "time vertex", "time raster", "time write"}) CHECK(r.output.find(stage) != std::string::npos);
    CHECK(r.output.find("triangles in       1") != std::string::npos);
    CHECK(r.output.find("pixels shaded") != std::string::npos);
    CHECK(r.output.find("material red") != std::string::npos);
    // A texture's memory: a 256x256 8-bit image is 0.25 MiB; the triangle is
    // magnified (no mip levels) and filtered bilinearly (a decoded copy, 4 floats a texel,
    // which spans of 16 pixels or more read).
    // A second texture of the same file shares its image, counted once; a texture no
    // material uses has its texels and nothing else.
    const std::string grid = source_path("models/textures/uvgrid.png");
    write_text(dir + "/textured.txt", "size 128 96\ncamera eye 0 0 3\ntexture grid file " + grid +
                                           " filter bilinear\ntexture again file " + grid + " filter nearest\n"
                                           "texture other file " + source_path("models/textures/checker.png") +
                                           "\nmaterial m texture grid\n"
                                           "triangle material m v -1 -1 0 0 0 v 1 -1 0 0.01 0 v 0 1 0 0.005 0.01\n");
    const RunResult textured = run_texr("render " + dir + "/textured.txt -o " + dir + "/out.png --stats");
    CAPTURE(textured.output);
    CHECK(textured.output.find("texture grid         256x256 8-bit 0.25 MiB; mip levels not built; decoded copies 1.00 MiB\n") !=
          std::string::npos);
    CHECK(textured.output.find("texture again        256x256 8-bit (the image of texture grid); mip levels not built\n") !=
          std::string::npos);
    CHECK(textured.output.find("texture other        256x256 8-bit 0.25 MiB; mip levels not built; decoded copies none\n") !=
          std::string::npos);
    // The worker threads the frame used: --threads, at most one per 8 rows (24 rows: 3).
    for (const auto& [given, used] : {std::pair<int, int>{2, 2}, {5, 3}}) {
        const RunResult t = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png --stats --threads " + std::to_string(given));
        CAPTURE(t.output);
        CHECK(t.output.find("threads            " + std::to_string(used) + "  (worker threads") != std::string::npos);
    }
}

TEST_CASE("texr explain tells a pixel's u, v and derivatives as worked out by hand") {
    // A square at depth 2 filling a 90-degree view of 64x64 pixels, UV (0,0) bottom left to
    // (1,1) top right. At pixel (16, 48): u = 16.5/64, v = 1 - 48.5/64, q = 1/w = 1/2,
    // du/dx = 1/64, dv/dy = -1/64.
    const std::string dir = scratch_folder("explain");
    write_text(dir + "/scene.txt",
               "size 64 64\ncamera eye 0 0 0 target 0 0 -1 fov 90\n"
               "quad v -2 -2 -2 0 0 v 2 -2 -2 1 0 v 2 2 -2 1 1 v -2 2 -2 0 1\n");
    const RunResult r = run_texr("explain " + dir + "/scene.txt 16 48");
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("u = u'/q = 0.2578125 ") != std::string::npos);
    CHECK(r.output.find("v = v'/q = 0.2421875") != std::string::npos);
    CHECK(r.output.find("q = 1/w = 0.5") != std::string::npos);
    CHECK(r.output.find("du/dx = 0.015625 ") != std::string::npos);
    CHECK(r.output.find("dv/dy = -0.015625") != std::string::npos);
    const RunResult outside = run_texr("explain " + dir + "/scene.txt 64 0");
    CHECK(outside.exit_code == 2);
    CHECK(outside.output.find("X must be a pixel index from 0 to 63") != std::string::npos);
}

TEST_CASE("texr explain names the texels nearest and bilinear read, their fractions, and the bytes written") {
    // The square of the test above, textured by a 4 x 4 image whose top two rows are red and
    // bottom two blue (row 0 is the bottom, v = 0). At pixel (16, 32): u = 16.5/64 = 0.2578125,
    // v = 1 - 32.5/64 = 0.4921875, so u resU = 1.03125 and v resV = 1.96875.
    //  - nearest: column floor(1.03125) = 1, row floor(1.96875) = 1: blue;
    //  - bilinear: x = u resU - 1/2 = 0.53125, y = v resV - 1/2 = 1.46875: columns 0 and 1
    //    (f_u = 0.53125), rows 1 (blue) and 2 (red) (f_v = 0.46875), so the value is
    //    (0.46875, 0, 0.53125), written as sRGB 255 (1.055 x^(1/2.4) - 0.055): 182 and 193.
    const std::string dir = scratch_folder("explain-taps");
    std::string ppm = "P6\n4 4\n255\n";
    for (int row = 0; row < 4; ++row)  // from the top
        for (int column = 0; column < 4; ++column) ppm += row < 2 ? std::string("\xff\x00\x00", 3) : std::string("\x00\x00\xff", 3);
    std::ofstream(dir + "/t.ppm", std::ios::binary) << ppm;
    const auto explain = [&](const std::string& filter, const char* quad = "v -2 -2 -2 0 0 v 2 -2 -2 1 0 v 2 2 -2 1 1 v -2 2 -2 0 1") {
        write_text(dir + "/scene.txt", "size 64 64\ncamera eye 0 0 0 target 0 0 -1 fov 90\ntexture t file t.ppm filter " + filter +
                                           "\nmaterial m texture t\nquad material m " + quad + "\n");
        const RunResult r = run_texr("explain " + dir + "/scene.txt 16 32");
        CHECK(r.exit_code == 0);
        return r.output;
    };
    std::string out = explain("nearest");
    CAPTURE(out);
    CHECK(out.find("the nearest texel (resU x resV = 4 x 4): u resU = 1.0312, v resV = 1.9688;") != std::string::npos);
    CHECK(out.find("on the wrapped t_u): texel (1, 1) (row 0 is the image's bottom),\n    linear RGBA (0.00000, 0.00000, 1.00000, 1.00000)") !=
          std::string::npos);
    CHECK(out.find("sRGB bytes (0, 0, 255)") != std::string::npos);
    CHECK(out.find("linear RGBA: (0.00000, 0.00000, 1.00000, 1.00000) from 1 texel read\n") != std::string::npos);
    // The UVs times 8 (repeat): u resU = 8.25 and v resV = 15.75, column 8 and row 15 before
    // the wrap, column 0 and row 3 (red) after it: the slide's min(floor(t_u resU), resU - 1)
    // on the wrapped t_u = 0.0625, t_v = 0.9375.
    out = explain("nearest", "v -2 -2 -2 0 0 v 2 -2 -2 8 0 v 2 2 -2 8 8 v -2 2 -2 0 8");
    CAPTURE(out);
    CHECK(out.find("u resU = 8.2500, v resV = 15.7500;") != std::string::npos);
    CHECK(out.find("on the wrapped t_u): texel (0, 3) (row 0 is the image's bottom),\n    linear RGBA (1.00000, 0.00000, 0.00000, 1.00000)") !=
          std::string::npos);
    out = explain("bilinear");
    CAPTURE(out);
    CHECK(out.find("x = u resU - 1/2 = 0.5312,\n    y = v resV - 1/2 = 1.4688") != std::string::npos);
    CHECK(out.find("bilinear reads columns 0 and 1 (f_u = 0.53125), rows 1 and 2 (f_v = 0.46875)") != std::string::npos);
    CHECK(out.find("t00 (0, 1) (0.00000, 0.00000, 1.00000, 1.00000)   t10 (1, 1) (0.00000, 0.00000, 1.00000, 1.00000)") !=
          std::string::npos);
    CHECK(out.find("t01 (0, 2) (1.00000, 0.00000, 0.00000, 1.00000)   t11 (1, 2) (1.00000, 0.00000, 0.00000, 1.00000)") !=
          std::string::npos);
    CHECK(out.find("the filter's value, linear RGBA: (0.46875, 0.00000, 0.53125, 1.00000) from 4 texel reads") != std::string::npos);
    CHECK(out.find("sRGB bytes (182, 0, 193)") != std::string::npos);
}

TEST_CASE("texr explain prints lattice coordinates from 1e15 on in powers of ten") {
    // A 2 x 2 texture; v = (16 - 7.5) / 16 = 0.53125 at row 7, so y = 0.53125 x 2 - 1/2 =
    // 0.5625. With clamp, u = 1e20 at every pixel: x = 2e20 - 1/2 (the 1/2 lost), printed as
    // 2.000000e+20, not as 21 digits and 4 decimals. With repeat, u = 6e14 + 0.25 is re-based
    // to 0.25 (x = 0), and the scene's x = 1.2e15 + 0.5 - 0.5 is printed as 1.200000e+15.
    const std::string dir = scratch_folder("explain-huge-lattice");
    write_text(dir + "/t.ppm", std::string("P6\n2 2\n255\n") + std::string(12, char(128)));
    for (const auto& [wrap, u] : std::vector<std::pair<std::string, std::string>>{{"clamp", "1e20"}, {"repeat", "600000000000000.25"}}) {
        write_text(dir + "/scene.txt", "size 16 16\ncamera eye 0 0 0 target 0 0 -1 fov 90\ntexture t file t.ppm wrap " + wrap +
                                           "\nmaterial m texture t\nquad material m v -2 -2 -2 " + u + " 0 v 2 -2 -2 " + u +
                                           " 0 v 2 2 -2 " + u + " 1 v -2 2 -2 " + u + " 1\n");
        const RunResult r = run_texr("explain " + dir + "/scene.txt 8 7");
        CHECK(r.exit_code == 0);
        const std::string want = wrap == "clamp" ? "x = u resU - 1/2 = 2.000000e+20,\n    y = v resV - 1/2 = 0.5625\n"
                                                 : "x = u resU - 1/2 = 0.0000,\n    y = v resV - 1/2 = 0.5625\n    (of the re-based u and "
                                                   "v; of the scene's, x = 1.200000e+15 and y = 0.5625:";
        CAPTURE(r.output);
        CHECK(r.output.find(want) != std::string::npos);
    }
    // Nearest's u resU, and border wrap's t_u (u itself), the same way: u = 1e300 on the 2 x 2
    // texture is u resU = 2e300 and t_u = 1e300.
    for (const auto& [options, want] : std::vector<std::pair<std::string, std::string>>{
             {"filter nearest wrap clamp", "u resU = 2.000000e+300, v resV = 1.0625; column\n"},
             {"filter bilinear wrap border", "t_u = 1.000000e+300, t_v = 0.531250 (outside [0, 1]"}}) {
        write_text(dir + "/scene.txt", "size 16 16\ncamera eye 0 0 0 target 0 0 -1 fov 90\ntexture t file t.ppm " + options +
                                           "\nmaterial m texture t\n"
                                           "quad material m v -2 -2 -2 1e300 0 v 2 -2 -2 1e300 0 v 2 2 -2 1e300 1 v -2 2 -2 1e300 1\n");
        const RunResult r = run_texr("explain " + dir + "/scene.txt 8 7");
        CAPTURE(r.output);
        CHECK(r.output.find(want) != std::string::npos);
    }
}

TEST_CASE("texr explain gives u and v in the scene's coordinates when the setup re-based them by whole periods") {
    // The square of the test above with UVs offset by (100, -3), and a repeating texture: the
    // setup subtracts the whole periods 100 and -3 (each triangle's smallest u and v to
    // [0, 1)). At pixel (16, 48): u = 100 + 16.5/64 = 100.2578125, v = -3 + 15.5/64 = -2.7578125.
    const std::string dir = scratch_folder("explain-rebased");
    write_text(dir + "/t.ppm", std::string("P6\n2 2\n255\n") + std::string(6, char(0)) + std::string(6, char(255)));
    const auto explain = [&](const std::string& wrap) {
        write_text(dir + "/scene.txt",
                   "size 64 64\ncamera eye 0 0 0 target 0 0 -1 fov 90\ntexture t file t.ppm wrap " + wrap +
                       "\nmaterial m texture t\n"
                       "quad material m v -2 -2 -2 100 -3 v 2 -2 -2 101 -3 v 2 2 -2 101 -2 v -2 2 -2 100 -2\n");
        const RunResult r = run_texr("explain " + dir + "/scene.txt 16 48");
        CAPTURE(r.output);
        CHECK(r.exit_code == 0);
        return r.output;
    };
    std::string out = explain("repeat");
    CHECK(out.find("u = u'/q = 0.2578125 ") != std::string::npos);
    CHECK(out.find("v = v'/q = 0.2421875") != std::string::npos);
    CHECK(out.find("moved the triangle's u by -100 and its v by +3, whole periods") != std::string::npos);
    CHECK(out.find("In the scene's coordinates u = 100.2578125, v = -2.7578125)") != std::string::npos);
    // The lattice coordinates of the 2 x 2 texture, of both: 0.2578125 x 2 - 1/2 = 0.015625
    // and 0.2421875 x 2 - 1/2 = -0.015625; 100.2578125 x 2 - 1/2 = 200.015625 and
    // -2.7578125 x 2 - 1/2 = -6.015625.
    CHECK(out.find("x = u resU - 1/2 = 0.0156,\n    y = v resV - 1/2 = -0.0156\n") != std::string::npos);
    CHECK(out.find("of the scene's, x = 200.0156 and y = -6.0156: whole periods apart") != std::string::npos);
    // Mirror's period is 2: u loses 100, v loses -4.
    out = explain("mirror");
    CHECK(out.find("u = u'/q = 0.2578125 ") != std::string::npos);
    CHECK(out.find("v = v'/q = 1.2421875") != std::string::npos);
    CHECK(out.find("moved the triangle's u by -100 and its v by +4, whole periods") != std::string::npos);
    CHECK(out.find("coordinates u = 100.2578125, v = -2.7578125") != std::string::npos);
    // Clamp is not periodic: nothing is re-based, and nothing is said.
    out = explain("clamp");
    CHECK(out.find("u = u'/q = 100.2578125 ") != std::string::npos);
    CHECK(out.find("moved the triangle's") == std::string::npos);
    // Only v far from 0: only v is said to move.
    write_text(dir + "/scene.txt", "size 64 64\ncamera eye 0 0 0 target 0 0 -1 fov 90\ntexture t file t.ppm wrap repeat\n"
                                   "material m texture t\nquad material m v -2 -2 -2 0 -3 v 2 -2 -2 1 -3 v 2 2 -2 1 -2 v -2 2 -2 0 -2\n");
    out = run_texr("explain " + dir + "/scene.txt 16 48").output;
    CHECK(out.find("(the setup moved the triangle's v by +3, whole periods") != std::string::npos);
    CHECK(out.find("(U holds the corners' UVs after the setup moved the triangle's v by +3: step 3 says why)") != std::string::npos);
    CHECK(out.find("In the scene's coordinates u = 0.2578125, v = -2.7578125)") != std::string::npos);
    // A span mode's (u, v) that differ from u'/q, v'/q are in the same moved coordinates, and
    // are given in the scene's too: on a tilted quad (affine is wrong there), 100 more in u and
    // 3 less in v.
    write_text(dir + "/scene.txt", "size 64 64\ncamera eye 0 0 0 target 0 0 -1 fov 90\ntexture t file t.ppm wrap repeat\n"
                                   "material m texture t\nquad material m v -2 -2 -1 100 -3 v 2 -2 -3 101 -3 v 2 2 -3 101 -2 v -2 2 -1 100 -2\n");
    out = run_texr("explain " + dir + "/scene.txt 16 48 --span affine").output;
    CAPTURE(out);
    CHECK(out.find("moved the triangle's u by -100 and its v by +3, whole periods") != std::string::npos);
    const std::size_t given = out.find("--span affine gives this pixel u = "), scene_uv = out.find("those are moved as in step 3: in the scene's coordinates u = ");
    REQUIRE(given != std::string::npos);
    REQUIRE(scene_uv != std::string::npos);
    double u = 0, v = 0, su = 0, sv = 0;
    REQUIRE(std::sscanf(out.c_str() + given, "--span affine gives this pixel u = %lf, v = %lf", &u, &v) == 2);
    REQUIRE(std::sscanf(out.c_str() + scene_uv, "those are moved as in step 3: in the scene's coordinates u = %lf, v = %lf", &su, &sv) == 2);
    CHECK(u > 0.0);
    CHECK(u < 1.0);
    CHECK(su - u == doctest::Approx(100.0).epsilon(1e-9));
    CHECK(sv - v == doctest::Approx(-3.0).epsilon(1e-9));
    // Step 2's rows are of the moved UVs, and it says so.
    CHECK(out.find("(U holds the corners' UVs after the setup moved the triangle's u by -100 and its v by +3: step 3 says why)") !=
          std::string::npos);
    // The screen vertices are printed exactly: multiples of 1/256.
    for (const char* name : {"    v0 = (", "    v1 = (", "    v2 = ("}) {
        const std::size_t at = out.find(name);
        REQUIRE(at != std::string::npos);
        double x = 0, y = 0;
        REQUIRE(std::sscanf(out.c_str() + at + std::strlen(name), "%lf, %lf", &x, &y) == 2);
        CHECK(x * 256.0 == std::floor(x * 256.0));
        CHECK(y * 256.0 == std::floor(y * 256.0));
    }
}

TEST_CASE("texr explain tells border wrap's registrations apart: the slide's border colour (node), or texels beyond the edge blended (cell)") {
    // A 2 x 2 texture on a quad whose u runs from -0.5 to 1.5: the left quarter of the frame
    // lies at u < 0. With node registration (the slide's test) a pixel there is the border
    // colour; with cell registration (OpenGL's) texels beyond the edge are, and bilinear blends
    // them with the texels inside it reaches.
    const std::string dir = scratch_folder("explain-border");
    write_text(dir + "/t.ppm", std::string("P6\n2 2\n255\n") + std::string(12, char(255)));
    const auto explain = [&](const std::string& registration, int x) {
        write_text(dir + "/scene.txt", "size 64 64\ncamera eye 0 0 1 target 0 0 0 fov 90\ntexture t file t.ppm wrap border border 0 0 0 1 "
                                       "registration " + registration + "\nmaterial m texture t\n"
                                       "quad material m v -1 -1 0 -0.5 0 v 1 -1 0 1.5 0 v 1 1 0 1.5 1 v -1 1 0 -0.5 1\n");
        const RunResult r = run_texr("explain " + dir + "/scene.txt " + std::to_string(x) + " 32");
        CAPTURE(r.output);
        CHECK(r.exit_code == 0);
        return r.output;
    };
    // Pixel 4: u = -0.5 + 2 (4.5 / 64) = -0.359, far outside: black either way. Pixel 15:
    // u = -0.016, within half a texel (1/4) of the edge: black for node, half grey for cell.
    std::string out = explain("node", 15);
    CHECK(out.find("(outside [0, 1]: the border colour)\n") != std::string::npos);
    CHECK(out.find("the filter's value, linear RGBA: (0.00000, 0.00000, 0.00000, 1.00000)") != std::string::npos);
    out = explain("cell", 15);
    CHECK(out.find("(outside [0, 1]: texels beyond the image's edge are the border colour,\n"
                   "    which the filter blends with the texels inside it reaches, as OpenGL does)\n") != std::string::npos);
    CHECK(out.find("(outside [0, 1]: the border colour)") == std::string::npos);
    // x = u resU - 1/2 = -0.531: 0.469 of texel 0 (white) and 0.531 of the border (black).
    CHECK(out.find("the filter's value, linear RGBA: (0.46875, 0.46875, 0.46875, 1.00000)") != std::string::npos);
    CHECK(explain("cell", 4).find("the filter's value, linear RGBA: (0.00000, 0.00000, 0.00000, 1.00000)") != std::string::npos);
    // Nearest: the lattice line is bilinear's, and says which one nearest takes.
    CHECK(out.find("nearest takes") == std::string::npos);
    const std::string scene = read_file(dir + "/scene.txt");
    write_text(dir + "/scene.txt", scene.substr(0, scene.find(" registration")) + " filter nearest" + scene.substr(scene.find(" registration")));
    out = run_texr("explain " + dir + "/scene.txt 15 32").output;
    CAPTURE(out);
    CHECK(out.find("    (the lattice that bilinear reads; nearest takes floor(u resU), below)\n") != std::string::npos);
    CHECK(out.find("u resU = -0.0312") != std::string::npos);  // (floor: texel -1, the border)
    CHECK(out.find("(outside [0, 1]: texels beyond the image's edge are the border\n    colour, as OpenGL has it)\n") != std::string::npos);
}

TEST_CASE("texr explain shades the pixel step by step: texture value, vertex colour, normal, each light, the background") {
    // A floor lit at 45 degrees: N = (0, 1, 0) from normals (0, 2, 0), L = (0, 1, 1) / sqrt 2,
    // N . L = 0.70711; ambient 0.5 is linear 0.21404 (the sRGB curve), so the irradiance is
    // 0.92115. Vertex colours 0.5 0.5 0.5 are linear 0.21404 too. The texture is a 2x2
    // white image: the filter's value is 1. Colour: 1 x 1 x 0.21404 x 0.92115 = 0.19716.
    const std::string dir = scratch_folder("explain-shading");
    write_text(dir + "/white.ppm", std::string("P6\n2 2\n255\n") + std::string(12, char(255)));
    const auto scene_with = [](const std::string& light) {
        return "size 32 32\ncamera eye 0 3 0 target 0 0 0 up 0 0 -1 fov 90\nbackground 1 0 0\nambient 0.5 0.5 0.5\n" + light +
               "\ntexture white file white.ppm\nmaterial m texture white lighting lambert vertex_colors on\n"
               "quad material m v -2 0 2 0 0 n 0 2 0 c 0.5 0.5 0.5 v 2 0 2 1 0 n 0 2 0 c 0.5 0.5 0.5 "
               "v 2 0 -2 1 1 n 0 2 0 c 0.5 0.5 0.5 v -2 0 -2 0 1 n 0 2 0 c 0.5 0.5 0.5\n";
    };
    write_text(dir + "/scene.txt", scene_with("light directional 0 -1 -1"));
    RunResult r = run_texr("explain " + dir + "/scene.txt 16 16");
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("the filter's value, linear RGBA: (1.00000, 1.00000, 1.00000, 1.00000) from 4 texel reads") != std::string::npos);
    CHECK(r.output.find("linear colour = material colour x texture x vertex colour x irradiance") != std::string::npos);
    CHECK(r.output.find("x vertex colour (0.21404, 0.21404, 0.21404)") != std::string::npos);
    CHECK(r.output.find("N = (0.00000, 1.00000, 0.00000)") != std::string::npos);
    CHECK(r.output.find("+ light 0 (directional, L = (0.00000, 0.70711, 0.70711)) (1.00000, 1.00000, 1.00000) x max(0, N . L) = x 0.70711") !=
          std::string::npos);
    CHECK(r.output.find("x irradiance    (0.92115, 0.92115, 0.92115)") != std::string::npos);
    CHECK(r.output.find("    = (0.19716, 0.19716, 0.19716)") != std::string::npos);
    CHECK(r.output.find("Written: depth") != std::string::npos);
    CHECK(r.output.find("linear colour (0.19716, 0.19716, 0.19716)") != std::string::npos);
    // A point light straight above the point pixel (16, 16) sees: the ray through its centre,
    // (0, 3, 0) + 3 (1/32, -1, 1/32), meets the floor at (0.09375, 0, 0.09375); with the
    // light at height 1000 above it, L = (0, 1, 0) to 5 decimals and N . L = 1.
    write_text(dir + "/point.txt", scene_with("light point 0.09375 1000 0.09375"));
    r = run_texr("explain " + dir + "/point.txt 16 16");
    CAPTURE(r.output);
    CHECK(r.output.find("+ light 0 (point, L = (0.00000, 1.00000, 0.00000)) (1.00000, 1.00000, 1.00000) x max(0, N . L) = x 1.00000") !=
          std::string::npos);
    CHECK(r.output.find("x irradiance    (1.21404, 1.21404, 1.21404)") != std::string::npos);
    // A corner pixel the floor (x, z within 2 of the centre, a 3 high camera at 90 degrees)
    // does not reach: the background, linear (1, 0, 0).
    r = run_texr("explain " + dir + "/scene.txt 0 0");
    CHECK(r.output.find("the background colour shows, linear (1.00000, 0.00000, 0.00000)") != std::string::npos);
}

TEST_CASE("texr explain on an OBJ without texture coordinates: the vertex colours' blend, and why M^-1 has no u', v' rows") {
    // The camera at z = 3 (fov 60, 64x64) sees the corners (-1, -1), (1, -1), (0, 1) at
    // pixels (13.5248, 50.4752), (50.4752, 50.4752), (32, 13.5248): snapped to 1/256,
    // 13.5234375 and 50.4765625. At the centre of pixel (34, 30) the corners' weights are
    // w2 = (50.4765625 - 30.5) / 36.953125 = 0.54059, and across the row, between
    // x = 23.5117 and 40.4883, w1 = (1 - w2) (34.5 - 23.5117) / 16.9766 = 0.29736,
    // w0 = 0.16205: with red, green and blue corners, the colour itself.
    const std::string dir = scratch_folder("explain-obj-colours");
    write_text(dir + "/tri.obj", "v -1 -1 0 1 0 0\nv 1 -1 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n");
    write_text(dir + "/scene.txt", "size 64 64\ncamera eye 0 0 3 target 0 0 0 fov 60\nmaterial paint vertex_colors on\n"
                                   "mesh tri.obj material paint\ntriangle material paint v 0.6 -0.9 1 0 0 v 0.9 -0.9 1 0.5 0 v 0.75 -0.6 1 1 0\n");
    RunResult r = run_texr("explain " + dir + "/scene.txt 34 30");
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("x vertex colour (0.16205, 0.29736, 0.54059)") != std::string::npos);
    CHECK(r.output.find("every corner's u, v is 0, as in a mesh without texture coordinates") != std::string::npos);
    CHECK(r.output.find("collinear") == std::string::npos);
    // A small triangle beside it (z = 1, around pixel (52, 54)) whose UVs lie on a line
    // (v = 0): that one is told instead.
    r = run_texr("explain " + dir + "/scene.txt 52 54");
    CAPTURE(r.output);
    CHECK(r.output.find("object 1") != std::string::npos);
    CHECK(r.output.find("the UVs are collinear") != std::string::npos);
    CHECK(r.output.find("without texture coordinates") == std::string::npos);
}

TEST_CASE("texr explain names the mip levels each filter reads, with lambda, probes and ellipse worked out by hand") {
    // The square of the test above with the 1024^2 detail texture over u, v in [0, 0.375]:
    // 384 texels over 64 pixels, 6 texels per pixel along x and y, lambda = log2 6 = 2.5850.
    // Squeezed to v in [0, 0.09375], 1.5 texels per pixel along y: the footprint ellipse has
    // axes 6 and 1.5, so anisotropic takes 6 / 1.5 = 4 probes at log2(6 / 4) = 0.5850 and EWA
    // reads lambda = log2 1.5 = 0.5850; with max_anisotropy 2, 2 probes at log2 3 = 1.5850 and
    // EWA's minor axis stretched to 6 / 2 = 3, log2 3 = 1.5850.
    const std::string dir = scratch_folder("explain-levels");
    const auto explain = [&](const std::string& filter, double v_top, const std::string& options = "") {
        write_text(dir + "/scene.txt", "size 64 64\ncamera eye 0 0 0 target 0 0 -1 fov 90\ntexture t file " +
                                           source_path("models/textures/detail.png") + " filter " + filter + " " + options +
                                           "\nmaterial m texture t\nquad material m v -2 -2 -2 0 0 v 2 -2 -2 0.375 0 v 2 2 -2 0.375 " +
                                           std::to_string(v_top) + " v -2 2 -2 0 " + std::to_string(v_top) + "\n");
        const RunResult r = run_texr("explain " + dir + "/scene.txt 16 48");
        CHECK(r.exit_code == 0);
        return r.output;
    };
    std::string out = explain("bilinear", 0.375);
    CHECK(out.find("lambda = log2(max of the two) = 2.5850 (minified)") != std::string::npos);
    CHECK(out.find("the filter reads the base level only, without mip levels: minified without prefiltering") != std::string::npos);
    out = explain("nearest_mip_nearest", 0.375);  // ceil(2.585 + 1/2) - 1 = 3
    CHECK(out.find("coarsest): level 3 (128x128)") != std::string::npos);
    out = explain("trilinear", 0.375);
    CHECK(out.find("bilinear on level 2 (256x256) and level 3 (128x128), blended 0.5850 of the way") != std::string::npos);
    out = explain("anisotropic", 0.09375);
    CAPTURE(out);
    CHECK(out.find("major 6, minor 1.5 texels") != std::string::npos);
    CHECK(out.find("4 trilinear probe(s)") != std::string::npos);
    CHECK(out.find("lambda = log2(major / 4) = 0.5850: bilinear on level 0 (1024x1024) and level 1 (512x512)") != std::string::npos);
    out = explain("anisotropic", 0.09375, "max_anisotropy 2");
    CHECK(out.find("2 trilinear probe(s)") != std::string::npos);
    CHECK(out.find("lambda = log2(major / 2) = 1.5850: bilinear on level 1 (512x512) and level 2 (256x256)") != std::string::npos);
    out = explain("ewa", 0.09375);
    CHECK(out.find("lambda = max(0, log2(minor)) = 0.5850: the Gaussian-weighted mean over the ellipse on level 0 (1024x1024) and "
                   "level 1 (512x512), blended 0.5850") != std::string::npos);
    out = explain("ewa", 0.09375, "max_anisotropy 2");
    CHECK(out.find("the minor axis stretched to major / max_anisotropy = 3 texels") != std::string::npos);
    CHECK(out.find("lambda = max(0, log2(minor)) = 1.5850: the Gaussian-weighted mean over the ellipse on level 1 (512x512) and "
                   "level 2") != std::string::npos);
    // Magnified, 0.5 texels per pixel: lambda = -1, the base level; EWA's level is clamped at 0.
    out = [&] {
        write_text(dir + "/scene.txt", "size 64 64\ncamera eye 0 0 0 target 0 0 -1 fov 90\ntexture t file " +
                                           source_path("models/textures/detail.png") +
                                           " filter ewa\nmaterial m texture t\nquad material m v -2 -2 -2 0 0 v 2 -2 -2 0.03125 0 "
                                           "v 2 2 -2 0.03125 0.03125 v -2 2 -2 0 0.03125\n");
        return run_texr("explain " + dir + "/scene.txt 16 48").output;
    }();
    CHECK(out.find("lambda = log2(max of the two) = -1.0000 (magnified or 1:1)") != std::string::npos);
    CHECK(out.find("major 0.5, minor 0.5 texels") != std::string::npos);
    CHECK(out.find("lambda = max(0, log2(minor)) = 0.0000: the Gaussian-weighted mean over the ellipse on level 0 (1024x1024)\n") !=
          std::string::npos);
}

TEST_CASE("texr explain on a sheared footprint over a 256x64 texture, at the coarsest level, and under an affine span mode") {
    const std::string dir = scratch_folder("explain-sheared");
    // A 256 x 64 texture (any texels) on the 64x64 square of the tests above, with UVs
    // (0, 0), (1.5, 0), (2.25, 1.5), (0.75, 1.5) at the top left, top right, bottom right and
    // bottom left pixel corners: one pixel right moves (6, 0) texels, one down (3, 1.5). Worked
    // by hand: J J^T = [[45, 4.5], [4.5, 2.25]], eigenvalues (47.25 +- sqrt(1908.5625)) / 2, so
    // major = 6.7430, minor = |det J| / major = 9 / 6.7430 = 1.3347, eccentricity 5.05.
    // Trilinear: lambda = log2 max(6, sqrt(11.25)) = log2 6 = 2.5850, levels 2 (64x16), 3 (32x8).
    // Anisotropic: 6 probes at log2(6.7430 / 6) = 0.1684; max_anisotropy 2: 2 at log2(3.3715) =
    // 1.7534. EWA: log2(1.3347) = 0.4165; max_anisotropy 2: minor 3.3715, 1.7534.
    std::string ppm = "P6\n256 64\n255\n";
    for (int k = 0; k < 256 * 64 * 3; ++k) ppm += char(k * 7 % 256);
    write_text(dir + "/t.ppm", ppm);
    const auto explain = [&](const std::string& texture, const std::string& uvs, const std::string& where = "16 48",
                             const std::string& options = "") {
        write_text(dir + "/scene.txt", "size 64 64\ncamera eye 0 0 0 target 0 0 -1 fov 90\ntexture t file " + texture +
                                           "\nmaterial m texture t\nquad material m " + uvs + "\n");
        const RunResult r = run_texr("explain " + dir + "/scene.txt " + where + options);
        CHECK(r.exit_code == 0);
        return r.output;
    };
    const std::string sheared = "v -2 -2 -2 0.75 1.5 v 2 -2 -2 2.25 1.5 v 2 2 -2 1.5 0 v -2 2 -2 0 0";
    std::string out = explain("t.ppm filter trilinear", sheared);
    CAPTURE(out);
    CHECK(out.find("footprint: |d(u,v)/dx| = 6 texels, |d(u,v)/dy| = 3.354 texels") != std::string::npos);
    CHECK(out.find("bilinear on level 2 (64x16) and level 3 (32x8), blended 0.5850") != std::string::npos);
    out = explain("t.ppm filter anisotropic", sheared);
    CHECK(out.find("major 6.743, minor 1.335 texels") != std::string::npos);
    CHECK(out.find("6 trilinear probe(s)") != std::string::npos);
    CHECK(out.find("lambda = log2(major / 6) = 0.1684: bilinear on level 0 (256x64) and level 1 (128x32), blended 0.1684") !=
          std::string::npos);
    out = explain("t.ppm filter anisotropic max_anisotropy 2", sheared);
    CHECK(out.find("lambda = log2(major / 2) = 1.7534: bilinear on level 1 (128x32) and level 2 (64x16), blended 0.7534") !=
          std::string::npos);
    out = explain("t.ppm filter ewa", sheared);
    CHECK(out.find("lambda = max(0, log2(minor)) = 0.4165: the Gaussian-weighted mean over the ellipse on level 0 (256x64) and "
                   "level 1 (128x32), blended 0.4165") != std::string::npos);
    out = explain("t.ppm filter ewa max_anisotropy 2", sheared);
    CHECK(out.find("the minor axis stretched to major / max_anisotropy = 3.372 texels") != std::string::npos);
    CHECK(out.find("= 1.7534: the Gaussian-weighted mean over the ellipse on level 1 (128x32) and level 2 (64x16), blended 0.7534") !=
          std::string::npos);
    // 90 texels per pixel along v, 360 along u (UVs 0..90 over 64 pixels, both axes): EWA's
    // minor axis is 90 texels, lambda = log2(90) = 6.4919, levels 6 (4x1) and 7 (2x1), each one
    // texel across v, but the ellipse there only a few texels across v: summed cell by cell,
    // with no line about it. Likewise levels 7 (2x1) and 8 (1x1) at 181 texels per pixel.
    out = explain("t.ppm filter ewa", "v -2 -2 -2 0 0 v 2 -2 -2 90 0 v 2 2 -2 90 90 v -2 2 -2 0 90");
    CHECK(out.find("= 6.4919: the Gaussian-weighted mean over the ellipse on level 6 (4x1) and level 7 (2x1)") != std::string::npos);
    CHECK(out.find("is one texel across") == std::string::npos);
    out = explain("t.ppm filter ewa wrap_v border", "v -2 -2 -2 0 0 v 2 -2 -2 181 0 v 2 2 -2 181 181 v -2 2 -2 0 181");
    CHECK(out.find("= 7.4998: the Gaussian-weighted mean over the ellipse on level 7 (2x1) and level 8 (1x1)") != std::string::npos);
    CHECK(out.find("is one texel across") == std::string::npos);
    // A 1x64 texture under 64 image widths per pixel along u (UVs 0..4096) and 1 texel along v:
    // EWA's minor axis stretched to 64 / 16 = 4 texels, lambda = 2 exactly, level 2 (1x16)
    // alone, the ellipse about 90 cells across u there: summed row by row (ewa.h). At 6000
    // widths per pixel, lambda = log2(6000 / 1024) = 2.5507, levels 2 and 3 (1x8). The same
    // texture turned (64x1, UVs along v): column by column.
    std::string thin = "P6\n1 64\n255\n";
    for (int k = 0; k < 64 * 3; ++k) thin += char(k * 5 % 256);
    write_text(dir + "/thin.ppm", thin);
    write_text(dir + "/wide.ppm", "P6\n64 1\n255\n" + thin.substr(std::string("P6\n1 64\n255\n").size()));
    const std::string along_u = "v -2 -2 -2 0 0 v 2 -2 -2 4096 0 v 2 2 -2 4096 1 v -2 2 -2 0 1";
    const std::string by_rows = "    level 2 is one texel across u, and the ellipse's middle row 64 cells or more: summed\n    row by row along v, ";
    out = explain("thin.ppm filter ewa", along_u);
    CHECK(out.find("= 2.0000: the Gaussian-weighted mean over the ellipse on level 2 (1x16)\n") != std::string::npos);
    CHECK(out.find(by_rows + "each row's texel weighted by its cells' weights together\n") != std::string::npos);
    CHECK(out.find("    level 3 is") == std::string::npos);
    out = explain("thin.ppm filter ewa wrap_u border", along_u);
    CHECK(out.find(by_rows + "each row's one texel beside the border (u wraps to the border)\n") != std::string::npos);
    out = explain("thin.ppm filter ewa", "v -2 -2 -2 0 0 v 2 -2 -2 6000 0 v 2 2 -2 6000 1 v -2 2 -2 0 1");
    CHECK(out.find("= 2.5507: the Gaussian-weighted mean over the ellipse on level 2 (1x16) and level 3 (1x8)") != std::string::npos);
    CHECK(out.find("    level 3 is one texel across u, and the ellipse's middle row 64 cells or more: summed\n") != std::string::npos);
    // A 2x64 texture under 55 image widths per pixel along u (UVs 0..3520: 110 base texels)
    // and 1 texel along v, max anisotropy 64: the minor axis stretched to 110 / 64 = 1.72,
    // lambda = 0.7814, levels 0 (2x64: summed cell by cell) and 1 (1x32, the ellipse about 77
    // cells across u: by rows).
    std::string narrow = "P6\n2 64\n255\n";
    for (int k = 0; k < 2 * 64 * 3; ++k) narrow += char(k * 3 % 256);
    write_text(dir + "/narrow.ppm", narrow);
    out = explain("narrow.ppm filter ewa max_anisotropy 64", "v -2 -2 -2 0 0 v 2 -2 -2 3520 0 v 2 2 -2 3520 1 v -2 2 -2 0 1");
    CHECK(out.find("= 0.7814: the Gaussian-weighted mean over the ellipse on level 0 (2x64) and level 1 (1x32)") != std::string::npos);
    CHECK(out.find("    level 1 is one texel across u, and the ellipse's middle row 64 cells or more: summed\n") != std::string::npos);
    CHECK(out.find("    level 0 is") == std::string::npos);
    out = explain("wide.ppm filter ewa wrap_v border", "v -2 -2 -2 0 0 v 2 -2 -2 1 0 v 2 2 -2 1 4096 v -2 2 -2 0 4096");
    CHECK(out.find("= 2.0000: the Gaussian-weighted mean over the ellipse on level 2 (16x1)\n") != std::string::npos);
    CHECK(out.find("    level 2 is one texel across v, and the ellipse's middle row 64 cells or more: summed\n    column by column along u, "
                   "each column's one texel beside the border (v wraps to the border)\n") != std::string::npos);

    // 1024 texels per pixel on the 1024^2 texture (UVs 0..64): lambda = 10, the 1x1 level.
    const std::string detail = source_path("models/textures/detail.png");
    const std::string huge = "v -2 -2 -2 0 0 v 2 -2 -2 64 0 v 2 2 -2 64 64 v -2 2 -2 0 64";
    out = explain(detail + " filter trilinear", huge);
    CHECK(out.find("lambda = log2(max of the two) = 10.0000 (minified)") != std::string::npos);
    CHECK(out.find("trilinear: bilinear on level 10 (1x1), the coarsest") != std::string::npos);
    out = explain(detail + " filter ewa", huge);
    CHECK(out.find("at or beyond the coarsest level (the ellipse would cover the image): bilinear on level 10 (1x1)") != std::string::npos);
    // 2 texels per pixel (UVs 0..0.125): lambda = 1 exactly. Trilinear reads levels 1 and 2
    // (the second with weight 0); EWA reads level 1 alone.
    const std::string two = "v -2 -2 -2 0 0 v 2 -2 -2 0.125 0 v 2 2 -2 0.125 0.125 v -2 2 -2 0 0.125";
    out = explain(detail + " filter trilinear", two);
    CHECK(out.find("trilinear: bilinear on level 1 (512x512) and level 2 (256x256), blended 0.0000") != std::string::npos);
    out = explain(detail + " filter ewa", two);
    CHECK(out.find("= 1.0000: the Gaussian-weighted mean over the ellipse on level 1 (512x512)\n") != std::string::npos);

    // A square tilted away, under affine16: the span mode's (u, v) are not u'/q, v'/q, and the
    // footprint the lookup uses is taken there. The level of detail printed must be the one
    // of the derivatives printed with them: lambda = log2 of the longer footprint side.
    write_text(dir + "/tilted.txt", "size 64 48\ncamera eye 0 0 3 target 0 0 0 up 0 1 0 fov 45\ntexture t file " + detail +
                                        " filter trilinear\nmaterial m texture t\nquad material m v -1 -1 0 0 0 v 1 -1 0 4 0 "
                                        "v 1 1 0 4 4 v -1 1 0 0 4 rotate -75 1 0 0 rotate 30 0 0 1 scale 2\n");
    RunResult r = run_texr("explain " + dir + "/tilted.txt 56 8 --span affine16");
    CHECK(r.exit_code == 0);
    // Step 3 names the span mode that ran (it named the incremental walk under every mode).
    CHECK(r.output.find("The span walk (--span affine16) divides at the ends of sub-spans of 16 pixels") != std::string::npos);
    CHECK(r.output.find("--span incremental") == std::string::npos);
    const std::size_t at = r.output.find("the lookup below reads them, with du/dx = ");
    REQUIRE(at != std::string::npos);
    double dudx = 0, dvdx = 0, dudy = 0, dvdy = 0, lambda = 0;
    REQUIRE(std::sscanf(r.output.c_str() + at, "the lookup below reads them, with du/dx = %lf dv/dx = %lf du/dy = %lf dv/dy = %lf", &dudx,
                        &dvdx, &dudy, &dvdy) == 4);
    const std::size_t lod = r.output.find("level of detail lambda = log2(max of the two) = ");
    REQUIRE(lod != std::string::npos);
    REQUIRE(std::sscanf(r.output.c_str() + lod, "level of detail lambda = log2(max of the two) = %lf", &lambda) == 1);
    const double side = std::max(std::hypot(1024 * dudx, 1024 * dvdx), std::hypot(1024 * dudy, 1024 * dvdy));
    CHECK(lambda == doctest::Approx(std::log2(side)).epsilon(1e-4));
    // And those derivatives are the quotient rule's at the span mode's (u, v): du/dx =
    // (du'/dx - u dq/dx) / q with the rows of M^-1 (section 2) and q at the centre (section 3).
    double row[3][3], q = 0.0, u = 0.0, v = 0.0;
    const char* const names[3] = {"    u' [", "    v' [", "    q  ["};
    for (int k = 0; k < 3; ++k) {
        const std::size_t line = r.output.find(names[k]);
        REQUIRE(line != std::string::npos);
        REQUIRE(std::sscanf(r.output.c_str() + line + std::strlen(names[k]), "%lf %lf %lf", &row[k][0], &row[k][1], &row[k][2]) == 3);
    }
    const std::size_t at_q = r.output.find("q = 1/w = "), at_uv = r.output.find("--span affine16 gives this pixel u = ");
    REQUIRE(at_q != std::string::npos);
    REQUIRE(at_uv != std::string::npos);
    REQUIRE(std::sscanf(r.output.c_str() + at_q, "q = 1/w = %lf", &q) == 1);
    REQUIRE(std::sscanf(r.output.c_str() + at_uv, "--span affine16 gives this pixel u = %lf, v = %lf", &u, &v) == 2);
    CHECK(dudx == doctest::Approx((row[0][0] - u * row[2][0]) / q).epsilon(1e-4));
    CHECK(dvdx == doctest::Approx((row[1][0] - v * row[2][0]) / q).epsilon(1e-4));
    CHECK(dudy == doctest::Approx((row[0][1] - u * row[2][1]) / q).epsilon(1e-4));
    CHECK(dvdy == doctest::Approx((row[1][1] - v * row[2][1]) / q).epsilon(1e-4));
    // render's --span-tolerance is taken too.
    CHECK(run_texr("explain " + dir + "/tilted.txt 56 8 --span adaptive --span-tolerance 0.5").exit_code == 0);
    // The exact mode reads u'/q, v'/q: no such line.
    r = run_texr("explain " + dir + "/tilted.txt 56 8 --span exact");
    CHECK(r.output.find("the lookup below reads them") == std::string::npos);
    CHECK(r.output.find("The span walk (--span exact) divides u' and v' by q at every pixel") != std::string::npos);
    r = run_texr("explain " + dir + "/tilted.txt 56 8");
    CHECK(r.output.find("The span walk (--span incremental, the default) steps u', v' and q") != std::string::npos);
}

TEST_CASE("more command-line and scene mistakes: empty -o, padded --size, a folder, a comment ending in a backslash") {
    const std::string dir = scratch_folder("more");
    write_text(dir + "/scene.txt", good_scene);
    CHECK(run_texr("render " + dir + "/scene.txt -o ''").exit_code == 2);
    CHECK(run_texr("render " + dir + "/scene.txt --size ' 8x8' -o " + dir + "/a.png").exit_code == 2);
    CHECK(run_texr("render " + dir + "/scene.txt --size +8x8 -o " + dir + "/a.png").exit_code == 2);
    RunResult r = run_texr("render " + dir + " -o " + dir + "/a.png");
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("is a folder, not a scene file") != std::string::npos);
    // A '\\' at the end of a comment does not swallow the next line.
    write_text(dir + "/comment.txt",
               "material red color 1 0 0  # a note ending in a backslash \\\n"
               "triangle material red v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n");  // would be swallowed
    r = run_texr("render " + dir + "/comment.txt -o " + dir + "/c.png");
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
}

TEST_CASE("an OBJ usemtl name picks the scene material of that name, with or without a .mtl file") {
    const std::string dir = scratch_folder("usemtl");
    write_text(dir + "/t.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nv 1 1 0\nusemtl red\nf 1 2 3\nusemtl blue\nf 2 4 3\n");
    write_text(dir + "/scene.txt", "size 8 8\ncamera eye 0 0 3\nmaterial red color 1 0 0\nmaterial blue color 0 0 1\nmesh t.obj\n");
    // Pixel (2, 5) lies in the first triangle (lower left), pixel (5, 2) in the second.
    CHECK(explained_material(dir, 2, 5) == "red");
    CHECK(explained_material(dir, 5, 2) == "blue");
    // A usemtl line without a name (spaces, a tab, CR) leaves the material in force.
    write_text(dir + "/t.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nv 1 1 0\nusemtl red\nf 1 2 3\nusemtl \t \r\nf 2 4 3\n");
    CHECK(explained_material(dir, 5, 2) == "red");
}

TEST_CASE("a missing map_Kd image names the .mtl material, with the scene line once") {
    const std::string dir = scratch_folder("mapkd");
    write_text(dir + "/t.obj", "mtllib t.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl paint\nf 1/1 2/2 3/3\n");
    write_text(dir + "/t.mtl", "newmtl paint\nKd 1 1 1\nmap_Kd missing.png\n");
    write_text(dir + "/scene.txt", "camera eye 0 0 3\nmesh t.obj\n");
    const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("scene.txt:2: OBJ material 'paint' (map_Kd in " + dir + "/t.mtl): ") != std::string::npos);
    CHECK(r.output.find("missing.png: cannot open image file") != std::string::npos);
    CHECK(r.output.find("scene.txt:2: texr") == std::string::npos);
    CHECK(r.output.find("scene.txt:2:", r.output.find("scene.txt:2:") + 1) == std::string::npos);  // once
}

TEST_CASE("a map_Kd image is found from its .mtl file's folder, which may differ from the OBJ's") {
    // sub/x.obj reads mtl/x.mtl (from the OBJ's folder), whose map_Kd names a 1x1 red image
    // beside the .mtl. A red image of the same name beside the OBJ would be found otherwise:
    // there a green one stands in its way.
    const std::string dir = scratch_folder("mtl-folder");
    REQUIRE(std::system(("mkdir -p '" + dir + "/sub/mtl'").c_str()) == 0);
    write_text(dir + "/sub/x.obj", "mtllib mtl/x.mtl\nusemtl m\nv -9 -9 0\nv 9 -9 0\nv 0 9 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n");
    write_text(dir + "/sub/mtl/x.mtl", "newmtl m\nKd 1 1 1\nmap_Kd t.ppm\n");
    write_text(dir + "/sub/mtl/t.ppm", std::string("P6\n1 1\n255\n") + char(255) + char(0) + char(0));
    write_text(dir + "/sub/t.ppm", std::string("P6\n1 1\n255\n") + char(0) + char(255) + char(0));
    write_text(dir + "/scene.txt", "size 4 4\ncamera eye 0 0 3\nmesh sub/x.obj\n");
    RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.ppm");
    CAPTURE(r.output);
    REQUIRE(r.exit_code == 0);
    // The triangle covers the whole 4x4 frame; a .mtl material is unlit: Kd 1 times red.
    const std::string frame = read_file(dir + "/out.ppm");
    std::string red;
    for (int k = 0; k < 16; ++k) red += std::string{char(255), char(0), char(0)};
    CHECK(frame == "P6\n4 4\n255\n" + red);
    // Missing there, it is named there, with the .mtl file.
    std::remove((dir + "/sub/mtl/t.ppm").c_str());
    r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.ppm");
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("scene.txt:3: OBJ material 'm' (map_Kd in " + dir + "/sub/mtl/x.mtl): " + dir + "/sub/mtl/t.ppm: cannot open image file") !=
          std::string::npos);
}

TEST_CASE("a missing .mtl file is refused at its mtllib line, but one of several names is enough") {
    const std::string dir = scratch_folder("mtllib-missing");
    write_text(dir + "/scene.txt", "camera eye 0 0 3\nmesh t.obj\n");
    const std::string faces = "\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nusemtl paint\nf 1 2 3\n";
    write_text(dir + "/t.obj", "# made by hand\nmtllib nosuch.mtl" + faces);
    const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output == "texr: " + dir + "/scene.txt:2: " + dir + "/t.obj:2: mtllib: cannot open " + dir + "/nosuch.mtl\n");
    CHECK_FALSE(file_exists(dir + "/out.png"));
    write_text(dir + "/t.mtl", "newmtl paint\nKd 0 1 0\n");
    write_text(dir + "/t.obj", "mtllib nosuch.mtl t.mtl" + faces);
    CHECK(run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png").exit_code == 0);
    // A name with a space, written with '\\ ' (as tinyobjloader reads it).
    write_text(dir + "/my paint.mtl", "newmtl paint\nKd 0 1 0\n");
    write_text(dir + "/t.obj", "mtllib my\\ paint.mtl" + faces);
    const RunResult explained = run_texr("explain " + dir + "/scene.txt 320 240");
    CAPTURE(explained.output);
    CHECK(explained.output.find("material colour (0.00000, 1.00000, 0.00000)") != std::string::npos);  // its Kd
}

TEST_CASE("a scene file named as its own mesh is refused at the mesh line") {
    const std::string dir = scratch_folder("mesh-self");
    write_text(dir + "/scene.txt", "camera eye 0 0 3\nmesh scene.txt\n");
    const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("scene.txt:2: " + dir + "/scene.txt: ") != std::string::npos);
}

TEST_CASE("a .mtl Kd that is not 3 numbers (or 1) from 0 to 10000 is refused at its .mtl line, and nothing is written") {
    // tinyobjloader reads a word that is not a number as 0 and 'Kd 0.5' as (0.5, 0, 0).
    const std::string dir = scratch_folder("kd");
    write_text(dir + "/t.obj", "mtllib t.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nusemtl paint\nf 1 2 3\n");
    write_text(dir + "/scene.txt", "camera eye 0 0 3\nmesh t.obj\n");
    struct Case {
        std::string kd, message;
    };
    const std::string out_of_range = "Kd needs numbers from 0 to 10000, got ";
    for (const Case& k : {Case{"-0.5 0 0", out_of_range + "'-0.5'"}, Case{"0.2 1e30 0.2", out_of_range + "'1e30'"},
                          Case{"0 0 10001", out_of_range + "'10001'"}, Case{"nan 0.5 0.5", out_of_range + "'nan'"},
                          Case{"1 x 1", out_of_range + "'x'"}, Case{"-1", out_of_range + "'-1'"}, Case{"x", out_of_range + "'x'"},
                          Case{"spectral paint.rfl", out_of_range + "'spectral'"}, Case{"xyz 0.5 0.5 0.5", out_of_range + "'xyz'"},
                          // the bad word is named however long the line
                          Case{"0.123456789012345678 0.123456789012345678 0.123456789012345678 x", out_of_range + "'x'"},
                          Case{"0.5 0.5", "Kd needs 3 numbers (or 1, a grey), got 2"},
                          Case{"0.1 0.2 0.3 0.4", "Kd needs 3 numbers (or 1, a grey), got 4"}, Case{"", "Kd needs 3 numbers (or 1, a grey), got 0"}}) {
        write_text(dir + "/t.mtl", "# paint\nnewmtl paint\n  Kd " + k.kd + "\n");
        std::remove((dir + "/out.png").c_str());
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CAPTURE(r.output);
        CHECK(r.exit_code == 1);
        CHECK(r.output == "texr: " + dir + "/scene.txt:2: " + dir + "/t.mtl:3: " + k.message + "\n");
        CHECK(!file_exists(dir + "/out.png"));
    }
    // The ends of the range render.
    write_text(dir + "/t.mtl", "newmtl paint\nKd 0 10000 1\n");
    CHECK(run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png").exit_code == 0);
    // Every .mtl tinyobjloader reads is checked: lines ended by CR alone (as it splits them),
    // and a second file on a line whose first an earlier mtllib line loaded (it skips that one).
    write_text(dir + "/t.mtl", "newmtl paint\rKd 0.5 0\r");
    RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
    CHECK(r.output == "texr: " + dir + "/scene.txt:2: " + dir + "/t.mtl:2: Kd needs 3 numbers (or 1, a grey), got 2\n");
    write_text(dir + "/t.mtl", "newmtl paint\nKd 0 1 0\n");
    write_text(dir + "/b.mtl", "newmtl paint\nKd 0.5 0\n");
    write_text(dir + "/t.obj", "mtllib t.mtl\nmtllib t.mtl b.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nusemtl paint\nf 1 2 3\n");
    r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
    CHECK(r.output == "texr: " + dir + "/scene.txt:2: " + dir + "/b.mtl:2: Kd needs 3 numbers (or 1, a grey), got 2\n");
    // An OBJ in a folder whose name holds ':' finds its .mtl beside it.
    std::system(("mkdir -p '" + dir + "/a:b'").c_str());
    write_text(dir + "/a:b/t.mtl", "newmtl paint\nKd 0 0 1\n");
    write_text(dir + "/a:b/t.obj", "mtllib t.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nusemtl paint\nf 1 2 3\n");
    write_text(dir + "/scene.txt", "camera eye 0 0 3\nmesh a:b/t.obj\n");
    r = run_texr("explain " + dir + "/scene.txt 320 240");
    CHECK(r.output.find("material colour (0.00000, 0.00000, 1.00000)") != std::string::npos);
}

TEST_CASE("TextLineReader ends lines at LF, CRLF and a CR alone, as a byte-by-byte reading does") {
    const auto lines_of = [](const std::string& text) {
        std::istringstream in(text);
        texr::TextLineReader reader(in);
        std::vector<std::string> lines;
        for (std::string line; reader.next(line);) lines.push_back(line);
        return lines;
    };
    using Lines = std::vector<std::string>;
    CHECK(lines_of("") == Lines{});
    CHECK(lines_of("a\nb") == Lines{"a", "b"});
    CHECK(lines_of("a\r\nb\r\n") == Lines{"a", "b"});
    CHECK(lines_of("a\rb\r") == Lines{"a", "b"});
    CHECK(lines_of("a\r\r\nb") == Lines{"a", "", "b"});
    CHECK(lines_of("\n\r\n\r") == Lines{"", "", ""});
    CHECK(lines_of("a\n\rb\n\r\n") == Lines{"a", "", "b", ""});
    // Against a byte-by-byte reading (the rule tinyobjloader follows: LF ends a line; CR
    // ends it too, taking an LF right after it along; the text's end ends a line that has
    // something in it), on every text of up to 8 bytes from 'a', CR and LF.
    const auto by_bytes = [](const std::string& text) {
        Lines lines;
        std::string line;
        bool open = false;
        for (std::size_t i = 0; i < text.size(); ++i) {
            if (text[i] == '\n' || text[i] == '\r') {
                if (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
                lines.push_back(line), line.clear(), open = false;
            } else {
                line += text[i], open = true;
            }
        }
        if (open) lines.push_back(line);
        return lines;
    };
    int texts = 0;
    for (int length = 0; length <= 8; ++length) {
        int count = 1;
        for (int k = 0; k < length; ++k) count *= 3;
        for (int code = 0; code < count; ++code, ++texts) {
            std::string text;
            for (int k = 0, c = code; k < length; ++k, c /= 3) text += "a\r\n"[c % 3];
            CAPTURE(text);
            CHECK(lines_of(text) == by_bytes(text));
        }
    }
    CHECK(texts == 9841);
}

TEST_CASE("scene, OBJ and .mtl files with lines ended by CRLF or by CR alone render as with LF, and errors keep their lines") {
    // tinyobjloader ends OBJ and .mtl lines at LF, CRLF or CR; texr's own checks of those
    // files, and its scene files, must see the same lines.
    const std::string dir = scratch_folder("line-ends");
    std::system(("cp -r '" + source_path("models/textures") + "' '" + dir + "/textures'").c_str());
    const auto ended = [](const std::string& text, const std::string& eol) {
        std::string out;
        for (const char c : text) out += c == '\n' ? eol : std::string(1, c);
        return out;
    };
    const RunResult reference = run_texr("render " + source_path("models/demo.scene") + " --size 200x150 -o " + dir + "/lf.ppm");
    REQUIRE(reference.exit_code == 0);
    for (const std::string eol : {"\r\n", "\r"}) {
        CAPTURE(eol.size());
        for (const char* name : {"demo.scene", "torus.obj", "cube.obj", "cube.mtl"})
            write_text(dir + "/" + name, ended(read_file(source_path(std::string("models/") + name)), eol));
        const RunResult r = run_texr("render " + dir + "/demo.scene --size 200x150 -o " + dir + "/ended.ppm");
        CAPTURE(r.output);
        CHECK(r.exit_code == 0);
        CHECK(read_file(dir + "/ended.ppm") == read_file(dir + "/lf.ppm"));
        // An error on a later line names that line, in each kind of file.
        write_text(dir + "/t.obj", ended("# t\nmtllib t.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nv 1 x 0\nf 1 2 3\n", eol));
        write_text(dir + "/t.mtl", ended("newmtl a\nKd 1 1 1\n", eol));
        write_text(dir + "/scene.txt", ended("# a\ncamera eye 0 0 3\n\nmesh t.obj\n", eol));
        CHECK(run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png").output ==
              "texr: " + dir + "/scene.txt:4: " + dir + "/t.obj:6: expected a number after 'v', got 'x'\n");
        write_text(dir + "/t.obj", ended("# t\nmtllib t.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n", eol));
        write_text(dir + "/t.mtl", ended("newmtl a\n# b\nKd 1 1\n", eol));
        CHECK(run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png").output ==
              "texr: " + dir + "/scene.txt:4: " + dir + "/t.mtl:3: Kd needs 3 numbers (or 1, a grey), got 2\n");
        write_text(dir + "/scene.txt", ended("# a\ncamera eye 0 0 3\n\nbackground 1 2\n", eol));
        CHECK(run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png").output.rfind("texr: " + dir + "/scene.txt:4: ", 0) == 0);
        CHECK(!file_exists(dir + "/out.png"));
    }
}

TEST_CASE("an OBJ line that ends in '\\' continues on the next: the same picture, errors at the continued line's first line") {
    const std::string dir = scratch_folder("obj-continued");
    write_text(dir + "/scene.txt", "camera eye 0 0 3\nmesh t.obj\n");
    // Two triangles of two materials and a quad (two triangles more), with and without
    // continued lines; the continued version's '\\' at the ends of words, after blanks, in a
    // mtllib and a usemtl line; a '\\' in a comment does not continue its line.
    write_text(dir + "/t.mtl", "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n");
    const std::string plain = "mtllib t.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nv -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\n"
                              "usemtl red\nf 1 2 3\nusemtl blue\nf 4 5 6 7\n";
    write_text(dir + "/t.obj", plain);
    REQUIRE(run_texr("render " + dir + "/scene.txt --size 96x72 -o " + dir + "/plain.ppm").exit_code == 0);
    const std::string continued = "mtllib \\\n t.mtl\nv -1 -1 0\nv 1 -1 0\nv 0\\\n1 0 # a comment \\\nv -1 -1 -1\nv 1 -1 -1\n"
                                  "v 1 1 -1\nv -1 1 -1\nusemtl red\nf 1 \\ \n 2 \\\n\t3\nusemtl\\\n blue\nf 4 5 6 7";
    write_text(dir + "/t.obj", continued);
    RunResult r = run_texr("render " + dir + "/scene.txt --size 96x72 -o " + dir + "/continued.ppm");
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    CHECK(read_file(dir + "/continued.ppm") == read_file(dir + "/plain.ppm"));
    // Errors: at the first line of a continued line, and at its own line after one.
    write_text(dir + "/t.obj", "v -1 -1 0\nv 1 \\\n x \\\n 0\nv 0 1 0\nf 1 2 3\n");
    r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
    CHECK(r.output == "texr: " + dir + "/scene.txt:2: " + dir + "/t.obj:2: expected a number after 'v', got 'x'\n");
    write_text(dir + "/t.obj", "v -1 -1 0\nv 1 \\\n -1 \\\n 0\nv 0 1 0\nf 1 2 4\n");
    r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
    CHECK(r.output.rfind("texr: " + dir + "/scene.txt:2: " + dir + "/t.obj:6: ", 0) == 0);
    CHECK(!file_exists(dir + "/out.png"));
    // tinyobjloader's own errors (a joint weight texr does not check) keep the file's line
    // numbers after a continued line.
    write_text(dir + "/t.obj", "v -1 -1 0\nv 1 \\\n -1 \\\n 0\nv 0 1 0\nvw 0 -1 0.5\nf 1 2 3\n");
    r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
    CHECK(r.output.rfind("texr: " + dir + "/scene.txt:2: " + dir + "/t.obj: not a readable OBJ file: ", 0) == 0);
    CHECK(r.output.find("line 6.") != std::string::npos);
    // A file with no comment, whose only change for tinyobjloader is the joined line (a tab
    // after the '\\' still continues it), and the same without the '\\'.
    write_text(dir + "/t.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
    REQUIRE(run_texr("render " + dir + "/scene.txt --size 96x72 -o " + dir + "/one.ppm").exit_code == 0);
    write_text(dir + "/t.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 \\\t\n2 3\n");
    r = run_texr("render " + dir + "/scene.txt --size 96x72 -o " + dir + "/joined.ppm");
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    CHECK(read_file(dir + "/joined.ppm") == read_file(dir + "/one.ppm"));
    // A '\\' on the file's last line is refused at that line, as in scene files.
    for (const std::string end : {"f 1 2 3 \\", "f 1 2 \\\n3 \\\n"}) {
        write_text(dir + "/t.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\n" + end);
        r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CHECK(r.output == "texr: " + dir + "/scene.txt:2: " + dir + "/t.obj:" + (end.size() > 10 ? "5" : "4") +
                              ": line ends with '\\' but the file ends there\n");
    }
}

TEST_CASE("a .mtl Kd of one number is a grey, as the MTL format reads it, with every line ending") {
    // (tinyobjloader alone would read 'Kd 0.25' as (0.25, 0, 0).)
    const std::string dir = scratch_folder("kd-grey");
    write_text(dir + "/scene.txt", "camera eye 0 0 3\nmesh t.obj\n");
    for (const std::string eol : {"\n", "\r\n", "\r"}) {
        CAPTURE(eol.size());
        write_text(dir + "/t.obj", "mtllib t.mtl" + eol + "v -1 -1 0" + eol + "v 1 -1 0" + eol + "v 0 1 0" + eol + "usemtl grey" + eol +
                                       "f 1 2 3" + eol + "v -1 -1 -1" + eol + "v 1 -1 -1" + eol + "v 0 1 -1" + eol + "usemtl red" + eol +
                                       "f 4 5 6" + eol);
        write_text(dir + "/t.mtl", "newmtl grey" + eol + "  Kd\t0.25 # a grey" + eol + "newmtl red" + eol + "Kd 1 0 0" + eol);
        RunResult r = run_texr("explain " + dir + "/scene.txt 320 240");
        CAPTURE(r.output);
        CHECK(r.exit_code == 0);
        CHECK(r.output.find("material colour (0.25000, 0.25000, 0.25000)") != std::string::npos);
        write_text(dir + "/t.mtl", "newmtl grey" + eol + "Kd 0.25" + eol + "newmtl red" + eol + "Kd 1 0" + eol);
        r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CHECK(r.output == "texr: " + dir + "/scene.txt:2: " + dir + "/t.mtl:4: Kd needs 3 numbers (or 1, a grey), got 2\n");
    }
    // The last line without an end of line.
    write_text(dir + "/t.mtl", "newmtl grey\nKd 0.75");
    RunResult r = run_texr("explain " + dir + "/scene.txt 320 240");
    CHECK(r.output.find("material colour (0.75000, 0.75000, 0.75000)") != std::string::npos);
    // A .mtl that starts with a UTF-8 byte order mark keeps its first material (tinyobjloader
    // alone would read the mark as part of 'newmtl', and drop it).
    write_text(dir + "/t.mtl", "\xEF\xBB\xBFnewmtl grey\nKd 0.5 0.25 1\n");
    r = run_texr("explain " + dir + "/scene.txt 320 240");
    CHECK(r.output.find("material colour (0.50000, 0.25000, 1.00000)") != std::string::npos);
}

TEST_CASE("texr bench: the index lists an earlier run's benchmarks too, filters.md links its frames, and scenes without a texture are refused") {
    const std::string dir = scratch_folder("bench-index");
    REQUIRE(run_texr("bench filters --quick --out " + dir).exit_code == 0);
    REQUIRE(run_texr("bench spans --quick --out " + dir).exit_code == 0);
    const std::string index = read_file(dir + "/index.md");
    CAPTURE(index);
    const auto line_of = [&](const std::string& name) {
        const std::size_t at = index.find("- [" + name + "](" + name + ".md): ");
        return at == std::string::npos ? std::string() : index.substr(at, index.find('\n', at) - at);
    };
    CHECK(line_of("filters").find("(from an earlier run: its targets are not in targets.md)") != std::string::npos);
    CHECK(line_of("spans") != "");
    CHECK(line_of("spans").find("earlier run") == std::string::npos);
    CHECK(index.find("threads") == std::string::npos);
    // The spans plot says where an error of 0 (the exact mode's) is drawn.
    CHECK(read_file(dir + "/spans.svg").find("exact (error 0)") != std::string::npos);
    // Every frame filters.md links is there: 2 scenes x (8 filters + the ground truth).
    const std::string md = read_file(dir + "/filters.md");
    int links = 0;
    for (std::size_t at = md.find("](filters-"); at != std::string::npos; at = md.find("](filters-", at + 1), ++links)
        CHECK(file_exists(dir + "/" + md.substr(at + 2, md.find(')', at) - at - 2)));
    CHECK(links == 18);
    // Models whose benchmark scene draws nothing with a texture: one message, and no folder.
    const std::string models = scratch_folder("bench-models");
    std::system(("mkdir -p " + models + "/bench").c_str());
    const std::string untextured = "camera eye 0 0 3\ntriangle v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1\n";
    write_text(models + "/bench/plane.scene", untextured);
    write_text(models + "/bench/grazing.scene", untextured);
    for (const char* name : {"filters", "spans", "threads", "scale"}) {
        const RunResult r = run_texr(std::string("bench ") + name + " --quick --models " + models + " --out " + models + "/out");
        CAPTURE(r.output);
        CHECK(r.exit_code == 1);
        CHECK(r.output == "texr: " + models + "/bench/plane.scene: no object of this benchmark scene is drawn with a texture (texr bench times and scores texture filtering)\n");
        CHECK_FALSE(file_exists(models + "/out"));
    }
    // A texture defined but drawn by no object is refused too; threads and scale read the
    // plane alone, and take a grazing scene without a texture.
    const std::string textured = "camera eye 0 0 3\ntexture t file " + source_path("models/textures/checker.png") +
                                 "\nmaterial m texture t\ntriangle v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1 material m\n";
    write_text(models + "/bench/plane.scene", "texture t file " + source_path("models/textures/checker.png") + "\n" + untextured);
    CHECK(run_texr("bench threads --quick --models " + models + " --out " + models + "/out").exit_code == 1);
    CHECK_FALSE(file_exists(models + "/out"));
    write_text(models + "/bench/plane.scene", textured);
    CHECK(run_texr("bench threads --quick --models " + models + " --out " + models + "/out").exit_code == 0);
    const RunResult filters = run_texr("bench filters --quick --models " + models + " --out " + models + "/out");
    CHECK(filters.exit_code == 1);
    CHECK(filters.output.find(models + "/bench/grazing.scene: no object") != std::string::npos);
    const RunResult missing = run_texr("bench --quick --models " + models + "/none --out " + models + "/out2");
    CHECK(missing.exit_code == 1);
    CHECK_FALSE(file_exists(models + "/out2"));
    CHECK(run_texr("bench --out ''").exit_code == 2);
    // Scenes whose camera looks away from the textured triangle: nothing is covered, so
    // nothing is scored (NaN, each target missed), and stderr says why (the spans errors read
    // 0 and met the 1/64-texel bound; PSNR read +infinity).
    const std::string away = "camera eye 0 0 3 target 0 0 6\ntexture t file " + source_path("models/textures/checker.png") +
                             "\nmaterial m texture t\ntriangle v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1 material m\n";
    write_text(models + "/bench/plane.scene", away);
    write_text(models + "/bench/grazing.scene", away);
    write_text(models + "/bench/wall.scene", away);
    for (const char* name : {"filters", "spans"}) {
        const RunResult r = run_texr(std::string("bench ") + name + " --quick --models " + models + " --out " + models + "/out3");
        CAPTURE(r.output);
        CHECK(r.exit_code == 0);
        CHECK(r.output.find(std::string("bench ") + name + ": plane covers no pixel of the frame") != std::string::npos);
        CHECK(r.output.find("target met") == std::string::npos);
        CHECK(r.output.find(std::string(name) == "spans" ? "max error <= 1/64 texel              nan texel" : "PSNR >= 35 dB") !=
              std::string::npos);
    }
    // No pixel read a texel: 0 texels a pixel, not 0 / 0 printed as -nan.
    const std::string csv = read_file(models + "/out3/filters.csv");
    CHECK(csv.find("-nan") == std::string::npos);
    CHECK(csv.find(",0.00\n") != std::string::npos);
}

TEST_CASE("texr bench --quick writes every benchmark's CSV, table and plot, and an index") {
    const std::string dir = scratch_folder("bench");
    const RunResult r = run_texr("bench --quick --out " + dir);
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    for (const char* name : {"filters", "spans", "threads", "scale"})
        for (const char* ext : {".csv", ".md", ".svg"}) CHECK(file_exists(dir + "/" + name + ext));
    CHECK(file_exists(dir + "/index.md"));
    // The issues' targets, each checked: 5 from filters, 4 from spans, 8 from threads, 2 from scale.
    std::ifstream targets(dir + "/targets.md");
    std::string line;
    std::map<std::string, int> per_benchmark;
    while (std::getline(targets, line))
        for (const char* name : {"filters", "spans", "threads", "scale"})
            if (line.rfind(std::string("| ") + name + " |", 0) == 0) ++per_benchmark[name];
    CHECK(per_benchmark["filters"] == 5);
    CHECK(per_benchmark["spans"] == 4);
    CHECK(per_benchmark["threads"] == 8);
    CHECK(per_benchmark["scale"] == 2);
    // --quick measures one small frame, a small terrain and a small texture: the targets of the
    // filters, threads and scale benchmarks, and the span modes' time ratios, are not
    // measured as the issues ask.
    CHECK(r.output.find("of 19 targets met, 17 not measured as the issues ask") != std::string::npos);
    std::ifstream again(dir + "/targets.md");
    int not_measured = 0;
    while (std::getline(again, line)) not_measured += line.find("| not measured: ") != std::string::npos ? 1 : 0;
    CHECK(not_measured == 5 + 2 + 8 + 2);  // spans: its two time ratios (its error bounds hold at any size)
    // The scale table counts the decoded texel copies the frames made: the 1024^2 trilinear
    // texture's, 16 bytes a texel on every level, 16 MiB x (1 + 1/4 + 1/16 + ...) = 21.3 MiB.
    std::ifstream scale(dir + "/scale.md");
    bool texture_row = false;
    while (std::getline(scale, line))
        if (line.rfind("| texture | plane | 1048576 |", 0) == 0) {
            texture_row = true;
            CHECK(line.find(" | 21.3 | ") != std::string::npos);
        }
    CHECK(texture_row);
    // Every CSV row names the scene, size, threads, filter and mode (issue 4).
    std::ifstream csv(dir + "/spans.csv");
    std::string header;
    std::getline(csv, header);
    for (const char* column : {"scene", "width", "height", "threads", "filter", "mode"}) CHECK(header.find(column) != std::string::npos);
    CHECK(run_texr("bench --size 100000x100000 --out " + dir).exit_code == 2);
    // --size wins over --quick's 256x192 before it or after it (it lost when given first).
    for (const std::string order : {"--size 96x64 --quick", "--quick --size 96x64"}) {
        CAPTURE(order);
        REQUIRE(run_texr("bench spans " + order + " --out " + dir).exit_code == 0);
        std::ifstream rows(dir + "/spans.csv");
        std::getline(rows, line);  // the header
        std::getline(rows, line);
        CHECK(line.rfind("plane,96,64,", 0) == 0);
    }
    // And --spp: the filters table names the ground truth it scored against.
    for (const std::string order : {"--spp 2 --quick", "--quick --spp 2"}) {
        CAPTURE(order);
        REQUIRE(run_texr("bench filters " + order + " --size 64x48 --out " + dir).exit_code == 0);
        CHECK(read_file(dir + "/filters.md").find("against 2x2 supersampling") != std::string::npos);
    }
}

TEST_CASE("bad OBJ lines are refused with the OBJ file and line: numbers, missing coordinates, quads with a bad index") {
    const std::string dir = scratch_folder("obj-bad-lines");
    const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    struct Case {
        std::string obj, where, what;
    };
    const Case cases[] = {
        {"v 0 0 x\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bad.obj:1: ", "expected a number"},
        {"v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bad.obj:1: ", "needs x, y and z"},
        {"v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bad.obj:1: ", "finite"},
        {triangle + "vn 0 1\nf 1//1 2//1 3//1\n", "bad.obj:4: ", "needs x, y and z"},
        {triangle + "f 1 2\n", "bad.obj:4: ", "at least 3 corners"},
        {triangle + "f 1 2 3/a\n", "bad.obj:4: ", "expected a face corner"},
        // A corner cut short (a truncated file) or with a fourth part: tinyobjloader read '3/'
        // as index 0 and said only "zero value for face index", and ignored '/1' after vn.
        {triangle + "vt 0 0\nf 1/1 2/1 3/\n", "bad.obj:5: ", "expected a face corner (v, v/vt, v//vn or v/vt/vn), got '3/'"},
        {triangle + "f 1 2 3//\n", "bad.obj:4: ", "got '3//'"},
        {"v 0 0 1\xC2\xA0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bad.obj:1: ", "expected a number after 'v', got '1\\xC2\\xA0'"},
        {triangle + "vt 0 0\nf 1/1/ 2/1 3/1\n", "bad.obj:5: ", "got '1/1/'"},
        {triangle + "vt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1/1\n", "bad.obj:6: ", "got '3/1/1/1'"},
        // tinyobjloader drops such a quad with only a warning
        {triangle + "v 1 1 0\nusemtl red\nf 1 2 3\nf 1 2 4 99\n", "bad.obj:7: ", "vertex that does not exist"},
        {triangle + "f -1 -2 -4\n", "bad.obj:4: ", "vertex that does not exist"},
        {"v 0 0 0\nv 1 0 0\nf 1 2 7\n", "bad.obj:3: ", "vertex that does not exist"},
        // (found by the OBJ fuzzer: tinyobjloader passes such indices through unchecked)
        {triangle + "vn 0 0 1\nf 1//1 2//1 3//4\n", "bad.obj:5: ", "normal (vn) that does not exist"},
        {triangle + "vt 0 0\nf 1/1 2/1 3/9\n", "bad.obj:5: ", "texture coordinate (vt) that does not exist"},
        {"f 1 2 9\n" + triangle, "bad.obj:1: ", "vertex that does not exist (9)"},  // (ahead of the vertices, and past them)
        {"v 0 0 1e400\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bad.obj:1: ", "finite"},
        // finite as a double, not as the float a position, normal or texture coordinate is kept
        // in (tinyobjloader reads floats: vt 1e39 became infinity, and every u NaN)
        {"v 0 0 1e39\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bad.obj:1: ", "beyond a float's range"},
        {triangle + "vn 0 -4e38 1\nf 1//1 2//1 3//1\n", "bad.obj:4: ", "beyond a float's range"},
        {triangle + "vt 0 0\nvt 1 0\nvt 1e39 0\nf 1/1 2/2 3/3\n", "bad.obj:6: ", "'1e39' is beyond a float's range"},
        // Vertex colours (v x y z r g b): on every vertex or none, each from 0 to 10000; no
        // other count of numbers (tinyobjloader read 5 as no colour, 7 as a colour and one more)
        {"v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0\nf 1 2 3\n", "bad.obj:3: ",
         "a vertex without a colour: vertex colours (v x y z r g b) are on 2 of the file's 3 vertices (the first at line 1)"},
        {"v 0 0 0\nv 1 0 0 0 1 0\nv 0 1 0 1 1 1\nf 1 2 3\n", "bad.obj:1: ", "are on 2 of the file's 3 vertices (the first at line 2)"},
        {"v 0 0 0 1 0 0\nv 1 0 0 0 1 0 1\nv 0 1 0 1 1 1\nf 1 2 3\n", "bad.obj:2: ", "not 7 numbers"},
        {"v 0 0 0 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bad.obj:1: ", "not 5 numbers"},
        {"v 0 0 0 1 0 0\nv 1 0 0 0 -0.5 0\nv 0 1 0 1 1 1\nf 1 2 3\n", "bad.obj:2: ", "r, g and b from 0 to 10000"},
        {"v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 1 1 10001\nf 1 2 3\n", "bad.obj:3: ", "r, g and b from 0 to 10000"},
        // A smoothing group is a whole number, on or off (tinyobjloader read '-1', '1.5' and
        // 'yes' as groups of its own choosing, and an empty one as 0).
        {triangle + "s yes\nf 1 2 3\n", "bad.obj:4: ", "a smoothing group (s) is a whole number, on or off, not 'yes'"},
        {triangle + "s -1\nf 1 2 3\n", "bad.obj:4: ", "not '-1'"},
        {triangle + "s 1.5\nf 1 2 3\n", "bad.obj:4: ", "not '1.5'"},
        {triangle + "f 1 2 3\ns\n", "bad.obj:5: ", "a smoothing group (s) is a whole number, on or off, not nothing"},
        {triangle + "s 1 2\nf 1 2 3\n", "bad.obj:4: ", "a smoothing group (s) line holds one group, not '1' and '2'"},
        // At each bound: a vn of 4 numbers, a vt of none, a corner without its v or with index
        // 0, a number just past the float maximum, colours told at the first plain v line.
        {triangle + "vn 0 0 1 5\nf 1//1 2//1 3//1\n", "bad.obj:4: ", "a normal (vn) needs x, y and z"},
        {triangle + "vt\nf 1/1 2/1 3/1\n", "bad.obj:4: ", "a texture coordinate (vt) needs u (and v)"},
        {triangle + "vt 0 0\nf 1/1 2/1 /1\n", "bad.obj:5: ", "expected a face corner (v, v/vt, v//vn or v/vt/vn), got '/1'"},
        {triangle + "f 1 2 0\n", "bad.obj:4: ", "expected a face corner (v, v/vt, v//vn or v/vt/vn), got '0'"},
        {"v 0 0 0\nv 0 0 0\nv 3.4028236e38 0 0\nf 1 2 3\n", "bad.obj:3: ", "beyond a float's range"},
        {"v -1 -1 0 1 0 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n", "bad.obj:2: ", "a vertex without a colour"},
        // Numbers tinyobjloader reads otherwise than texr: 0e500 is 0 x 5^500 2^500 = NaN to it
        // (a colour's NaN turned a whole triangle's red to 0; a position's dropped it, a
        // normal's made N NaN); an exponent past an int's digits makes it drop every colour;
        // it splits words at spaces and tabs alone ('1\v0' moved a vertex without a word).
        {"v 0 0 0 0e500 0 0\nv 1 0 0 0 1 0\nv 0 1 0 1 1 1\nf 1 2 3\n", "bad.obj:1: ", "reads the number 0 as nan on this v line"},
        {"v 0 0 0\nv 1 0e500 0\nv 0 1 0\nf 1 2 3\n", "bad.obj:2: ", "reads the number 0 as nan on this v line"},
        {triangle + "vn 0e500 0 1\nf 1//1 2//1 3//1\n", "bad.obj:4: ", "reads the number 0 as nan on this vn line"},
        {triangle + "vt 0.5 0e999\nf 1/1 2/1 3/1\n", "bad.obj:4: ", "reads the number 0 as nan on this vt line"},
        {"v 0 0 0 0e99999999999 0 0\nv 1 0 0 0 1 0\nv 0 1 0 1 1 1\nf 1 2 3\n", "bad.obj:1: ",
         "'0e99999999999': an exponent the OBJ parser (tinyobjloader) cannot read"},
        {"v 0 0 0 1\v0 0\nv 1 0 0 0 1 0\nv 0 1 0 1 1 1\nf 1 2 3\n", "bad.obj:1: ", "got '1\\x0B0'"},
        {"v -1\v5 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bad.obj:1: ", "got '-1\\x0B5'"},
        {"\fv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 2 3 4\n", "bad.obj:5: ", "vertex that does not exist (4)"},  // (no v line)
    };
    for (const Case& c : cases) {
        write_text(dir + "/bad.obj", c.obj);
        write_text(dir + "/scene.txt", "size 16 16\nmaterial red color 1 0 0\nmesh bad.obj\n");
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CAPTURE(c.obj);
        CAPTURE(r.output);
        CHECK(r.exit_code == 1);
        CHECK(r.output.find("scene.txt:3: ") != std::string::npos);
        CHECK(r.output.find(c.where) != std::string::npos);
        CHECK(r.output.find(c.what) != std::string::npos);
        CHECK_FALSE(file_exists(dir + "/out.png"));
    }
    // Read: negative indices counting back from the last vertex defined, a face ahead of its
    // vertices, a comment with no space before it or after a face, a number that underflows
    // to 0, a UTF-8 byte order mark.
    for (const std::string& good : std::vector<std::string>{triangle + "f -3 -2 -1\n", "f 1 2 3\n" + triangle, "v 0 0 0#c\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                                   "v 0 0 1e-400\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", triangle + "f 1 2 3 # a comment\n",
                                   "v 0 0 3e38\nv 1 0 0\nv 0 1 0\nvt 3e38 0\nf 1/1 2/1 3/1\n",
                                   "v 0 0 0 1\nv 1 0 0 0.5\nv 0 1 0\nf 1 2 3\n",  // (a w, no colour)
                                   "v 0 0 0 0 0 0\nv 1 0 0 1 1 1\nv 0 1 0 10000 0 1\nf 1 2 3\n",
                                   // digit strings the two parsers may round an ulp apart, a float
                                   // subnormal, exponents of 0 and ones both read alike
                                   "v 0.333333333333333333333 123456789.123 -7.5e-3\nv 1e-40 1.17549435e-38 3.4e38\nv 0e400 0 1e-99999\n"
                                   "vt 0.1 0.9\nvt 1e-45 5\nvn 0.577 0.577 0.577\nf 1/1/1 2/2/1 3/1/1\n",
                                   "\xEF\xBB\xBF" + triangle + "f 1 2 3\n"}) {
        write_text(dir + "/good.obj", good);
        write_text(dir + "/scene.txt", "size 16 16\nmesh good.obj\n");
        CAPTURE(good);
        CHECK(run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png").exit_code == 0);
    }
}

TEST_CASE("an OBJ usemtl name ends at a tab or a comment") {
    const std::string dir = scratch_folder("usemtl-tab");
    write_text(dir + "/t.mtl", "newmtl green\nKd 0 1 0\n");
    write_text(dir + "/t.obj", "mtllib t.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nv 1 1 0\nusemtl green\t\nf 1 2 3\nusemtl red # paint\nf 2 4 3\n");
    write_text(dir + "/scene.txt", "size 8 8\ncamera eye 0 0 3\nmaterial red color 1 0 0\nmesh t.obj\n");
    CHECK(explained_material(dir, 2, 5) == "green");
    CHECK(explained_material(dir, 5, 2) == "red");
}

TEST_CASE("texr explain with --size or --span and no value says the value is missing") {
    for (const char* option : {"--size", "--span"}) {
        const RunResult r = run_texr("explain " + source_path("models/plane.scene") + " 1 2 " + option);
        CAPTURE(r.output);
        CHECK(r.exit_code == 2);
        CHECK(r.output.find(std::string(option) + " needs a value") != std::string::npos);
    }
    // An argument too many is named; too few say what is needed.
    RunResult r = run_texr("explain " + source_path("models/plane.scene") + " 1 2 3");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("texr explain takes SCENE X Y; '3' is one too many") != std::string::npos);
    r = run_texr("explain " + source_path("models/plane.scene") + " 1");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("texr explain needs SCENE X Y") != std::string::npos);
}

TEST_CASE("a command-line option given twice is refused, and nothing is written") {
    const std::string dir = scratch_folder("option-twice");
    const std::string scene = source_path("models/plane.scene");
    struct Twice {
        std::string command, message;
    };
    for (const Twice& t : {Twice{"render " + scene + " -o " + dir + "/a.png -o " + dir + "/b.png", "-o is given twice"},
                           Twice{"render " + scene + " --output " + dir + "/a.png -o " + dir + "/b.png", "-o is given twice"},
                           Twice{"render " + scene + " -o " + dir + "/a.png --size 10x10 --size 20x20", "--size is given twice"},
                           Twice{"render " + scene + " -o " + dir + "/a.png --threads 2 --threads 1", "--threads is given twice"},
                           Twice{"render " + scene + " -o " + dir + "/a.png --stats --stats", "--stats is given twice"},
                           Twice{"explain " + scene + " 1 2 --size 10x10 --size 20x20", "--size is given twice"},
                           Twice{"bench filters --out " + dir + "/bench --quick --quick", "--quick is given twice"}}) {
        const RunResult r = run_texr(t.command);
        CAPTURE(t.command);
        CAPTURE(r.output);
        CHECK(r.exit_code == 2);
        CHECK(r.output.find(t.message + ": give it once") != std::string::npos);
        CHECK_FALSE(file_exists(dir + "/a.png"));
        CHECK_FALSE(file_exists(dir + "/b.png"));
        CHECK_FALSE(file_exists(dir + "/bench"));
    }
    // Once each is fine.
    CHECK(run_texr("render " + scene + " -o " + dir + "/a.png --size 10x10 --threads 2").exit_code == 0);
    CHECK(file_exists(dir + "/a.png"));
}

TEST_CASE("an OBJ material neither the scene nor a .mtl describes is the default grey, and a later scene material of its name is refused clearly") {
    const std::string dir = scratch_folder("usemtl-undescribed");
    write_text(dir + "/t.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nusemtl paint\nf 1 2 3\n");
    write_text(dir + "/plain.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
    // The centre pixel of each: the same light grey (sRGB 0.8: byte 204) with or without usemtl.
    for (const char* obj : {"t.obj", "plain.obj"}) {
        write_text(dir + "/scene.txt", std::string("size 9 9\ncamera eye 0 0 3\nmesh ") + obj + "\n");
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.ppm");
        REQUIRE(r.exit_code == 0);
        std::ifstream in(dir + "/out.ppm", std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const std::size_t pixels = bytes.size() - 9 * 9 * 3, centre = pixels + (4 * 9 + 4) * 3;
        CAPTURE(obj);
        CHECK(int(std::uint8_t(bytes[centre])) == 204);
        CHECK(int(std::uint8_t(bytes[centre + 2])) == 204);
    }
    write_text(dir + "/scene.txt", "mesh t.obj\nmaterial paint color 1 0 0\n");
    const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("scene.txt:2: material 'paint' is already defined: line 1's OBJ file uses it") != std::string::npos);
}

TEST_CASE("scene files with a byte order mark or a NUL byte, explain lines of any length, bench --size messages") {
    // A UTF-8 byte order mark before the first command is skipped (it made 'size' unknown).
    const std::string dir = scratch_folder("bom-nul");
    write_text(dir + "/scene.txt", "\xEF\xBB\xBF" + good_scene);
    CHECK(run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png").exit_code == 0);
    // A NUL byte is refused at its line (a message quoting it was cut short there).
    expect_failure("nul", good_scene + std::string("material m color 1 1 1\0 0\n", 27), "scene.txt:5: a NUL byte");
    // explain formats each line whole: %.4f of a lattice coordinate near 1e300 was over 300
    // characters, and the line's "y = " and newline were lost past 255. (Such coordinates are
    // now printed in powers of ten, so the lines are short; they must still be whole.)
    write_text(dir + "/huge.txt", "size 64 48\ntexture t file " + source_path("models/textures/checker.png") +
                                      "\nmaterial m texture t\n"
                                      "triangle material m v -1 -1 0 -1e300 0 v 1 -1 0 1e300 0 v 0 1 0 0 1e300\n");
    const RunResult r = run_texr("explain " + dir + "/huge.txt 32 30");
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    const std::size_t at = r.output.find("before wrapping): x = u resU - 1/2 = ");
    REQUIRE(at != std::string::npos);
    const std::size_t y_at = r.output.find('\n', at) + 1;
    const std::string line = r.output.substr(at, y_at - 1 - at), y_line = r.output.substr(y_at, r.output.find('\n', y_at) - y_at);
    CHECK(line.find("e+") != std::string::npos);
    CHECK(line.back() == ',');
    CHECK(y_line.rfind("    y = v resV - 1/2 = ", 0) == 0);
    CHECK(y_line.find("e+") != std::string::npos);
    CHECK(r.output.find("\n    bilinear reads columns", y_at) != std::string::npos);  // the next line starts a line
    // texr bench --size quotes the whole value and the real limit.
    for (const char* size : {"10x10x10", "0x0", "20000x10"}) {
        const RunResult b = run_texr(std::string("bench --size ") + size + " --out " + dir);
        CAPTURE(b.output);
        CHECK(b.exit_code == 2);
        CHECK(b.output.find(std::string("got '") + size + "'") != std::string::npos);
        CHECK(b.output.find("from 1 to 16384") != std::string::npos);
    }
}

TEST_CASE("a folder or a device named as a mesh, texture, .mtl or scene is refused at once, by name") {
    // (A review's `mesh /dev/zero` read for four minutes into 16.8 GB before running out of
    // memory; `mesh .` said the OBJ file had no faces. /dev/null stands for every device
    // here: were the check gone, it would fail at once, not read forever.)
    const std::string dir = scratch_folder("not-files");
    std::system(("mkdir -p " + dir + "/sub && ln -s /dev/null " + dir + "/dev.mtl").c_str());
    write_text(dir + "/lib.obj", "mtllib dev.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write_text(dir + "/folder-lib.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nmtllib sub\nf 1 2 3\n");
    for (const auto& line_expected : {std::pair<std::string, std::string>{"mesh /dev/null\n", "/dev/null: is a device, not an OBJ file"},
                                         {"mesh .\n", "is a folder, not an OBJ file"},
                                         {"texture t file /dev/null\nmaterial m texture t\nmesh " + source_path("models/cube.obj") + " material m\n",
                                          "/dev/null: is a device, not an image file"},
                                         {"texture t file .\nmaterial m texture t\nmesh " + source_path("models/cube.obj") + " material m\n",
                                          "is a folder, not an image file"},
                                         {"mesh lib.obj\n", "lib.obj:1: mtllib: " + dir + "/dev.mtl: is a device, not a .mtl file"},
                                         {"mesh folder-lib.obj\n", "folder-lib.obj:4: mtllib: " + dir + "/sub: is a folder, not a .mtl file"}}) {
        const std::string &line = line_expected.first, &expected = line_expected.second;  // (CAPTURE: as above)
        write_text(dir + "/scene.txt", "size 16 16\n" + line);
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CAPTURE(line);
        CAPTURE(r.output);
        CHECK(r.exit_code == 1);
        CHECK(r.output.find(expected) != std::string::npos);
        CHECK(r.output.find("scene.txt:2") != std::string::npos);
        CHECK_FALSE(file_exists(dir + "/out.png"));
    }
    const RunResult r = run_texr("render /dev/null -o " + dir + "/out.png");
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("/dev/null: is a device, not a scene file") != std::string::npos);
    // A scene from a pipe is read.
    write_text(dir + "/scene.txt", good_scene);
    const std::string piped = "cat " + dir + "/scene.txt | " + TEXR_BINARY + " render /dev/stdin -o " + dir + "/piped.png > /dev/null 2>&1";
    CHECK(std::system(piped.c_str()) == 0);
    CHECK(file_exists(dir + "/piped.png"));
}

TEST_CASE("a continued mesh line: OBJ, .mtl and map_Kd errors at its file name's line, a textured material's at its own") {
    const std::string dir = scratch_folder("continued-mesh-errors");
    write_text(dir + "/plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");  // no vt
    write_text(dir + "/lib.obj", "mtllib lib.mtl\nusemtl painted\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n");
    write_text(dir + "/lib.mtl", "newmtl painted\nKd 1 1 1\nmap_Kd gone.png\n");
    write_text(dir + "/lib-plain.obj", "mtllib lib2.mtl\nusemtl tex\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write_text(dir + "/lib2.mtl", "newmtl tex\nKd 1 1 1\nmap_Kd " + source_path("models/textures/checker.png") + "\n");
    const std::string head = "size 16 16\ntexture t file " + source_path("models/textures/checker.png") + "\nmaterial tm texture t\n";
    struct Case {
        std::string mesh, message;
    };
    for (const Case& k : {Case{"mesh \\\n  lib.obj \\\n  cull back\n", "scene.txt:5: OBJ material 'painted' (map_Kd in " + dir + "/lib.mtl): " + dir + "/gone.png: cannot open image file"},
                          Case{"mesh \\\n  plain.obj \\\n  cull back \\\n  material tm\n", "scene.txt:7: " + dir + "/plain.obj has faces without texture coordinates (vt) drawn with material 'tm'"},
                          Case{"mesh plain.obj \\\n  material tm \\\n  cull back\n", "scene.txt:5: " + dir + "/plain.obj has faces without texture coordinates (vt) drawn with material 'tm'"},
                          Case{"mesh \\\n  lib-plain.obj \\\n  cull back\n", "scene.txt:5: " + dir + "/lib-plain.obj has faces without texture coordinates (vt) drawn with material 'tex'"}}) {
        CAPTURE(k.mesh);
        write_text(dir + "/scene.txt", head + k.mesh);
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CAPTURE(r.output);
        CHECK(r.exit_code == 1);
        CHECK(r.output.find(k.message) != std::string::npos);
    }
    // A material an OBJ made, defined again below: the message names the line of the mesh's file.
    write_text(dir + "/shade.obj", "mtllib shade.mtl\nusemtl shade\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write_text(dir + "/shade.mtl", "newmtl shade\nKd 1 0 0\n");
    write_text(dir + "/scene.txt", head + "mesh \\\n  shade.obj \\\n  cull back\nmaterial shade color 1 0 0\n");
    const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
    CAPTURE(r.output);
    CHECK(r.output.find("scene.txt:7: material 'shade' is already defined: line 5's OBJ file uses it") != std::string::npos);
}

TEST_CASE("texr explain prints HDR values near the float maximum in 6 significant digits, small ones to 5 decimals, NaN as nan, -0 as 0") {
    // A 2x2 flat Radiance file (no run-length rows under 8 texels): RGBE (128, 128, 128, 252)
    // is 128 x 2^(252 - 136) = 2^123 = 1.06338e+37 (10633823966279326983230456482242756608);
    // (128, 64, 32, 129) is (1, 0.5, 0.25). As %.5f, 2^123 would print 39 digits.
    const std::string dir = scratch_folder("hdr-explain");
    // explain at the centre of a square filling the view, textured with `texture` under the
    // material options and scene lines given.
    const auto explain = [&](const std::string& texture, const std::string& material = "", const std::string& lines = "") {
        write_text(dir + "/scene.txt", "size 8 8\ncamera eye 0 0 1 target 0 0 0 fov 90\n" + lines + "texture t file " + texture +
                                           " filter nearest\nmaterial m texture t" + material +
                                           "\nquad material m v -2 -2 0 0 0 v 2 -2 0 1 0 v 2 2 0 1 1 v -2 2 0 0 1\n");
        RunResult r = run_texr("explain " + dir + "/scene.txt 4 4");
        CHECK(r.exit_code == 0);
        return r.output;
    };
    for (const auto& [name, rgbe] : {std::pair<std::string, std::string>{"huge", {char(128), char(128), char(128), char(252)}},
                                     std::pair<std::string, std::string>{"small", {char(128), char(64), char(32), char(129)}}}) {
        std::string texels;
        for (int k = 0; k < 4; ++k) texels += rgbe;
        std::ofstream(dir + "/" + name + ".hdr", std::ios::binary) << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 2\n" + texels;
        const std::string out = explain(name + ".hdr");
        CAPTURE(out);
        if (name == "huge") {
            CHECK(out.find("the filter's value, linear RGBA: (1.06338e+37, 1.06338e+37, 1.06338e+37, 1.00000)") != std::string::npos);
            CHECK(out.find("x texture       (1.06338e+37, 1.06338e+37, 1.06338e+37)") != std::string::npos);
            CHECK(out.find("10633823966279326983230456482242756608") == std::string::npos);
        } else {
            CHECK(out.find("the filter's value, linear RGBA: (1.00000, 0.50000, 0.25000, 1.00000)") != std::string::npos);
        }
    }
    // The huge texel lit from behind: colour x texture overflows to inf, times an irradiance
    // of 0 that is NaN, printed "nan" (printf's own form carries the sign: "-nan").
    const std::string lit = explain("huge.hdr", " color 1000 1000 1000 lighting lambert", "light directional 0 0 1\n");
    CAPTURE(lit);
    CHECK(lit.find("    x irradiance    (0.00000, 0.00000, 0.00000)\n    = (nan, nan, nan)\n") != std::string::npos);
    CHECK(lit.find("-nan") == std::string::npos);
    // A material colour of -0 (the scene format takes it: -0 is not below 0) times the small
    // texel's 1 is -0: printed "0.00000" (printf's own form: "-0.00000").
    const std::string signed_zero = explain("small.hdr", " color -0 1 1");
    CAPTURE(signed_zero);
    CHECK(signed_zero.find("    material colour (0.00000, 1.00000, 1.00000)\n    x texture       (1.00000, 0.50000, 0.25000)\n"
                           "    = (0.00000, 0.50000, 0.25000)\n") != std::string::npos);
    CHECK(signed_zero.find("-0.00000") == std::string::npos);
    // 'colorspace srgb' asked of an HDR image, whose values are linear, is refused at that word
    // (on the next line here); 'colorspace linear' says what it is, and is read.
    write_text(dir + "/srgb.txt", "size 8 8\ntexture t file small.hdr \\\n  colorspace srgb\nmaterial m texture t\n"
                                  "quad material m v -2 -2 0 0 0 v 2 -2 0 1 0 v 2 2 0 1 1 v -2 2 0 0 1\n");
    RunResult r = run_texr("render " + dir + "/srgb.txt -o " + dir + "/srgb.png");
    CHECK(r.exit_code == 1);
    CHECK(r.output == "texr: " + dir + "/srgb.txt:3: a Radiance HDR image holds linear values: 'colorspace srgb' does not apply to it (leave it out)\n");
    CHECK(explain("small.hdr colorspace linear").find("(1.00000, 0.50000, 0.25000, 1.00000)") != std::string::npos);
}

TEST_CASE("a Radiance .hdr with run-length rows is read, and one cut short inside its rows is refused, not read for ever") {
    // 8x4 texels, each channel of each row one run of 8 (count 128 + 8, then the value): RGBE
    // (128, 64, 32, 129) is 2^(129 - 128) x (128, 64, 32) / 256 = (1, 0.5, 0.25).
    const std::string dir = scratch_folder("hdr-rle");
    std::string rows;
    for (int row = 0; row < 4; ++row) {
        rows += std::string{2, 2, 0, 8};
        for (const int value : {128, 64, 32, 129}) rows += std::string{char(0x88), char(value)};
    }
    const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n";
    std::ofstream(dir + "/whole.hdr", std::ios::binary) << header + rows;
    const texr::Image image = texr::load_image(dir + "/whole.hdr", texr::ColorSpace::linear);
    REQUIRE(image.width() == 8);
    REQUIRE(image.height() == 4);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 8; ++i) CHECK(image.texel(i, j) == texr::Color4(1.0f, 0.5f, 0.25f, 1.0f));
    // Cut inside its third row: stb_image read the end of the file as runs of 0 texels, and
    // looped for ever (`timeout` turns that into a failure here).
    std::ofstream(dir + "/cut.hdr", std::ios::binary) << header + rows.substr(0, 12 + 12 + 7);
    write_text(dir + "/scene.txt", "texture t file cut.hdr\n" + good_scene);
    const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png", 20);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("scene.txt:1: " + dir + "/cut.hdr: not a readable image: its run-length data is cut short or damaged (row 3 of 4)") !=
          std::string::npos);
    CHECK_FALSE(file_exists(dir + "/out.png"));
}

TEST_CASE("an image that leaves texels undefined is refused: palette indices beyond the palette, data it does not hold") {
    // stb_image returned such images with exit 0, their texels whatever memory held (valgrind:
    // uninitialised; two runs, two frames). Small files written by hand (hex), each damaged:
    // a 4x4 8-bit PNG with a palette of 2 entries indexing entry 200; an 8-bit BMP with 2
    // palette entries indexing 200 and 255; a 64x64 TGA with 5 bytes of its 12288; a JPEG
    // frame header with no scan. Then well-formed palette images, which read as before.
    const std::string dir = scratch_folder("undefined-texels");
    const auto write_hex = [&](const std::string& name, const std::string& hex) {
        std::string bytes;
        for (std::size_t i = 0; i + 1 < hex.size(); i += 2) bytes += char(std::stoi(hex.substr(i, 2), nullptr, 16));
        std::ofstream(dir + "/" + name, std::ios::binary) << bytes;
    };
    write_hex("pal.png", "89504e470d0a1a0a0000000d49484452000000040000000408030000009e2f6e4c00000006504c5445000000000000a567b9cf0000001049444154789c6360603cf19f019500003fcc0721b514375c0000000049454e44ae426082");
    write_hex("pal.bmp", "424d4e000000000000003e0000002800000004000000040000000100080000000000100000000000000000000000020000000000000000000000000000000001c8ff0001c8ff0001c8ff0001c8ff");
    write_hex("short.tga", "0000020000000000000000004000400018001010101010");  // (refused before it is decoded: below)
    write_hex("noscan.jpg", "ffd8ffc0000b080008000801011100ffd9");
    write_hex("pal4.png", "89504e470d0a1a0a0000000d49484452000000040000000404030000005bdf834d0000000c504c5445000102030405060708090a0bdc4c389c0000000174524e5380ad5e5b460000000d49444154789c63605466802100032800910d3b44840000000049454e44ae426082");
    write_hex("pal.tga", "000101000002001800000000040004000800ff000000ff00000102fa000102fa000102fa000102fa");
    for (const std::string name : {"pal.png", "noscan.jpg"}) {
        CAPTURE(name);
        write_text(dir + "/scene.txt", "texture t file " + name + "\n" + good_scene);
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CHECK(r.exit_code == 1);
        CHECK(r.output.find(name + ": not a readable image: it leaves texels undefined") != std::string::npos);
        CHECK_FALSE(file_exists(dir + "/out.png"));
    }
    // From a review of the above: the stack below stb_image is not all filled where its BMP
    // palette lies (an index of 160 into 1 entry passed both decodes alike, and its colour
    // changed from run to run), so BMP palette indices are checked against the entries stb_image
    // reads (4 short of the file's for the OS/2 header); a Radiance width past an int (stb_image
    // reads an int: 2^32 + 8 is 8) and Radiance texels read flat past the end of the file
    // (stb_image left them unset) are refused too.
    const std::pair<std::string, std::string> more[] = {
        {"pal.bmp", "palette index 200 is beyond the 2 palette entries stb_image reads"},
        {"os2.bmp", "stb_image reads no entry of this OS/2 BMP's palette"},
        {"short-palette.bmp", "palette index 160 is beyond the 1 palette entries stb_image reads"},
        {"wrapped-width.hdr", "its run-length data is cut short or damaged (row 1 of 2)"},
        {"flat-cut.hdr", "the file is cut short (its texels need 48 more bytes, it holds 0)"},
        {"row-cut.hdr", "the file is cut short (its texels need 64 more bytes, it holds 0)"},
        {"os2-p4.bmp", "palette index 15 is beyond the 12 palette entries stb_image reads (of an OS/2 BMP it reads 4 fewer than the file holds)"},
        // 18 bytes of header and 64 x 64 x 3 of texels
        {"short.tga", "the file is cut short (a 64 x 64 TGA needs at least 12306 bytes, the file holds 23)"},
    };
    write_hex("os2.bmp", "424d2800000000000000200000000c0000000800010001000100000000ffffff55000000");
    write_hex("short-palette.bmp", "424d3e000000000000003a000000280000000400000001000000010008000000000004000000130b0000130b000000000000000000001e140a00a0a0a0a0");
    write_hex("wrapped-width.hdr", "233f52414449414e43450a464f524d41543d33322d6269745f726c655f726762650a0a2d592032202b5820343239343936373330340a020200088880");
    write_hex("flat-cut.hdr", "233f52414449414e43450a464f524d41543d33322d6269745f726c655f726762650a0a2d592033202b5820340a");
    write_hex("row-cut.hdr", "233f52414449414e43450a464f524d41543d33322d6269745f726c655f726762650a0a2d592033202b5820380a020200088880884088208881");
    write_hex("os2-p4.bmp", "424d56000000000000004a0000000c0000000500030001000400000000975b252eb64ac5116f5c6c94f3c7b98a22de217d03b8d8284f334de68e727de9971444bcab9fe142fa06d9552bfffff000fffff000fffff000");
    for (const auto& name_message : more) {
        const std::string &name = name_message.first, &message = name_message.second;  // (CAPTURE: as above)
        CAPTURE(name);
        write_text(dir + "/scene.txt", "texture t file " + name + "\n" + good_scene);
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png", 20);
        CHECK(r.exit_code == 1);
        CHECK(r.output.find(name + ": not a readable image: " + message) != std::string::npos);
    }
    // A 4x4 4-bit PNG whose 4-entry palette covers its indices, and a TGA with a palette.
    for (const std::string name : {"pal4.png", "pal.tga"}) {
        CAPTURE(name);
        write_text(dir + "/scene.txt", "texture t file " + name + "\nmaterial m texture t\n" + good_scene +
                                           "quad material m v -1 -1 0 0 0 v 1 -1 0 1 0 v 1 1 0 1 1 v -1 1 0 0 1\n");
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CAPTURE(r.output);
        CHECK(r.exit_code == 0);
    }
}

TEST_CASE("faces with repeated corners keep their usemtl material, each face k - 2 triangles") {
    // A six-corner face that repeats its triangle is 4 triangles (tinyobjloader's own split made
    // none of it, and the materials of later faces were lost or refused). The square [0, 2]^2:
    // the face of material a covers its lower right half (1 2 3), b's its upper left (1 3 5).
    const std::string dir = scratch_folder("obj-uneven-faces");
    const std::string points = "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 1 0.5 0\nv 0 2 0\n";
    write_text(dir + "/one.obj", points + "usemtl b\nf 1 2 3 1 2 3\nf 1 3 5\n");
    write_text(dir + "/two.obj", points + "usemtl a\nf 1 2 3 1 2 3\nusemtl b\nf 1 3 5\n");
    const std::string head = "size 32 24\ncamera eye 1 1 3 target 1 1 0 fov 60\nmaterial a color 1 0 0\nmaterial b color 0 1 0\n";
    write_text(dir + "/scene.txt", head + "mesh one.obj\n");
    CHECK(explained_material(dir, 20, 16) == "b");  // (1.65, 0.35): lower right
    CHECK(explained_material(dir, 10, 6) == "b");   // (0.21, 1.79): upper left
    write_text(dir + "/scene.txt", head + "mesh two.obj\n");
    CHECK(explained_material(dir, 20, 16) == "a");
    CHECK(explained_material(dir, 10, 6) == "b");
    const texr::Scene scene = texr::load_scene(dir + "/scene.txt");
    REQUIRE(scene.meshes.size() == 1);
    CHECK(scene.meshes[0].triangles.size() == 5);
}

TEST_CASE("a normal of length 0 (vn 0 0 0, or n 0 0 0) takes the computed normal instead of shading as NaN") {
    // The triangle (0,0,0), (2,0,0), (0,2,0) winds counter-clockwise seen from +z: its computed
    // normal is (0, 0, 1). Lit by a light shining along -z: N . L = 1, so the lit colour is the
    // ambient 0.1 (sRGB; linear 0.01002) + 1. With the zero normals it was N = (-nan, ...) and
    // the light was lost.
    const std::string dir = scratch_folder("zero-normals");
    write_text(dir + "/zero.obj", "v 0 0 0\nv 2 0 0\nv 0 2 0\nvn 0 0 0\nf 1//1 2//1 3//1\n");
    const std::string head = "size 32 24\ncamera eye 0.5 0.5 3 target 0.5 0.5 0 fov 60\nlight directional 0 0 -1\nambient 0.1 0.1 0.1\n"
                             "material m color 1 1 1 lighting lambert\n";
    for (const std::string object : {"mesh zero.obj material m\n", "triangle material m v 0 0 0 0 0 n 0 0 0 v 2 0 0 1 0 n 0 0 0 v 0 2 0 0 1 n 0 0 0\n"}) {
        CAPTURE(object);
        write_text(dir + "/scene.txt", head + object);
        const RunResult r = run_texr("explain " + dir + "/scene.txt 16 12");
        CAPTURE(r.output);
        CHECK(r.exit_code == 0);
        CHECK(r.output.find("N = (0.00000, 0.00000, 1.00000)") != std::string::npos);
        CHECK(r.output.find("linear colour (1.01002, 1.01002, 1.01002)") != std::string::npos);
    }
}

TEST_CASE("an uncompressed BMP shorter than its header says is refused, one without its last row's padding is read") {
    // stb_image_write's BMP of 3 x 2 texels: rows of 9 bytes padded to 12, after a 54-byte
    // header: 78 bytes. stb_image read a BMP that ends early as if zeros followed (a 64-byte
    // file claiming 16000 x 16000 took 2 GB and became black).
    const std::string dir = scratch_folder("bmp-short");
    const unsigned char rgb[3 * 2 * 3] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30, 40, 50, 60, 70, 80, 90};
    std::string bmp;
    stbi_write_bmp_to_func(append_to_string,
                           &bmp, 3, 2, 3, rgb);
    REQUIRE(bmp.size() == 78);
    const std::string quad = "material m texture t\nquad material m v -1 -1 0 0 0 v 1 -1 0 1 0 v 1 1 0 1 1 v -1 1 0 0 1\n";
    for (const std::size_t cut : {0, 3, 4, 20}) {  // bytes taken off the end: 3 is the last row's padding
        CAPTURE(cut);
        std::ofstream(dir + "/t.bmp", std::ios::binary) << bmp.substr(0, bmp.size() - cut);
        write_text(dir + "/scene.txt", "texture t file t.bmp\n" + quad + good_scene);
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CAPTURE(r.output);
        if (cut <= 3) {
            CHECK(r.exit_code == 0);
        } else {
            CHECK(r.exit_code == 1);
            CHECK(r.output.find("t.bmp: not a readable image: the file is cut short (its header asks for 75 bytes, it holds " +
                                std::to_string(78 - cut) + ")") != std::string::npos);
        }
    }
    // The file read whole has the texels written: the top row of the file is v = 1.
    std::ofstream(dir + "/t.bmp", std::ios::binary) << bmp;
    const texr::Image image = texr::load_image(dir + "/t.bmp", texr::ColorSpace::linear);
    REQUIRE(image.width() == 3);
    REQUIRE(image.height() == 2);
    CHECK(image.texel(0, 1) == texr::Color4(1.0f, 0.0f, 0.0f, 1.0f));
    CHECK(image.texel(2, 0) == texr::Color4(70 / 255.0f, 80 / 255.0f, 90 / 255.0f, 1.0f));
}

TEST_CASE("a sequential JPEG whose header asks for more blocks than its data could hold is refused") {
    // Every 8 x 8 block of a sequential JPEG costs at least 2 bits (a DC code and an end of
    // block, each at least 1 bit). stb_image_write's JPEG at quality 90 is 4:2:0: an MCU of
    // 16 x 16 pixels holds 4 luma blocks and one of each chroma, 6 blocks, 12 bits at least.
    // stb_image read such a file as if zeros followed (613 bytes claiming 16000 x 16000
    // took 12 s and 2 GB).
    const std::string dir = scratch_folder("jpeg-short");
    std::string jpeg = small_jpeg(37);
    // The frame header: FF C0, length 17, precision 8, height, width, 3 components: Y sampled
    // 2 x 2, Cb and Cr 1 x 1.
    const std::size_t sof = jpeg.find("\xff\xc0");
    REQUIRE(sof != std::string::npos);
    REQUIRE(jpeg.substr(sof, 10) == std::string("\xff\xc0\x00\x11\x08\x00\x08\x00\x08\x03", 10));
    REQUIRE(static_cast<unsigned char>(jpeg[sof + 11]) == 0x22);
    REQUIRE(static_cast<unsigned char>(jpeg[sof + 14]) == 0x11);
    REQUIRE(static_cast<unsigned char>(jpeg[sof + 17]) == 0x11);
    const auto with_size = [&](int width, int height) {
        std::string j = jpeg;
        j[sof + 5] = char(height >> 8), j[sof + 6] = char(height & 255), j[sof + 7] = char(width >> 8), j[sof + 8] = char(width & 255);
        return render_texture_file(dir, "t.jpg", j);
    };
    const std::string file_bytes = std::to_string(jpeg.size());
    // 16000 x 16000: 1000 x 1000 MCUs of 6 blocks, 12e6 bits: 1500000 bytes.
    RunResult r = with_size(16000, 16000);
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("t.jpg: not a readable image: the file is cut short (a 16000 x 16000 sequential JPEG needs at least "
                        "1500000 bytes of image data, the file holds " + file_bytes + ")") != std::string::npos);
    CHECK_FALSE(file_exists(dir + "/out.png"));
    // A row of MCUs 16 pixels high: as many as the file's bits can hold is read, one more is not.
    const int mcus = int(jpeg.size() * 8 / 12);
    r = with_size(16 * mcus, 16);
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    r = with_size(16 * (mcus + 1), 16);
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("t.jpg: not a readable image: the file is cut short") != std::string::npos);
    // The file as written reads.
    r = with_size(8, 8);
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
}

TEST_CASE("a JPEG Huffman table of more than 256 codes is refused before stb_image writes past its arrays") {
    // stb_image 2.27 stores a table's code lengths and symbols in arrays of 256 (and 257)
    // without checking the count (UBSan: index 257 out of bounds; found by fuzzing texr's image
    // loading). The first DHT table of stb_image_write's JPEG gets counts 0 x 14, 255, 45: 300.
    const std::string dir = scratch_folder("jpeg-dht");
    std::string jpeg = small_jpeg(53);
    const auto render_with = [&](const std::string& bytes) { return render_texture_file(dir, "t.jpg", bytes); };
    RunResult r = render_with(jpeg);
    CHECK(r.exit_code == 0);
    std::remove((dir + "/out.png").c_str());
    const std::size_t dht = jpeg.find("\xff\xc4");
    REQUIRE(dht != std::string::npos);
    // FF C4, 2 bytes of length, the table's class and index, then its 16 counts.
    for (int i = 0; i < 14; ++i) jpeg[dht + 5 + std::size_t(i)] = 0;
    jpeg[dht + 19] = char(255), jpeg[dht + 20] = char(45);
    r = render_with(jpeg);
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("t.jpg: not a readable image: a Huffman table (DHT) of the JPEG defines 300 codes, more than the 256 there can be") !=
          std::string::npos);
    CHECK_FALSE(file_exists(dir + "/out.png"));
    // stb_image reads FF bytes before a marker as fill, also before the start of image: with
    // three of them the good file still renders, and the damaged one is still refused.
    // (Found by fuzzing: the check had looked for FF D8 in the first two bytes only.)
    r = render_with("\xff\xff\xff" + small_jpeg(53));
    CHECK(r.exit_code == 0);
    std::remove((dir + "/out.png").c_str());
    r = render_with("\xff\xff\xff" + jpeg);
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("defines 300 codes, more than the 256 there can be") != std::string::npos);
    CHECK_FALSE(file_exists(dir + "/out.png"));
    // A segment whose stated length (3) ends inside its table: stb_image reads the table's 16
    // counts past the segment anyway (16 x 255 = 4080 codes). (From a review of the check.)
    r = render_with(std::string("\xff\xd8\xff\xc4\x00\x03\x00", 7) + std::string(16, '\xff') + std::string(40, '\0'));
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("defines 4080 codes, more than the 256 there can be") != std::string::npos);
}

TEST_CASE("an image whose header claims more than 16384 texels on a side is refused before it is decoded") {
    // A GIF's logical screen can be any size while its one image is 1 x 1: stb_image sets aside
    // the whole screen (a 214-byte GIF of 28013 x 24941 asked for 1.8 GB; found by fuzzing).
    // The GIF: header, screen width and height (little-endian), a 2-entry colour table, one
    // 1 x 1 image of LZW codes clear (4), 0, end (5) in 3 bits each: bytes 44 01.
    const std::string dir = scratch_folder("image-too-large");
    const auto gif = [](unsigned width, unsigned height) {
        std::string g = "GIF89a";
        for (const unsigned side : {width, height}) g += char(side & 255), g += char(side >> 8);
        g += std::string("\x80\x00\x00" "\x00\x00\x00" "\xff\xff\xff", 9);                          // flags, colours
        g += std::string("\x2c\x00\x00\x00\x00\x01\x00\x01\x00\x00" "\x02\x02\x44\x01\x00" "\x3b", 16);  // the image
        return g;
    };
    RunResult r = render_texture_file(dir, "t.gif", gif(16384, 1));
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    std::remove((dir + "/out.png").c_str());
    for (const auto& [w, h] : {std::pair(16385u, 1u), std::pair(1u, 16385u), std::pair(28013u, 24941u)}) {
        r = render_texture_file(dir, "t.gif", gif(w, h));
        CAPTURE(r.output);
        CHECK(r.exit_code == 1);
        CHECK(r.output.find("t.gif: the image is too large: its header says " + std::to_string(w) + " x " + std::to_string(h) +
                            " texels, and texr reads at most 16384 per side") != std::string::npos);
        CHECK_FALSE(file_exists(dir + "/out.png"));
    }
    // A Softimage PIC, whose size stbi_info does not give when it cannot read the packets (7
    // bits per channel below) or the image is above 2^28 texels, while stb_image's loader
    // sets aside the whole image first (found in review). The PIC: 53 80 F6 34, 84 bytes, "PICT", width and height
    // (big-endian), 8 bytes, packets (chained, bits per channel, type, channels), texels.
    const auto pic = [](unsigned width, unsigned height, char bits) {
        std::string p = std::string("\x53\x80\xF6\x34", 4) + std::string(84, '\0') + "PICT";
        for (const unsigned side : {width, height}) p += char(side >> 8), p += char(side & 255);
        p += std::string(8, '\0') + std::string("\x00", 1) + bits + std::string("\x00\xf0", 2);  // one packet: RGBA, uncompressed
        return p + std::string(std::size_t(4) * std::min(width * height, 4u), '\x80');
    };
    r = render_texture_file(dir, "t.pic", pic(2, 2, 8));
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    std::remove((dir + "/out.png").c_str());
    for (const auto& [w, h, bits] : {std::tuple(16385u, 1u, 8), std::tuple(16385u, 1u, 7), std::tuple(65535u, 8191u, 8), std::tuple(65535u, 8191u, 7)}) {
        r = render_texture_file(dir, "t.pic", pic(w, h, char(bits)));
        CAPTURE(r.output);
        CHECK(r.exit_code == 1);
        CHECK(r.output.find("t.pic: the image is too large: its header says " + std::to_string(w) + " x " + std::to_string(h) +
                            " texels, and texr reads at most 16384 per side") != std::string::npos);
        CHECK_FALSE(file_exists(dir + "/out.png"));
    }
    // A PNG that is its header alone (signature and IHDR: 20000 x 20000, 8-bit RGB): too large
    // is told, not that it is cut short of its texels (a review found the second).
    std::string ihdr = "IHDR";
    for (const unsigned side : {20000u, 20000u})
        for (const int shift : {24, 16, 8, 0}) ihdr += char((side >> shift) & 255);
    ihdr += std::string("\x08\x02\x00\x00\x00", 5);
    const uLong crc = crc32(0, reinterpret_cast<const Bytef*>(ihdr.data()), uInt(ihdr.size()));
    std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + std::string("\x00\x00\x00\x0d", 4) + ihdr;
    for (const int shift : {24, 16, 8, 0}) png += char((crc >> shift) & 255);
    r = render_texture_file(dir, "t.png", png);
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("t.png: the image is too large: its header says 20000 x 20000 texels, and texr reads at most 16384 per side") !=
          std::string::npos);
    CHECK_FALSE(file_exists(dir + "/out.png"));
}

TEST_CASE("a JPEG scan that decodes with a Huffman table no DHT has defined is refused") {
    // stb_image reads such a table from memory it never set and indexed its 256 symbols at
    // 665 (UBSan; found by fuzzing texr's image loading). The two files are the image fuzz
    // seeds base.jpg (sequential) and prog.jpg (progressive); their layouts, from a marker
    // dump: base.jpg defines DC 0, AC 0, DC 1 and AC 1 (class/index bytes at 0xb5, 0xce, 0xf7,
    // 0x10f), then one scan of components 1 (DC 0, AC 0), 2 and 3 (DC 1, AC 1). prog.jpg's
    // first scan to read AC 1 (component 3, Ss = 1) follows the table at 0x13e that defines it.
    const std::string dir = scratch_folder("jpeg-undefined-table");
    const std::string base = read_file(source_path("tests/fuzz/corpus/image/base.jpg"));
    const std::string prog = read_file(source_path("tests/fuzz/corpus/image/prog.jpg"));
    REQUIRE(base.size() > 0x130);
    REQUIRE(prog.size() > 0x160);
    const auto redefined = [](std::string jpeg, std::size_t at, unsigned char was, unsigned char now) {
        REQUIRE(static_cast<unsigned char>(jpeg[at]) == was);
        jpeg[at] = static_cast<char>(now);
        return jpeg;
    };
    struct Damage {
        const std::string* jpeg;
        std::size_t at;
        unsigned char was, now;
        std::string table;
    };
    for (const Damage& d : {Damage{&base, 0xf7, 0x01, 0x02, "DC 1"}, Damage{&base, 0x10f, 0x11, 0x13, "AC 1"},
                            Damage{&prog, 0x13e, 0x11, 0x12, "AC 1"}}) {
        CAPTURE(d.at);
        RunResult r = render_texture_file(dir, "t.jpg", *d.jpeg);
        CHECK(r.exit_code == 0);
        std::remove((dir + "/out.png").c_str());
        r = render_texture_file(dir, "t.jpg", redefined(*d.jpeg, d.at, d.was, d.now));
        CAPTURE(r.output);
        CHECK(r.exit_code == 1);
        CHECK(r.output.find("t.jpg: not a readable image: a scan of the JPEG decodes with Huffman table " + d.table +
                            ", which no table (DHT) before it defines") != std::string::npos);
        CHECK_FALSE(file_exists(dir + "/out.png"));
    }
    // A file that ends inside the scan's header, before its Ss, Se and Ah/Al bytes (which
    // stb_image then reads as 0): an 8 x 8 frame of component 1 (SOF0, length 11), then a scan
    // of component 1 with DC table 0 and AC table 0 (SOS, length 8), and no DHT at all.
    const std::string cut("\xff\xd8\xff\xc0\x00\x0b\x08\x00\x08\x00\x08\x01\x01\x11\x00\xff\xda\x00\x08\x01\x01\x00", 22);
    RunResult r = render_texture_file(dir, "t.jpg", cut);
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("t.jpg: not a readable image: a scan of the JPEG decodes with Huffman table DC 0, which no table (DHT) before it "
                        "defines") != std::string::npos);
    CHECK_FALSE(file_exists(dir + "/out.png"));
}

TEST_CASE("a JPEG that dequantizes with a quantization table no DQT has defined is refused") {
    // stb_image multiplies by table values it never set (UBSan: signed overflow; found by
    // fuzzing, where the file's one DQT lay inside an APP0 segment). Both seeds define
    // table 0 (index byte at 0x18) and table 1 (0x5d) and use 0 for component 1, 1 for
    // components 2 and 3; renaming table 1 as table 2 leaves table 1 undefined. base.jpg
    // (sequential) uses it in its one scan, prog.jpg (progressive) at its end.
    const std::string dir = scratch_folder("jpeg-undefined-quantizer");
    for (const auto& [name, who] : {std::pair("base.jpg", "a scan of the JPEG"), std::pair("prog.jpg", "the progressive JPEG")}) {
        std::string jpeg = read_file(source_path(std::string("tests/fuzz/corpus/image/") + name));
        REQUIRE(jpeg.size() > 0x100);
        RunResult r = render_texture_file(dir, "t.jpg", jpeg);
        CHECK(r.exit_code == 0);
        const std::string frame = read_file(dir + "/out.png");
        std::remove((dir + "/out.png").c_str());
        REQUIRE(jpeg.substr(0x14, 2) == "\xff\xdb");
        REQUIRE(jpeg.substr(0x59, 2) == "\xff\xdb");
        REQUIRE(jpeg[0x5d] == '\x01');
        jpeg[0x5d] = '\x02';
        r = render_texture_file(dir, "t.jpg", jpeg);
        CAPTURE(r.output);
        CHECK(r.exit_code == 1);
        CHECK(r.output.find(std::string("t.jpg: not a readable image: ") + who +
                            " dequantizes with quantization table 1, which no table (DQT) before it defines") != std::string::npos);
        CHECK_FALSE(file_exists(dir + "/out.png"));
        // The same table defined after the frame header, still before the scans, is fine:
        // move the second DQT segment (0x59, 69 bytes) behind the frame header (0x9e, 19 bytes).
        jpeg[0x5d] = '\x01';
        const std::string moved = jpeg.substr(0, 0x59) + jpeg.substr(0x9e, 19) + jpeg.substr(0x59, 69) + jpeg.substr(0x9e + 19);
        REQUIRE(moved.size() == jpeg.size());
        r = render_texture_file(dir, "t.jpg", moved);
        CAPTURE(r.output);
        CHECK(r.exit_code == 0);
        CHECK(read_file(dir + "/out.png") == frame);  // the same texels
        std::remove((dir + "/out.png").c_str());
    }
}

TEST_CASE("a PNG whose image data cannot hold its header's size is refused before it is decoded") {
    // Deflate packs at most 1032 bytes into one. stb_image set aside and filled the whole
    // image before finding too few pixels (1077 bytes claiming 16000 x 16000: 3.7 s, 1.7 GB).
    const std::string dir = scratch_folder("png-short");
    const auto write_png = [&](int w, int h, const std::vector<unsigned char>& rgb) {
        std::string png;
        REQUIRE(stbi_write_png_to_func(append_to_string,
                                       &png, w, h, 3, rgb.data(), w * 3));
        return png;
    };
    const auto render_with = [&](const std::string& png) { return render_texture_file(dir, "t.png", png); };
    std::vector<unsigned char> rgb(4 * 4 * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<unsigned char>(71 * i);
    std::string png = write_png(4, 4, rgb);
    REQUIRE(png.substr(12, 4) == "IHDR");
    // IHDR: width and height (big-endian) at bytes 16 and 20; 16000 is 00 00 3e 80.
    for (const std::size_t at : {16, 20}) png.replace(at, 4, std::string("\x00\x00\x3e\x80", 4));
    RunResult r = render_with(png);
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    // 16000 x 16000 x 3 bytes = 768000000, of which deflate's 1032 : 1 (with 1032 bytes to
    // spare) needs ceil((768000000 - 1032) / 1032) = 744186 bytes.
    CHECK(r.output.find("t.png: not a readable image: the file is cut short (a 16000 x 16000 PNG needs at least 744186 bytes of "
                        "image data") != std::string::npos);
    CHECK_FALSE(file_exists(dir + "/out.png"));
    // A flat 2048 x 2048 PNG, the most compressible kind, reads.
    png = write_png(2048, 2048, std::vector<unsigned char>(2048 * 2048 * 3, 200));
    CAPTURE(png.size());
    r = render_with(png);
    CHECK(r.exit_code == 0);
    // So does a flat 4096 x 4096 one deflated by zlib at its best (level 9): 50335744 bytes of
    // rows in about 58600, 859 : 1, near deflate's limit.
    const std::string rows = [] {
        std::string one(1 + 4096 * 3, '\xc8');
        one[0] = 0;  // filter: none
        std::string all;
        for (int y = 0; y < 4096; ++y) all += one;
        return all;
    }();
    std::vector<unsigned char> deflated(compressBound(uLong(rows.size())));
    uLongf deflated_size = uLongf(deflated.size());
    REQUIRE(compress2(deflated.data(), &deflated_size, reinterpret_cast<const Bytef*>(rows.data()), uLong(rows.size()), 9) == Z_OK);
    CAPTURE(deflated_size);
    CHECK(deflated_size < 60000);
    png = std::string("\x89PNG\r\n\x1a\n", 8) +
          png_chunk("IHDR", std::string("\x00\x00\x10\x00\x00\x00\x10\x00\x08\x02\x00\x00\x00", 13)) +
          png_chunk("IDAT", std::string(reinterpret_cast<const char*>(deflated.data()), deflated_size)) + png_chunk("IEND", "");
    r = render_with(png);
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
}

TEST_CASE("a PNG with empty IDAT chunks reads as the same PNG without them") {
    // An empty IDAT is legal; stb_image 2.27 copied the first one from a null buffer (UBSan,
    // found by fuzzing). A 4 x 4 RGB image, its rows (filter byte 0, then the texels) deflated
    // by zlib, in one IDAT, then with empty IDATs before and after it.
    const std::string dir = scratch_folder("png-empty-idat");
    std::string rows;
    for (int y = 0; y < 4; ++y) {
        rows += '\0';
        for (int i = 0; i < 12; ++i) rows += char(17 * y + 50 * i);
    }
    std::vector<unsigned char> deflated(compressBound(uLong(rows.size())));
    uLongf deflated_size = uLongf(deflated.size());
    REQUIRE(compress2(deflated.data(), &deflated_size, reinterpret_cast<const Bytef*>(rows.data()), uLong(rows.size()), 9) == Z_OK);
    const std::string head = std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", std::string("\x00\x00\x00\x04\x00\x00\x00\x04\x08\x02\x00\x00\x00", 13));
    const std::string data = png_chunk("IDAT", std::string(reinterpret_cast<const char*>(deflated.data()), deflated_size));
    const std::string empty = png_chunk("IDAT", ""), end = png_chunk("IEND", "");
    REQUIRE(empty.size() == 12);
    RunResult r = render_texture_file(dir, "t.png", head + data + end);
    REQUIRE(r.exit_code == 0);
    const std::string frame = read_file(dir + "/out.png");
    std::remove((dir + "/out.png").c_str());
    r = render_texture_file(dir, "t.png", head + empty + data + empty + empty + end);
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    CHECK(read_file(dir + "/out.png") == frame);
    std::remove((dir + "/out.png").c_str());
    // Only empty IDATs: no image data at all.
    r = render_texture_file(dir, "t.png", head + empty + empty + end);
    CAPTURE(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("t.png: not a readable image") != std::string::npos);
    CHECK_FALSE(file_exists(dir + "/out.png"));
}

TEST_CASE("a TGA or Photoshop file shorter than its header asks for is refused before it is decoded") {
    // stb_image read such files as if zeros followed: 22 to 56 bytes claiming 16000 x 16000
    // took 6 to 11 s and 2 GB each. Small files written by hand (hex), whole, one byte short,
    // and with the header of a 16000 x 16000 image.
    const std::string dir = scratch_folder("tga-psd-short");
    const auto bytes_of = [](const std::string& hex) {
        std::string bytes;
        for (std::size_t i = 0; i + 1 < hex.size(); i += 2) bytes += char(std::stoi(hex.substr(i, 2), nullptr, 16));
        return bytes;
    };
    struct File {
        std::string name, whole, huge;  // the file, and its header claiming 16000 x 16000 (3e80 hex)
        std::size_t needed_huge;
        const char* kind;
    };
    const std::string psd_start = "3842505300010000000000000003";  // 8BPS, version 1, 6 reserved bytes, 3 channels
    const File files[] = {
        // Uncompressed 24-bit, 2 x 2 (BGR texels): 18 + 12 bytes; 18 + 16000^2 x 3.
        {"raw.tga", bytes_of("000002" "000000000000000000" "02000200" "1800" "0a141e" "0a141e" "0a141e" "0a141e"),
         bytes_of("000002" "000000000000000000" "803e803e" "1800" "0a141e"), 768000018, "TGA"},
        // Run-length 24-bit, 4 x 2: one packet repeating one texel 8 times, 18 + 4 bytes;
        // 18 + 16000^2 / 128 packets of 4 bytes.
        {"rle.tga", bytes_of("00000a" "000000000000000000" "04000200" "1800" "87" "0a141e"),
         bytes_of("00000a" "000000000000000000" "803e803e" "1800" "87" "0a141e"), 8000018, "run-length TGA"},
        // Photoshop, 3 channels of 8 bits, RGB, three empty sections, raw: 26 + 12 + 2 + 12 bytes;
        // 40 + 3 x 16000^2.
        {"raw.psd", bytes_of(psd_start + "00000002" "00000002" "0008" "0003" "00000000" "00000000" "00000000" "0000" "1e1e1e1e" "14141414" "0a0a0a0a"),
         bytes_of(psd_start + "00003e80" "00003e80" "0008" "0003" "00000000" "00000000" "00000000" "0000" "1e1e1e1e"), 768000040,
         "Photoshop image"},
        // Run-length: 40 bytes, a 2-byte count per row of each channel (12), then per channel
        // one run repeating a value 4 times (fd = -3: 257 - 253 = 4), 2 bytes: 58 bytes;
        // 40 + 16000 x 3 x 2 + 3 x 16000^2 / 128 runs of 2 bytes.
        {"rle.psd", bytes_of(psd_start + "00000002" "00000002" "0008" "0003" "00000000" "00000000" "00000000" "0001" "000200020002000200020002" "fd1e" "fd14" "fd0a"),
         bytes_of(psd_start + "00003e80" "00003e80" "0008" "0003" "00000000" "00000000" "00000000" "0001" "fd1e"), 12096040,
         "run-length Photoshop image"},
    };
    const auto render_with = [&](const std::string& name, const std::string& bytes) { return render_texture_file(dir, name, bytes); };
    for (const File& f : files) {
        CAPTURE(f.name);
        // Whole: it reads, every texel (30, 20, 10) / 255 (TGA stores blue first).
        RunResult r = render_with(f.name, f.whole);
        CAPTURE(r.output);
        CHECK(r.exit_code == 0);
        const texr::Image image = texr::load_image(dir + "/" + f.name, texr::ColorSpace::linear);
        CHECK(image.texel(0, 0) == texr::Color4(30 / 255.0f, 20 / 255.0f, 10 / 255.0f, 1.0f));
        CHECK(image.texel(image.width() - 1, image.height() - 1) == texr::Color4(30 / 255.0f, 20 / 255.0f, 10 / 255.0f, 1.0f));
        std::remove((dir + "/out.png").c_str());
        // One byte short.
        r = render_with(f.name, f.whole.substr(0, f.whole.size() - 1));
        CHECK(r.exit_code == 1);
        CHECK(r.output.find(f.name + ": not a readable image: the file is cut short (a " + std::to_string(image.width()) + " x " +
                            std::to_string(image.height()) + " " + f.kind + " needs at least " + std::to_string(f.whole.size()) +
                            " bytes, the file holds " + std::to_string(f.whole.size() - 1) + ")") != std::string::npos);
        // 16000 x 16000 claimed.
        r = render_with(f.name, f.huge);
        CHECK(r.exit_code == 1);
        CHECK(r.output.find(f.name + ": not a readable image: the file is cut short (a 16000 x 16000 " + f.kind + " needs at least " +
                            std::to_string(f.needed_huge) + " bytes, the file holds " + std::to_string(f.huge.size()) + ")") != std::string::npos);
        // A TGA header cut short (its last byte, the descriptor, missing) reads as if a zero
        // followed, as stb_image reads it (found by fuzzing: 17 bytes took 15 s and 2 GB).
        if (f.name.find(".tga") != std::string::npos) {
            r = render_with(f.name, f.huge.substr(0, 17));
            CHECK(r.exit_code == 1);
            CHECK(r.output.find(f.name + ": not a readable image: the file is cut short (a 16000 x 16000 " + f.kind + " needs at least " +
                                std::to_string(f.needed_huge) + " bytes, the file holds 17)") != std::string::npos);
        }
        CHECK_FALSE(file_exists(dir + "/out.png"));
    }
    // An empty file (the header checks read no byte of it: UBSan saw a null pointer there).
    RunResult r = render_with("empty.tga", "");
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("empty.tga: not a readable image: not a format stb_image reads") != std::string::npos);
    // A Photoshop header of no channels (the channel count, bytes 12 and 13, set to 0).
    std::string none = files[2].whole;
    none[12] = none[13] = 0;
    r = render_with("none.psd", none);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("none.psd: not a readable image: the Photoshop image has no channels") != std::string::npos);
}

TEST_CASE("a texture read from a pipe renders as the same file does") {
    // A pipe can be read once: the loader read the format through one open and decoded
    // through another, which waited for a second writer for ever (`timeout` turns such a wait
    // into a failure). Now the file is read once, and decoded from memory.
    const std::string dir = scratch_folder("texture-pipe");
    std::system(("cp " + source_path("models/textures/checker.png") + " " + dir + "/file.png && mkfifo " + dir + "/pipe.png").c_str());
    for (const std::string name : {"file", "pipe"})
        write_text(dir + "/" + name + ".txt", "size 32 24\ncamera eye 0 0 3\ntexture t file " + name +
                                                  ".png filter bilinear\nmaterial m texture t\n"
                                                  "quad material m v -1 -1 0 0 0 v 1 -1 0 1 0 v 1 1 0 1 1 v -1 1 0 0 1\n");
    REQUIRE(run_texr("render " + dir + "/file.txt -o " + dir + "/file.ppm").exit_code == 0);
    const std::string piped = "cat " + dir + "/file.png > " + dir + "/pipe.png & timeout 20 " + TEXR_BINARY + " render " + dir +
                              "/pipe.txt -o " + dir + "/pipe.ppm > /dev/null 2>&1";
    CHECK(std::system(piped.c_str()) == 0);
    CHECK(read_file(dir + "/file.ppm").size() > 32 * 24 * 3);
    CHECK(read_file(dir + "/pipe.ppm") == read_file(dir + "/file.ppm"));
}

TEST_CASE("texr explain measures a node-registered texture's footprint in spacings between nodes") {
    // A 5x5 node texture (nodes at u = 0, 1/4, ..., 1) on a square filling a 16x16 frame with
    // u and v from 0 to 2: 1/8 per pixel, half a node spacing, so lambda = log2(1/2) = -1
    // (measured in n = 5 texels it would be log2(5/8) = -0.678). With u and v to 16: 1 per
    // pixel, 4 node spacings, lambda = 2: trilinear on level 2 (node levels of 5, 3, 2, 1
    // nodes) and level 3 with weight 0; the anisotropic ellipse 4 by 4 node spacings.
    const std::string dir = scratch_folder("explain-node");
    const std::vector<unsigned char> pixels(5 * 5 * 3, 128);
    REQUIRE(stbi_write_png((dir + "/t.png").c_str(), 5, 5, 3, pixels.data(), 5 * 3));
    const auto explain = [&](const std::string& filter, double top) {
        const std::string t = std::to_string(top);
        write_text(dir + "/scene.txt", "size 16 16\ncamera eye 0 0 1 target 0 0 0 fov 90\ntexture t file t.png registration node filter " +
                                           filter + "\nmaterial m texture t\nquad material m v -1 -1 0 0 0 v 1 -1 0 " + t + " 0 v 1 1 0 " + t +
                                           " " + t + " v -1 1 0 0 " + t + "\n");
        const RunResult r = run_texr("explain " + dir + "/scene.txt 5 9");
        CHECK(r.exit_code == 0);
        return r.output;
    };
    std::string out = explain("trilinear", 2.0);
    CAPTURE(out);
    CHECK(out.find("|d(u,v)/dx| = 0.5 texels, |d(u,v)/dy| = 0.5 texels (spacings between nodes)") != std::string::npos);
    CHECK(out.find("lambda = log2(max of the two) = -1.0000 (magnified or 1:1)") != std::string::npos);
    out = explain("trilinear", 16.0);
    CHECK(out.find("lambda = log2(max of the two) = 2.0000 (minified)") != std::string::npos);
    CHECK(out.find("bilinear on level 2 (2x2) and level 3 (1x1), blended 0.0000 of the way") != std::string::npos);
    out = explain("anisotropic", 16.0);
    CHECK(out.find("major 4, minor 4 texels") != std::string::npos);
}

TEST_CASE("texr render refuses to write its frame over a file the scene reads, by any name, and changes nothing") {
    const std::string dir = scratch_folder("output-is-input");
    // A 2x2 PPM texture, a .mtl's map_Kd image, and the scene file itself, each named as the
    // output: directly, through a symbolic link, and through another path to it.
    const std::string ppm = std::string("P6\n2 2\n255\n") + std::string(12, '\x80');
    write_text(dir + "/t.ppm", ppm);
    write_text(dir + "/m.ppm", ppm);
    write_text(dir + "/t.obj", "mtllib t.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl paint\nf 1/1 2/2 3/3\n");
    write_text(dir + "/t.mtl", "newmtl paint\nKd 1 1 1\nmap_Kd m.ppm\n");
    // (and an OBJ file and its .mtl named as frames could be: texr reads any name)
    write_text(dir + "/o.ppm", "mtllib l.ppm\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nusemtl green\nf 1 2 3\n");
    write_text(dir + "/l.ppm", "newmtl green\nKd 0 1 0\n");
    const std::string scene = "size 8 8\ncamera eye 0 0 3\ntexture t file t.ppm\nmaterial m texture t\n"
                              "triangle material m v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1\nmesh t.obj\nmesh o.ppm\n";
    write_text(dir + "/scene.ppm", scene);  // (a scene file may have any name)
    std::system(("ln -s t.ppm '" + dir + "/link.ppm'").c_str());
    struct Case {
        std::string output, read;
    };
    const Case cases[] = {{dir + "/t.ppm", dir + "/t.ppm"}, {dir + "/link.ppm", dir + "/t.ppm"},
                          {dir + "/../" + dir + "/t.ppm", dir + "/t.ppm"}, {dir + "/m.ppm", dir + "/m.ppm"},
                          {dir + "/scene.ppm", dir + "/scene.ppm"}, {dir + "/o.ppm", dir + "/o.ppm"},
                          {dir + "/l.ppm", dir + "/l.ppm"}};
    for (const Case& c : cases) {
        const RunResult r = run_texr("render " + dir + "/scene.ppm -o " + c.output);
        CAPTURE(c.output);
        CAPTURE(r.output);
        CHECK(r.exit_code == 1);
        CHECK(r.output == "texr: " + c.output + ": cannot write output file: the scene reads it (" + c.read + "); give another -o\n");
    }
    CHECK(read_file(dir + "/t.ppm") == ppm);
    CHECK(read_file(dir + "/m.ppm") == ppm);
    CHECK(read_file(dir + "/scene.ppm") == scene);
    // Another file, new or old, is written as always.
    write_text(dir + "/old.ppm", ppm);
    CHECK(run_texr("render " + dir + "/scene.ppm -o " + dir + "/old.ppm").exit_code == 0);
    CHECK(read_file(dir + "/old.ppm") != ppm);
    CHECK(run_texr("render " + dir + "/scene.ppm -o " + dir + "/new.ppm").exit_code == 0);
}

TEST_CASE("options take their value after '=' too, and lost standard output is an error") {
    const std::string dir = scratch_folder("option-equals");
    write_text(dir + "/scene.txt", "size 8 8\ncamera eye 0 0 3\ntriangle v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1\n");
    RunResult r = run_texr("render " + dir + "/scene.txt --output=" + dir + "/a.png --threads=2 --size=4x2");
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("wrote " + dir + "/a.png (4x2)") != std::string::npos);
    for (const std::string flag : {"--stats", "--help"}) {  // a flag takes no value
        r = run_texr("render " + dir + "/scene.txt " + flag + "=1");
        CHECK(r.exit_code == 2);
        CHECK(r.output == "texr: " + flag + " takes no value (give it as '" + flag + "')\n");
    }
    r = run_texr("render " + dir + "/scene.txt --frobnicate=1");
    CHECK(r.output == "texr: unknown option '--frobnicate=1' for 'texr render'\n");
    r = run_texr("render " + dir + "/scene.txt --threads=0");  // the value is checked as ever
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("--threads") != std::string::npos);
    r = run_texr("explain " + dir + "/scene.txt 4 4 --span=exact");
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("The span walk (--span exact) divides") != std::string::npos);
    if (!file_exists("/dev/full")) {
        MESSAGE("no /dev/full here: the lost-output check is skipped");
        return;
    }
    // Standard output to a full device: the explanation is lost, and texr says so and fails.
    // (Standard error goes to the pipe first, then standard output to /dev/full.)
    for (const std::string& command : {"explain " + dir + "/scene.txt 4 4", std::string("--help")}) {
        r = run_texr(command + " 2>&1 >/dev/full; echo exit $?");
        CAPTURE(command);
        CHECK(r.output == "texr: could not write to standard output: No space left on device\nexit 1\n");
    }
}

TEST_CASE("a zero camera up vector and a number with a no-break space get messages that say so") {
    const std::string dir = scratch_folder("up-and-nbsp");
    write_text(dir + "/up.txt", "size 8 8\ncamera eye 0 0 3 up 0 0 0\ntriangle v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1\n");
    RunResult r = run_texr("render " + dir + "/up.txt -o " + dir + "/a.png");
    CHECK(r.exit_code == 1);
    CHECK(r.output == "texr: " + dir + "/up.txt:2: camera up must not be the zero vector\n");
    write_text(dir + "/nbsp.txt", "size 8\xC2\xA0 8\ncamera eye 0 0 3\ntriangle v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1\n");
    r = run_texr("render " + dir + "/nbsp.txt -o " + dir + "/a.png");
    CHECK(r.exit_code == 1);
    CHECK(r.output == "texr: " + dir + "/nbsp.txt:1: expected the width, found '8\\xC2\\xA0'\n");
    CHECK_FALSE(file_exists(dir + "/a.png"));
}

TEST_CASE("words a message quotes from a scene or OBJ file show control bytes as \\xNN and are cut after 64 bytes") {
    const std::string dir = scratch_folder("shown-words");
    const std::string triangle = "triangle v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0 1";
    // A terminal's escape codes (colour, clear screen) and bytes that are not UTF-8.
    write_text(dir + "/esc.txt", "camera eye 0 0 3\n\x1b[31mfoo\n" + triangle + "\n");
    RunResult r = run_texr("render " + dir + "/esc.txt -o " + dir + "/a.png");
    CHECK(r.exit_code == 1);
    CHECK(r.output.rfind("texr: " + dir + "/esc.txt:2: unknown command '\\x1B[31mfoo' (expected ", 0) == 0);
    write_text(dir + "/esc.txt", "camera eye 0 0 3\n" + triangle + " material m\x1b[2J\xff\n");
    r = run_texr("render " + dir + "/esc.txt -o " + dir + "/a.png");
    CHECK(r.output.rfind("texr: " + dir + "/esc.txt:2: unknown material 'm\\x1B[2J\\xFF' (define it", 0) == 0);
    // A long word: its first 64 bytes, then "...".
    const std::string name(3000, 'm');
    write_text(dir + "/long.txt", "camera eye 0 0 3\n" + triangle + " material " + name + "\n");
    r = run_texr("render " + dir + "/long.txt -o " + dir + "/a.png");
    CHECK(r.output == "texr: " + dir + "/long.txt:2: unknown material '" + name.substr(0, 64) +
                          "...' (define it with a 'material' line first)\n");
    write_text(dir + "/t.obj", "v 0 0 1\nv 1 0 " + std::string(100, '7') + "x\nv 0 1 0\nf 1 2 3\n");
    write_text(dir + "/obj.txt", "camera eye 0 0 3\nmesh t.obj\n");
    r = run_texr("render " + dir + "/obj.txt -o " + dir + "/a.png");
    CHECK(r.output == "texr: " + dir + "/obj.txt:2: " + dir + "/t.obj:2: expected a number after 'v', got '" + std::string(64, '7') + "...'\n");
    CHECK_FALSE(file_exists(dir + "/a.png"));
    // A word of exactly 64 bytes is shown whole.
    write_text(dir + "/long.txt", "camera eye 0 0 3\n" + triangle + " material " + name.substr(0, 64) + "\n");
    r = run_texr("render " + dir + "/long.txt -o " + dir + "/a.png");
    CHECK(r.output == "texr: " + dir + "/long.txt:2: unknown material '" + name.substr(0, 64) + "' (define it with a 'material' line first)\n");
    // Names keep their UTF-8 characters; control bytes (C0 and C1) and bytes that are not
    // UTF-8 are escaped; keywords and numbers escape every byte that is not ASCII.
    write_text(dir + "/utf8.txt", "camera eye 0 0 3\n" + triangle + " material gr\xC3\xBCn\xC2\x9B\xC3\n");
    r = run_texr("render " + dir + "/utf8.txt -o " + dir + "/a.png");
    CHECK(r.output.rfind("texr: " + dir + "/utf8.txt:2: unknown material 'gr\xC3\xBCn\\xC2\\x9B\\xC3' (define it", 0) == 0);
    write_text(dir + "/utf8.txt", "camera eye 0 0 3\n" + triangle + " gr\xC3\xBCn\n");
    r = run_texr("render " + dir + "/utf8.txt -o " + dir + "/a.png");
    CHECK(r.output.rfind("texr: " + dir + "/utf8.txt:2: unknown triangle option 'gr\\xC3\\xBCn' (expected", 0) == 0);
    // Paths: control bytes escaped, UTF-8 kept, wherever a message names the file.
    write_text(dir + "/path.txt", "camera eye 0 0 3\nmesh \"a\x1b[2J\xC3\xA9.obj\"\n");
    r = run_texr("render " + dir + "/path.txt -o " + dir + "/a.png");
    CHECK(r.output == "texr: " + dir + "/path.txt:2: " + dir + "/a\\x1B[2J\xC3\xA9.obj: cannot open OBJ file\n");
    write_text(dir + "/t.obj", "mtllib a\x1b[31m.mtl\nv 0 0 1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    r = run_texr("render " + dir + "/obj.txt -o " + dir + "/a.png");
    CHECK(r.output == "texr: " + dir + "/obj.txt:2: " + dir + "/t.obj:1: mtllib: cannot open " + dir + "/a\\x1B[31m.mtl\n");
    // texr explain names a material the same way.
    write_text(dir + "/named.txt", "camera eye 0 0 3\nmaterial m\x1b[2J color 1 0 0\n" + triangle + " material m\x1b[2J\n");
    r = run_texr("explain " + dir + "/named.txt 320 240");
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("material 'm\\x1B[2J'") != std::string::npos);
    CHECK(r.output.find('\x1b') == std::string::npos);
    // And --stats, in its table of materials.
    r = run_texr("render " + dir + "/named.txt -o " + dir + "/a.png --stats");
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("material m\\x1B[2J") != std::string::npos);
    CHECK(r.output.find('\x1b') == std::string::npos);
}

TEST_CASE("a map_Kd line with texture options is refused at its .mtl line, as texr would draw the image without them") {
    const std::string dir = scratch_folder("mapkd-options");
    write_text(dir + "/t.obj", "mtllib t.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl paint\nf 1/1 2/2 3/3\n");
    write_text(dir + "/t.ppm", std::string("P6\n2 2\n255\n") + std::string(12, '\x80'));
    write_text(dir + "/scene.txt", "size 8 8\ncamera eye 0 0 3\nmesh t.obj\n");
    for (const std::string option : {"-s 2 2 1", "-o 0.5 0 0", "-clamp on", "-bm 1"}) {
        write_text(dir + "/t.mtl", "newmtl paint\nKd 1 1 1\nmap_Kd " + option + " t.ppm\n");
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CAPTURE(option);
        CAPTURE(r.output);
        CHECK(r.exit_code == 1);
        CHECK(r.output.find(dir + "/t.mtl:3: map_Kd option '" + option.substr(0, option.find(' ')) + "' is not supported") != std::string::npos);
        CHECK_FALSE(file_exists(dir + "/out.png"));
    }
    // Without options, and with file names holding or starting with a hyphen, it is read.
    for (const std::string name : {"t-1.ppm", "-grid.ppm"}) {
        write_text(dir + "/" + name, std::string("P6\n2 2\n255\n") + std::string(12, '\x80'));
        write_text(dir + "/t.mtl", "newmtl paint\nKd 1 1 1\nmap_Kd " + name + "\n");
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CAPTURE(r.output);
        CHECK(r.exit_code == 0);
    }
}

TEST_CASE("writing through a named temporary file: the same result, and a signal removes the file") {
    // write_file_atomically's fallback where the file system has no unnamed files.
    const std::string dir = scratch_folder("named-temporary");
    const auto temporaries = [&] { return temporary_files(dir); };
    const std::string path = dir + "/data.bin";
    write_text(path, "old");
    REQUIRE(::chmod(path.c_str(), 0640) == 0);
    const std::vector<std::uint8_t> bytes = {1, 2, 3, 0, 255};
    texr::write_file_atomically(path, bytes, texr::TemporaryFile::named);
    CHECK(read_file(path) == std::string("\x01\x02\x03\x00\xff", 5));
    struct stat info;
    REQUIRE(::stat(path.c_str(), &info) == 0);
    CHECK((info.st_mode & 0777) == 0640);
    CHECK(temporaries() == 0);
    // A process writing 64 MiB gets SIGHUP once its temporary file shows up; where that
    // stopped it before the rename, the file must be gone. A round that misses the write is
    // run again, up to 8 times. (SIGHUP: the test runner catches SIGTERM and SIGINT itself,
    // and the handler is installed only where a signal's action is the default.)
    const std::vector<std::uint8_t> large(std::size_t(64) << 20, 7);  // (made before the fork)
    bool stopped_while_writing = false;
    for (int round = 0; round < 8 && !stopped_while_writing; ++round) {
        std::remove(path.c_str());
        const pid_t child = ::fork();
        REQUIRE(child >= 0);
        if (child == 0) {
            default_signal_action(SIGHUP);  // (whatever the test runner's was)
            texr::remove_partial_outputs_on_signals();
            try {
                texr::write_file_atomically(path, large, texr::TemporaryFile::named);
            } catch (...) {
                ::_exit(1);
            }
            ::_exit(0);
        }
        const auto [status, seen] = wait_stopping_write(child, SIGHUP, [&] { return temporaries() > 0; });
        stopped_while_writing = seen && WIFSIGNALED(status) && WTERMSIG(status) == SIGHUP && !file_exists(path);
        if (stopped_while_writing) CHECK(temporaries() == 0);
    }
    CHECK(stopped_while_writing);
}

TEST_CASE("temporary names that files left by an earlier process take are passed over") {
    // An earlier texr with the same process number, stopped by SIGKILL while it wrote through
    // a named temporary file, left .texr-PID-0.tmp and .texr-PID-1.tmp: a render with that
    // number (the child below, before and after exec) names its file .texr-PID-2.tmp, writes
    // its frame, and leaves the two files as they are (they are not its own).
    const std::string dir = scratch_folder("stale-temporary");
    write_text(dir + "/scene.txt", good_scene);
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        for (const char* number : {"0", "1"})
            std::ofstream(dir + "/.texr-" + std::to_string(::getpid()) + "-" + number + ".tmp") << "stale";
        const int null = ::open("/dev/null", O_WRONLY);
        ::dup2(null, 1), ::dup2(null, 2);
        ::execl(TEXR_BINARY, TEXR_BINARY, "render", (dir + "/scene.txt").c_str(), "-o", (dir + "/frame.png").c_str(),
                static_cast<char*>(nullptr));
        ::_exit(127);
    }
    int status = 0;
    REQUIRE(::waitpid(child, &status, 0) == child);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
    CHECK(read_file(dir + "/frame.png").substr(0, 8) == "\x89PNG\r\n\x1a\n");
    CHECK(temporary_files(dir) == 2);
    for (const char* number : {"0", "1"}) CHECK(read_file(dir + "/.texr-" + std::to_string(child) + "-" + number + ".tmp") == "stale");
}

TEST_CASE("a render stopped by a signal while it writes its frame leaves no partial file behind") {
    // texr render writes a 48 MiB frame through a temporary file in the frame's folder: one
    // with no name (O_TMPFILE) where the file system allows it, as here, else a hidden one. As
    // soon as the render has that file open, it gets SIGKILL (then, in later rounds, SIGTERM
    // and SIGINT). Where it was stopped before the rename (killed by the signal, no frame
    // written), no temporary file may be left in the folder. The write takes a few tens of
    // milliseconds; a round that misses it (the render done first) is run again, up to 8 times.
    const std::string dir = scratch_folder("signal-partial");
    write_text(dir + "/empty.scene", "size 4 4\nbackground 0.2 0.4 0.6\ntriangle v -1 -1 -5 0 0 v 1 -1 -5 1 0 v 0 1 -5 0 1\n");
    char absolute[PATH_MAX];
    REQUIRE(::realpath(dir.c_str(), absolute) != nullptr);
    const std::string folder = absolute;
    // The temporary files in the folder (removed, with remove = true: one a round left behind
    // has been reported, and must not be taken for the next round's).
    const auto temporaries = [&](bool remove = false) { return temporary_files(dir, remove); };
    // Whether process `pid` is writing its temporary file: a named one is in the folder; an
    // unnamed one shows in /proc as "FOLDER/#INODE (deleted)".
    const auto writing = [&](pid_t pid) {
        bool found = false;
        const std::string fds = "/proc/" + std::to_string(pid) + "/fd";
        if (DIR* listing = ::opendir(fds.c_str())) {
            while (const dirent* entry = ::readdir(listing)) {
                char target[PATH_MAX + 1];
                const ssize_t n = ::readlink((fds + "/" + entry->d_name).c_str(), target, PATH_MAX);
                const std::string name(target, std::size_t(n > 0 ? n : 0));
                const std::string deleted = " (deleted)";  // (the scene file, in the folder too, is not it)
                if (name.rfind(folder + "/", 0) == 0 && name.size() > deleted.size() &&
                    name.compare(name.size() - deleted.size(), deleted.size(), deleted) == 0)
                    found = true;
            }
            ::closedir(listing);
        }
        return found || temporaries() > 0;
    };
    // Starts texr render writing `frame` (with file_size_limit > 0, under that limit; with
    // ignore_size_signal, SIGXFSZ ignored, so that the write fails instead, over a previous
    // frame, and texr's messages go to log.txt): its pid.
    const std::string frame = dir + "/frame.ppm", log = dir + "/log.txt";
    const auto start_render = [&](rlim_t file_size_limit, bool ignore_size_signal = false) {
        if (ignore_size_signal)
            write_text(frame, "previous frame");
        else
            std::remove(frame.c_str());
        temporaries(true);
        const pid_t child = ::fork();
        REQUIRE(child >= 0);
        if (child == 0) {
            // (not freopen: it would flush the parent's buffered output)
            const int out = ignore_size_signal ? ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644) : ::open("/dev/null", O_WRONLY);
            ::dup2(out, 1), ::dup2(out, 2);
            const rlimit limit{file_size_limit, file_size_limit};
            if (file_size_limit > 0) ::setrlimit(RLIMIT_FSIZE, &limit);
            for (const int s : {SIGTERM, SIGINT, SIGXFSZ}) default_signal_action(s);  // (whatever the test runner's were)
            if (ignore_size_signal) ::signal(SIGXFSZ, SIG_IGN);
            ::execl(TEXR_BINARY, TEXR_BINARY, "render", (dir + "/empty.scene").c_str(), "--size", "4096x4096", "-o", frame.c_str(),
                    static_cast<char*>(nullptr));
            ::_exit(127);
        }
        return child;
    };
    // SIGKILL leaves nothing only where the file system has unnamed files (not NFS, say).
    const int probe = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600);
    if (probe >= 0) ::close(probe);
    if (probe < 0) MESSAGE("no unnamed files in " << folder << " (" << std::strerror(errno) << "): the SIGKILL round is skipped");
    for (const int signal_number : {SIGKILL, SIGTERM, SIGINT}) {
        if (signal_number == SIGKILL && probe < 0) continue;
        CAPTURE(signal_number);
        bool stopped_while_writing = false;
        for (int round = 0; round < 8 && !stopped_while_writing; ++round) {
            const pid_t child = start_render(0);
            const auto [status, seen] = wait_stopping_write(child, signal_number, [&] { return writing(child); });
            stopped_while_writing = seen && WIFSIGNALED(status) && WTERMSIG(status) == signal_number && !file_exists(frame);
            if (stopped_while_writing) CHECK(temporaries() == 0);
        }
        CHECK(stopped_while_writing);
    }
    // A file size limit of 1 MiB stops the same write with SIGXFSZ, at the limit: every time.
    const pid_t child = start_render(1 << 20);
    int status = 0;
    REQUIRE(::waitpid(child, &status, 0) == child);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == SIGXFSZ);
    CHECK_FALSE(file_exists(frame));
    CHECK(temporaries() == 0);
    // With SIGXFSZ ignored, the write fails at the limit instead: texr says why, and leaves
    // the previous frame as it was.
    const pid_t failing = start_render(1 << 20, true);
    REQUIRE(::waitpid(failing, &status, 0) == failing);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 1);
    CHECK(read_file(log) == "texr: " + frame + ": cannot write output file: " + std::strerror(EFBIG) + "\n");
    CHECK(read_file(frame) == "previous frame");
    CHECK(temporaries() == 0);
}

TEST_CASE("texr compare: the same pixels, differences worked out by hand, tolerance, sizes and errors") {
    const std::string dir = scratch_folder("compare");
    // 2x2 PPMs, rows from the top. B differs from A at pixel (1, 0) (top row, right) by +3
    // in red and at (0, 1) by -1 in blue: 2 of 4 pixels differ, by at most 3; the mean
    // difference is (3 + 1) / 12 channels = 0.3333; MSE (9 + 1) / 12, PSNR
    // 10 log10(255^2 * 12 / 10) = 48.92 dB.
    const auto ppm = [&](const std::string& name, const std::string& pixels) {
        write_text(dir + "/" + name, "P6\n2 2\n255\n" + pixels);
        return dir + "/" + name;
    };
    const std::string a = ppm("a.ppm", "\x0a\x14\x1e\x0a\x14\x1e\x0a\x14\x1e\x0a\x14\x1e");
    const std::string b = ppm("b.ppm", std::string("\x0a\x14\x1e\x0d\x14\x1e\x0a\x14\x1d\x0a\x14\x1e", 12));
    RunResult r = run_texr("compare " + a + " " + b);
    CHECK(r.exit_code == 1);
    CHECK(r.output == "2x2: 2 of 4 pixels differ, by at most 3 of 255 (first at pixel (1, 0)); mean difference 0.3333 a channel, "
                      "PSNR 48.92 dB\n");
    r = run_texr("compare " + a + " " + b + " --max-diff 3");
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("PSNR 48.92 dB, within --max-diff 3\n") != std::string::npos);
    CHECK(run_texr("compare " + a + " " + b + " --max-diff=2").exit_code == 1);
    CHECK(run_texr("compare " + a + " " + b + " --max-diff 0003").exit_code == 0);  // (leading zeros)
    // Standard output that fails is trouble (2), not "they differ" (1).
    CHECK(std::system((std::string(TEXR_BINARY) + " compare " + a + " " + a + " > /dev/full 2>/dev/null; test $? -eq 2").c_str()) == 0);
    // The same pixels as a PNG (whose rows stb_image_write takes from the top) match the PPM.
    const std::string b_png = dir + "/b.png";
    REQUIRE(stbi_write_png(b_png.c_str(), 2, 2, 3, "\x0a\x14\x1e\x0d\x14\x1e\x0a\x14\x1d\x0a\x14\x1e", 6) != 0);
    r = run_texr("compare " + b_png + " " + b);
    CHECK(r.exit_code == 0);
    CHECK(r.output == "2x2: the same pixels\n");
    // Sizes that differ; images that cannot be read; bad command lines.
    const std::string wide = dir + "/wide.ppm";
    write_text(wide, "P6\n3 2\n255\n" + std::string(18, 'x'));
    r = run_texr("compare " + a + " " + wide);
    CHECK(r.exit_code == 1);
    CHECK(r.output == "sizes differ: 2x2 against 3x2\n");
    const float hdr_texels[3] = {1.0f, 2.0f, 3.0f};
    REQUIRE(stbi_write_hdr((dir + "/one.hdr").c_str(), 1, 1, 3, hdr_texels) != 0);
    // A 1x1 PNG of 16-bit grey: signature, IHDR (depth 16, colour type 0), IDAT (a zlib
    // stream of the row: filter 0, then 0x1234), IEND; the CRCs worked out by zlib's crc32.
    const auto chunk = [](const std::string& type, const std::string& data) {
        std::string out;
        for (const int shift : {24, 16, 8, 0}) out += char((data.size() >> shift) & 0xff);
        const std::string body = type + data;
        const unsigned long crc = ::crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size()));
        out += body;
        for (const int shift : {24, 16, 8, 0}) out += char((crc >> shift) & 0xff);
        return out;
    };
    const std::string row("\x00\x12\x34", 3);
    std::string packed(64, '\0');
    uLongf packed_size = uLongf(packed.size());
    REQUIRE(::compress(reinterpret_cast<Bytef*>(packed.data()), &packed_size, reinterpret_cast<const Bytef*>(row.data()), uLong(row.size())) == Z_OK);
    packed.resize(packed_size);
    write_text(dir + "/deep.png", std::string("\x89PNG\r\n\x1a\n", 8) +
                                      chunk("IHDR", std::string("\0\0\0\x01\0\0\0\x01\x10\0\0\0\0", 13)) + chunk("IDAT", packed) +
                                      chunk("IEND", ""));
    for (const auto& [arguments, message] : std::vector<std::pair<std::string, std::string>>{
             {a + " " + dir + "/missing.png", dir + "/missing.png: cannot open image file"},
             {dir + "/one.hdr " + a, dir + "/one.hdr: a Radiance HDR image: texr compare reads 8-bit images"},
             {a + " " + dir + "/deep.png", dir + "/deep.png: an image of 16 bits a channel: texr compare reads 8-bit images"},
             {a, "texr compare needs two images A B (try texr compare --help)"},
             {a + " " + b + " " + a, "texr compare takes two images A B; '" + a + "' is one too many"},
             {a + " " + b + " --max-diff 256", "--max-diff expects a whole number from 0 to 255, got '256'"},
             {a + " " + b + " --max-diff 1 --max-diff 2", "--max-diff given twice"},
             {a + " " + b + " --quiet", "unknown option '--quiet' for 'texr compare'"},
         }) {
        r = run_texr("compare " + arguments);
        CAPTURE(arguments);
        CHECK(r.exit_code == 2);
        CHECK(r.output == "texr: " + message + "\n");
    }
    CHECK(run_texr("compare --help").output.find("exit status: 0 the images match") != std::string::npos);
}

TEST_CASE("a file whose name starts with '-' is given after --, and a single-dash word that is no option says so") {
    const std::string dir = scratch_folder("dash-names");
    write_text(dir + "/-s.scene", good_scene);
    // Run in the folder, so that the names start with '-' as typed.
    RunResult r = run_texr_in(dir, "render ./-s.scene -o reference.ppm");
    REQUIRE(r.exit_code == 0);
    r = run_texr_in(dir, "render -- -s.scene -o out.ppm");  // (after --, -o is a second name)
    CHECK(r.exit_code == 2);
    CHECK(r.output == "texr: texr render takes one scene file; '-o' is one too many\n");
    r = run_texr_in(dir, "render -o -o.ppm -- -s.scene");
    CHECK(r.exit_code == 0);
    CHECK(read_file(dir + "/-o.ppm") == read_file(dir + "/reference.ppm"));
    r = run_texr_in(dir, "render --output=-d.ppm -- -s.scene");
    CHECK(r.exit_code == 0);
    CHECK(read_file(dir + "/-d.ppm") == read_file(dir + "/reference.ppm"));
    // Without --: an option texr does not know, and how to name the file.
    r = run_texr_in(dir, "render -s.scene -o out.ppm");
    CHECK(r.exit_code == 2);
    CHECK(r.output == "texr: unknown option '-s.scene' for 'texr render' (a file of that name: put -- before it, or write it as './-s.scene')\n");
    CHECK(!file_exists(dir + "/out.ppm"));
    // A long option that is not one gets no such hint.
    r = run_texr_in(dir, "render ./-s.scene --fast");
    CHECK(r.output == "texr: unknown option '--fast' for 'texr render'\n");
    // After --, --help and --name=value are names too.
    for (const std::string name : {"--help", "--size=4x4"}) {
        r = run_texr_in(dir, "render -o out.ppm -- " + name);
        CAPTURE(name);
        CHECK(r.exit_code == 1);
        CHECK(r.output.find("texr: " + name + ": ") == 0);
        CHECK(r.output.find("usage:") == std::string::npos);
    }
    CHECK(!file_exists(dir + "/out.ppm"));
    // texr explain: SCENE X Y after --; a negative X is a coordinate either way.
    r = run_texr_in(dir, "explain -- -s.scene 16 12");
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("pixel (16, 12)") == 0);
    r = run_texr_in(dir, "explain --size 8x6 -- -s.scene -1 0");
    CHECK(r.exit_code == 2);
    CHECK(r.output == "texr: X must be a pixel index from 0 to 7, got '-1'\n");
    r = run_texr_in(dir, "explain -s.scene 16 12");
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("unknown option '-s.scene' for 'texr explain' (a file of that name: put -- before it") != std::string::npos);
    // texr compare: A and B after --.
    write_text(dir + "/-a.ppm", read_file(dir + "/reference.ppm"));
    r = run_texr_in(dir, "compare --max-diff 0 -- -a.ppm reference.ppm");
    CHECK(r.exit_code == 0);
    CHECK(r.output == "32x24: the same pixels\n");
    r = run_texr_in(dir, "compare -a.ppm reference.ppm");
    CHECK(r.exit_code == 2);
    CHECK(r.output == "texr: unknown option '-a.ppm' for 'texr compare' (a file of that name: put -- before it, or write it as './-a.ppm')\n");
    r = run_texr_in(dir, "compare -- -a.ppm reference.ppm --max-diff 3");
    CHECK(r.exit_code == 2);
    CHECK(r.output == "texr: texr compare takes two images A B; '--max-diff' is one too many\n");
}

TEST_CASE("of two surfaces at the same depth the one written first shows, on any number of threads") {
    // Two copies of one triangle, unlit, in red and in blue: the first written keeps every
    // pixel (the depth test is strict), whichever colour that is.
    const std::string dir = scratch_folder("depth-ties");
    const std::string triangle = " v -1 -1 0 0 0 v 1 -1 0 1 0 v 0 1 0 0.5 1\n";
    const std::string head = "size 32 24\ncamera eye 0 0 3 target 0 0 0\nmaterial red color 1 0 0 lighting none\n"
                             "material blue color 0 0 1 lighting none\n";
    for (const bool red_first : {true, false}) {
        const std::string first = red_first ? "red" : "blue", second = red_first ? "blue" : "red";
        write_text(dir + "/s.scene", head + "triangle material " + first + triangle + "triangle material " + second + triangle);
        for (const std::string threads : {"1", "2"}) {
            CAPTURE(first);
            CAPTURE(threads);
            REQUIRE(run_texr("render " + dir + "/s.scene -o " + dir + "/o.ppm --threads " + threads).exit_code == 0);
            const std::string ppm = read_file(dir + "/o.ppm");
            const std::string header = "P6\n32 24\n255\n";
            REQUIRE(ppm.size() == header.size() + 32 * 24 * 3);
            int reds = 0, blues = 0;
            for (std::size_t i = header.size(); i < ppm.size(); i += 3) {
                const auto r = std::uint8_t(ppm[i]), g = std::uint8_t(ppm[i + 1]), b = std::uint8_t(ppm[i + 2]);
                reds += r == 255 && g == 0 && b == 0;
                blues += r == 0 && g == 0 && b == 255;
            }
            // The triangle's area, 2, times (12 / (3 tan 30 degrees))^2 = 48 pixels per unit
            // area at distance 3 in 24 rows of a 60-degree view: 96 pixels, give or take its edges.
            CHECK((red_first ? reds : blues) >= 86);
            CHECK((red_first ? reds : blues) <= 106);
            CHECK((red_first ? blues : reds) == 0);
        }
    }
}

TEST_CASE("a lecture word texr does not have yet is named as such, and a line cut short says so") {
    const std::string note = ", which texr does not have yet (docs/lecture-guide.md, \"Not in texr yet\")\n";
    for (const auto& [line, message] : std::vector<std::pair<std::string, std::string>>{
             {"cone 0 0 0 1", "unknown command 'cone' (expected size, camera, background, ambient, environment, texture, material, "
                              "light, projector, mesh, triangle, quad, billboard, sphere, cylinder or disc); 'cone' belongs to the lecture's "
                              "parametric surfaces (texr's: sphere, cylinder and disc)" + note},
             {"material m color 1 1 1 Opacity 0.5",
              "unknown material option 'Opacity' (expected color, texture, lighting, vertex_colors, bump, reflect, cutout, slope, slope_direction, lightmap, lightmap_repeat, projector, mapping, mapping_center, mapping_axis or mapping_size); 'Opacity': texr's "
              "opacity is an alpha test, a material's 'cutout THRESHOLD' (blending is not in texr; docs/scene-format.md)\n"},
             {"texture t procedural wood",
              "unknown procedural pattern 'wood' (expected one of: brick, checker, marble, noise, tile, turbulence); 'wood' belongs to "
              "the lecture's wood pattern (solid noise)" + note},
             {"texture t cubemap x.hdr",
              "unknown texture option 'cubemap' (expected file, filter, wrap, wrap_u, wrap_v, border, registration, colorspace, "
              "cubic, clamp_overshoot, max_anisotropy; or procedural, scale, color0, color1, mortar, octaves, amplitude, solid); "
              "'cubemap' belongs to the lecture's cube maps (texr's environment maps are latitude-longitude)" + note},
             {"quad normal_map 1", "unknown quad option 'normal_map' (expected v, n, c, material, cull, translate, rotate or scale); "
                                   "'normal_map' belongs to the lecture's normal mapping" + note},
             // Other words: no such note.
             {"material m shiny 1", "unknown material option 'shiny' (expected color, texture, lighting, vertex_colors, bump, reflect, cutout, slope, slope_direction, lightmap, lightmap_repeat, projector, mapping, mapping_center, mapping_axis or mapping_size)\n"},
             {"cone2 1", "unknown command 'cone2' (expected size, camera, background, ambient, environment, texture, material, "
                         "light, projector, mesh, triangle, quad, billboard, sphere, cylinder or disc)\n"},
             // A line cut short: what was expected, and that the line ended.
             {"triangle v 0 0 0 0 0 v 1 0 0 1 0 v 0 1 0 0.5 1 translate 1 2",
              "expected 3 numbers for translate after '2', found the end of the line\n"},
             {"triangle v 0 0 0 0 0 v 1 0 0 1 0 v 0 1 0 0.5 1 scale 1 2",
              "expected 1 or 3 scale factors (scale s, or scale sx sy sz) after '2', found the end of the line\n"},
             {"triangle v 0 0 0 0 0 v 1 0 0 1 0 v 0 1 0 0.5 1 scale 1 2 material red",
              "expected 1 or 3 scale factors (scale s, or scale sx sy sz), found 'material'\n"},
         }) {
        CAPTURE(line);
        const std::string dir = scratch_folder("lecture-words");
        write_text(dir + "/scene.txt", good_scene + line + "\n");
        const RunResult r = run_texr("render " + dir + "/scene.txt -o " + dir + "/out.png");
        CHECK(r.exit_code == 1);
        CHECK(r.output == "texr: " + dir + "/scene.txt:5: " + message);
        CHECK_FALSE(file_exists(dir + "/out.png"));
    }
}
