// Small helpers shared by the tests: scenes built in code, and running the texr binary.
#pragma once
#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <vector>

#include "texr/render/renderer.h"
#include "texr/scene/parser.h"
#include "texr/scene/scene.h"

namespace texr::testing {

// A scene with one camera and no objects; add_triangle adds the geometry.
inline Scene camera_scene(int width, int height, glm::dvec3 eye, glm::dvec3 target, double fov_y = 90.0,
                          double near = 0.1, double far = 100.0) {
    Scene s;
    s.width = width;
    s.height = height;
    s.camera.eye = eye;
    s.camera.target = target;
    s.camera.fov_y_degrees = fov_y;
    s.camera.near = near;
    s.camera.far = far;
    return s;
}

// Adds one triangle (own mesh and object) with the given material index.
inline void add_triangle(Scene& s, const std::array<Vertex, 3>& v, int material) {
    Mesh m;
    m.vertices.assign(v.begin(), v.end());
    m.triangles.push_back({0, 1, 2});
    m.triangle_material.push_back(material);
    m.has_uv = true;
    Object o;
    o.mesh = int(s.meshes.size());
    s.meshes.push_back(m);
    s.objects.push_back(o);
}

struct RunResult {
    int exit_code;
    std::string output;  // stdout and stderr together
};

// Runs the texr binary with the given argument string (already shell-quoted). With
// timeout_seconds, a run that takes longer is killed (exit code 124): a hang fails the test.
inline RunResult run_command(const std::string& command);
inline RunResult run_texr(const std::string& arguments, int timeout_seconds = 0) {
    const std::string limit = timeout_seconds > 0 ? "timeout " + std::to_string(timeout_seconds) + " " : "";
    return run_command(limit + std::string(TEXR_BINARY) + " " + arguments + " 2>&1");
}

// The same, run in the folder `folder` (whose name holds no single quote).
inline RunResult run_texr_in(const std::string& folder, const std::string& arguments) {
    return run_command("cd '" + folder + "' && " + std::string(TEXR_BINARY) + " " + arguments + " 2>&1");
}

// Runs a shell command, its output (the command's redirections decide which) and exit code.
inline RunResult run_command(const std::string& command) {
    RunResult r{-1, {}};
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return r;
    std::array<char, 4096> buffer{};
    std::size_t n;
    while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) r.output.append(buffer.data(), n);
    const int status = pclose(pipe);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

inline void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

inline bool file_exists(const std::string& path) { return bool(std::ifstream(path)); }

// The whole file as bytes ("" if it cannot be read).
inline std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// The pixels of a binary PPM texr wrote (RGB, rows from the top), checked to be w x h.
inline std::string ppm_pixels(const std::string& path, int w, int h) {
    const std::string ppm = read_file(path);
    const std::string header = "P6\n" + std::to_string(w) + " " + std::to_string(h) + "\n255\n";
    if (ppm.size() != header.size() + std::size_t(w) * std::size_t(h) * 3 || ppm.compare(0, header.size(), header) != 0)
        return std::string();  // (the caller's size check fails)
    return ppm.substr(header.size());
}

// The sRGB bytes texr explain says it wrote ("in the frame file as sRGB bytes (r, g, b)"),
// or -1s where the output has none.
inline std::array<int, 3> explained_bytes(const std::string& output) {
    std::array<int, 3> rgb{-1, -1, -1};
    const std::size_t at = output.rfind("in the frame file as sRGB bytes (");
    if (at != std::string::npos) std::sscanf(output.c_str() + at, "in the frame file as sRGB bytes (%d, %d, %d)", &rgb[0], &rgb[1], &rgb[2]);
    return rgb;
}

inline std::string source_path(const std::string& relative) { return std::string(TEXR_SOURCE_DIR) + "/" + relative; }

// An HDR image of w x h texels (row 0 first) whose four channels are each texel's value.
inline Image hdr_image(int w, int h, const std::vector<float>& values) {
    std::vector<float> rgba;
    for (const float t : values)
        for (int c = 0; c < 4; ++c) rgba.push_back(t);
    return Image::hdr(w, h, rgba);
}

// A scene file's text, parsed (`name` stands for its file in messages) and rendered with
// the default options.
inline Framebuffer render_scene_text(const std::string& text, const std::string& name) {
    std::istringstream in(text);
    const Scene scene = parse_scene(in, name);
    RenderStats stats;
    return render(scene, RenderOptions{}, stats);
}

// A fresh, empty folder texr-test-NAME in the working folder (ctest runs the tests in the
// build folder; .gitignore keeps any made elsewhere out of the repository).
inline std::string scratch_folder(const std::string& name) {
    const std::string path = "texr-test-" + name;
    std::system(("rm -rf '" + path + "' && mkdir -p '" + path + "'").c_str());
    return path;
}

}  // namespace texr::testing
