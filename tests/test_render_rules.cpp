// Rules of the frame checked on whole frames, each against what the rule itself says (not
// read back from the renderer): equal depth keeps the first surface drawn, and texture
// coordinates are re-based by whole periods only on axes that repeat.
#include <doctest/doctest.h>

#include <sstream>
#include <string>

#include "helpers.h"

using namespace texr;

namespace {

// A quad filling the view of "camera eye 0 0 2 fov 90" (z = 0, x and y within 3), with
// texture coordinates (u0, v0) to (u1, v1).
std::string quad(const std::string& material, double u0, double v0, double u1, double v1) {
    std::ostringstream q;
    q << "quad material " << material << " v -3 -3 0 " << u0 << ' ' << v0 << " v 3 -3 0 " << u1 << ' ' << v0 << " v 3 3 0 " << u1
      << ' ' << v1 << " v -3 3 0 " << u0 << ' ' << v1 << '\n';
    return q.str();
}

}  // namespace

TEST_CASE("two surfaces at the same depth: the one drawn first keeps every pixel, on batched and pixel-by-pixel spans") {
    // The depth test is strictly less: a second quad exactly on the first draws nothing. A
    // white quad, then a black one on it: every pixel white. 32 pixels wide, spans are
    // walked in batches; 8 wide, pixel by pixel. (Both textured with 2x2 8-bit images, which
    // take the short path; and untextured, flat white then flat black.)
    const std::string dir = testing::scratch_folder("equal-depth");
    testing::write_text(dir + "/white.ppm", std::string("P6\n2 2\n255\n") + std::string(12, char(255)));
    testing::write_text(dir + "/black.ppm", std::string("P6\n2 2\n255\n") + std::string(12, char(0)));
    for (const int size : {32, 8})
        for (const bool textured : {true, false}) {
            const std::string materials = textured ? "texture w file " + dir + "/white.ppm\ntexture b file " + dir +
                                                         "/black.ppm\nmaterial first texture w\nmaterial second texture b\n"
                                                   : "material first color 1 1 1\nmaterial second color 0 0 0\n";
            const std::string scene = "size " + std::to_string(size) + " " + std::to_string(size) +
                                      "\ncamera eye 0 0 2 target 0 0 0 fov 90\n" + materials + quad("first", 0.2, 0.2, 0.8, 0.8) +
                                      quad("second", 0.2, 0.2, 0.8, 0.8);
            const Framebuffer fb = testing::render_scene_text(scene, "equal-depth.scene");
            int white = 0;
            for (std::size_t i = 0; i < fb.color.size(); ++i) white += fb.color[i].x == 1.0f && fb.color[i].y == 1.0f;
            CAPTURE(size);
            CAPTURE(textured);
            CHECK(white == size * size);
        }
}

TEST_CASE("texture coordinates are re-based by whole periods only along an axis that repeats or mirrors") {
    // u repeats, v is clamped: v from 1.2 to 1.8 lies above the image, where clamp reads its
    // top row (white; the bottom row is black) at every pixel. Moving v by a period, as u
    // may be moved, would bring it to 0.2 .. 0.8 and read black below v = 0.5. Then the
    // other way round (u clamped beyond 1, v repeating): the right column, white.
    const std::string dir = testing::scratch_folder("rebase-axes");
    std::string column("P6\n1 2\n255\n");  // the top row white, the bottom one black
    column += std::string(3, char(255)) + std::string(3, char(0));
    testing::write_text(dir + "/column.ppm", column);
    std::string row("P6\n2 1\n255\n");  // the left column black, the right one white
    row += std::string(3, char(0)) + std::string(3, char(255));
    testing::write_text(dir + "/row.ppm", row);
    const std::string camera = "size 16 16\ncamera eye 0 0 2 target 0 0 0 fov 90\n";
    const std::string v_scene = camera + "texture t file " + dir + "/column.ppm filter nearest wrap_u repeat wrap_v clamp\n" +
                                "material m texture t\n" + quad("m", 0.0, 1.2, 1.0, 1.8);
    const std::string u_scene = camera + "texture t file " + dir + "/row.ppm filter nearest wrap_u clamp wrap_v repeat\n" +
                                "material m texture t\n" + quad("m", 1.2, 0.0, 1.8, 1.0);
    const Framebuffer v_clamped = testing::render_scene_text(v_scene, "rebase.scene");
    const Framebuffer u_clamped = testing::render_scene_text(u_scene, "rebase.scene");
    for (const Framebuffer* fb : {&v_clamped, &u_clamped}) {
        int white = 0;
        for (std::size_t i = 0; i < fb->color.size(); ++i) white += fb->color[i].x == 1.0f;
        CHECK(white == 16 * 16);
    }
}
