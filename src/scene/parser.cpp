// Scene file parser (format: docs/scene-format.md).
#include "texr/scene/parser.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <new>
#include <sstream>
#include <tuple>
#include <utility>
#include <vector>

#include <sys/stat.h>

#include <glm/gtc/matrix_transform.hpp>

#include "texr/core/error.h"
#include "texr/core/path.h"
#include "texr/core/scaling.h"
#include "texr/core/text_line.h"
#include "texr/scene/obj_mesh.h"

namespace texr {

namespace {

// A word a scene author may take from the lecture's parts that texr does not have yet
// (docs/lecture-guide.md, "Not in texr yet"): the end of the message that refuses it, so
// that it does not read as a typo. Empty for any other word.
std::string not_in_texr_yet(const std::string& word) {
    static const std::map<std::string, const char*> parts = {
        {"torus", "parametric surfaces (texr's: sphere, cylinder and disc)"},
        {"cone", "parametric surfaces (texr's: sphere, cylinder and disc)"},
        {"wood", "wood pattern (solid noise)"}, {"granite", "granite pattern (solid noise)"},
        {"bark", "bark pattern"}, {"clouds", "clouds pattern"}, {"spherical", "two-stage mapping (texr's: a material's 'mapping spherical')"},
        {"cylindrical", "two-stage mapping (texr's: a material's 'mapping cylindrical')"},
        {"planar", "two-stage mapping (texr's: a material's 'mapping planar')"},
        {"cubemap", "cube maps (texr's environment maps are latitude-longitude)"},
        {"sphere_map", "sphere maps (texr's environment maps are latitude-longitude)"},
        {"light_map", "light maps (texr's: a material's 'lightmap TEXTURE')"}, 
        {"normal_map", "normal mapping"}, {"normalmap", "normal mapping"}, {"displacement", "displacement mapping"},
        {"displace", "displacement mapping"}};
    std::string lower;
    for (const char ch : word) lower += (ch >= 'A' && ch <= 'Z') ? char(ch - 'A' + 'a') : ch;
    if (lower == "disk") return "; did you mean 'disc'?";
    // Opacity: texr's is an alpha test.
    for (const char* alpha : {"opacity", "alpha", "transparency", "alpha_test", "blend"})
        if (lower == alpha)
            return "; " + shown_token(word) + ": texr's opacity is an alpha test, a material's 'cutout THRESHOLD' (blending is not in "
                   "texr; docs/scene-format.md)";
    const auto it = parts.find(lower);
    if (it == parts.end()) return "";
    return "; " + shown_token(word) + " belongs to the lecture's " + it->second +
           ", which texr does not have yet (docs/lecture-guide.md, \"Not in texr yet\")";
}

// v times the power of two that brings its largest component into [1, 2): the same direction,
// and glm::normalize gives the same bits for it (every step scales exactly), but its squared
// length neither overflows nor underflows (a light direction of 1e300, an up of 1e-300).
// The zero vector stays zero.
glm::dvec3 direction_scaled(const glm::dvec3& v) {
    const int k = unit_scale_exponent(std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}));
    return glm::dvec3(std::ldexp(v.x, k), std::ldexp(v.y, k), std::ldexp(v.z, k));
}

// --- Tokens of one logical line ------------------------------------------------------------
struct Line {
    int number = 0;  // where the command starts
    std::vector<std::string> tokens;
    std::vector<int> token_lines;  // the file line of each token (a command continued with '\\' spans several)
};

// Splits on whitespace; "double quotes" keep spaces; '#' outside quotes ends the line.
std::vector<std::string> tokenize(const std::string& text, const std::string& file, int number) {
    std::vector<std::string> tokens;
    std::size_t i = 0;
    while (i < text.size()) {
        const char ch = text[i];
        if (ch == ' ' || ch == '\t') { ++i; continue; }
        if (ch == '#') break;
        std::string token;
        if (ch == '"') {
            const auto close = text.find('"', i + 1);
            if (close == std::string::npos) throw InputError(file, number, "unterminated quoted string");
            token = text.substr(i + 1, close - i - 1);
            i = close + 1;
        } else {
            while (i < text.size() && text[i] != ' ' && text[i] != '\t' && text[i] != '#')
                token += text[i++];
        }
        tokens.push_back(token);
    }
    return tokens;
}

// The part of a raw line before a '#' that is outside double quotes.
std::string without_comment(const std::string& raw) {
    bool quoted = false;
    for (std::size_t i = 0; i < raw.size(); ++i) {
        if (raw[i] == '"') quoted = !quoted;
        else if (raw[i] == '#' && !quoted) return raw.substr(0, i);
    }
    return raw;
}

std::vector<Line> read_lines(std::istream& in, const std::string& file) {
    std::vector<Line> lines;
    std::string raw;
    Line line;  // the command being read
    int number = 0;
    bool continuing = false;  // the line before ended with '\\'
    TextLineReader text(in);
    while (text.next(raw)) {
        ++number;
        if (number == 1 && raw.rfind("\xEF\xBB\xBF", 0) == 0) raw.erase(0, 3);  // a UTF-8 byte order mark
        // (A NUL would cut every message that quotes the line short.)
        if (raw.find('\0') != std::string::npos) throw InputError(file, number, "a NUL byte: is this a scene file?");
        raw = without_comment(raw);  // a '\\' inside a comment does not continue the line
        while (!raw.empty() && (raw.back() == ' ' || raw.back() == '\t')) raw.pop_back();
        const bool continued = !raw.empty() && raw.back() == '\\';
        if (continued) raw.pop_back();
        if (!continuing) line = Line{number, {}, {}};
        for (std::string& token : tokenize(raw, file, number)) {
            line.tokens.push_back(std::move(token));
            line.token_lines.push_back(number);
        }
        continuing = continued;
        if (continued) continue;
        if (!line.tokens.empty()) lines.push_back(std::move(line));
    }
    if (continuing) throw InputError(file, number, "line ends with '\\' but the file ends there");
    return lines;
}

// --- Reading one line's values, with messages that say what was expected --------------------
class Cursor {
public:
    Cursor(const Line& line, const std::string& file) : line_(line), file_(file) {}

    // At the line of the token read last (a command continued with '\\' spans several lines).
    [[noreturn]] void fail(const std::string& message) const { fail_at(next_ - 1, message); }
    // At the line of token `token` (from mark()): for a check made after more words were read.
    [[noreturn]] void fail_at(std::size_t token, const std::string& message) const {
        throw InputError(file_, line_of(token), message);
    }
    // The token read last (0: the command's name).
    std::size_t mark() const { return next_ - 1; }
    // The file line of token `token` (from mark()).
    int line_of(std::size_t token) const { return token < line_.token_lines.size() ? line_.token_lines[token] : line_.number; }
    bool done() const { return next_ >= line_.tokens.size(); }
    int line_number() const { return line_.number; }
    const std::string& peek() const { return line_.tokens[next_]; }

    std::string word(const std::string& what) {
        if (done()) fail("expected " + what + " after " + shown_token(line_.tokens[next_ - 1]) + ", found the end of the line");
        return line_.tokens[next_++];
    }

    // Refuses `key`, just read, as an unknown option of `command` (`expected`: its options).
    // A number there most often belongs to the option before it, which was given too many
    // (a vertex of six numbers, an eye of four): the message says so, naming that option.
    [[noreturn]] void unknown_option(const std::string& command, const std::string& key, const std::string& expected) const {
        std::string message = "unknown " + command + " option " + shown_token(key) + " (expected " + expected + ")" + not_in_texr_yet(key);
        double ignored = 0.0;
        if (parse_number(key, ignored)) {
            std::size_t option = mark();
            while (option > 1 && parse_number(line_.tokens[option - 1], ignored)) --option;
            std::size_t more = mark() + 1;  // the numbers from key on
            while (more < line_.tokens.size() && parse_number(line_.tokens[more], ignored)) ++more;
            if (option > 1 && option < mark())
                message += more - mark() == 1 ? ": a number too many for " + shown_token(line_.tokens[option - 1]) + " before it?"
                                              : ": numbers too many for " + shown_token(line_.tokens[option - 1]) +
                                                    " before them, or an option's name missing?";
        }
        fail(message);
    }

    double number(const std::string& what) {
        const std::string text = word(what);
        double value = 0.0;
        if (!parse_number(text, value)) fail("expected " + what + ", found " + shown_token(text));
        return value;
    }

    // Records option `key`, just read, of this command; refuses it the second time: of two
    // values, the last would silently win.
    void once(const std::string& key) {
        for (const auto& [name, at] : options_)
            if (name == key)
                fail(shown_token(key) + " is given a second time in this " + shown_token(line_.tokens[0]) + " command (first on line " +
                     std::to_string(line_of(at)) + "): give it once");
        options_.emplace_back(key, mark());
    }
    bool seen(const std::string& key) const { return where(key) != 0; }
    // The token of option `key` (0: not given).
    std::size_t where(const std::string& key) const {
        for (const auto& option : options_)
            if (option.first == key) return option.second;
        return 0;
    }

    bool next_is_number() const {
        double ignored;
        return !done() && parse_number(peek(), ignored);
    }

    glm::dvec3 vec3(const std::string& what) {
        glm::dvec3 v;
        for (int i = 0; i < 3; ++i) v[i] = number("3 numbers for " + what);
        return v;
    }

    // A number kept as a float (vertex positions and normals): within a float's range, which
    // a double's finite numbers need not be.
    float float_number(const std::string& expected, const std::string& what) {
        const double value = number(expected);
        if (!(std::fabs(value) <= double(std::numeric_limits<float>::max())))
            fail(what + ": " + shown_token(line_.tokens[next_ - 1]) + " is beyond a float's range (about 3.4e38)");
        return float(value);
    }
    glm::vec3 float_vec3(const std::string& what) {
        glm::vec3 v;
        for (int i = 0; i < 3; ++i) v[i] = float_number("3 numbers for " + what, what);
        return v;
    }

    // Colours in scene files are sRGB values (as a colour picker shows them), in [0, 1]
    // or above for bright lights, up to max_color; texr works on their linear values.
    glm::dvec3 color_values(const std::string& what) {
        const glm::dvec3 c = vec3(what);
        for (int i = 0; i < 3; ++i) {
            if (c[i] < 0.0) fail(what + " must not be negative");
            if (c[i] > max_color) fail(what + " must be at most " + max_color_text());
        }
        return c;
    }
    Color color(const std::string& what) {
        const glm::dvec3 c = color_values(what);
        return {srgb_to_linear(float(c.x)), srgb_to_linear(float(c.y)), srgb_to_linear(float(c.z))};
    }

private:
    static bool parse_number(const std::string& text, double& value) {
        std::istringstream s(text);
        s >> value;
        return s && s.peek() == std::char_traits<char>::eof() && std::isfinite(value);
    }
    const Line& line_;
    const std::string& file_;
    std::size_t next_ = 1;
    std::vector<std::pair<std::string, std::size_t>> options_;  // once(): the options read, where
};

template <typename Enum>
Enum choose(Cursor& c, const std::string& what, const std::map<std::string, Enum>& choices) {
    const std::string w = c.word(what);
    auto it = choices.find(w);
    if (it != choices.end()) return it->second;
    std::string names;
    for (const auto& [name, value] : choices) names += (names.empty() ? "" : ", ") + name;
    c.fail("unknown " + what + " " + shown_token(w) + " (expected one of: " + names + ")" + not_in_texr_yet(w));
}

const std::map<std::string, Wrap> wrap_names = {
    {"repeat", Wrap::repeat}, {"mirror", Wrap::mirror}, {"clamp", Wrap::clamp}, {"border", Wrap::border}};

// A path from the scene file: absolute as written, otherwise relative to the scene's folder.
std::string relative_to(const std::string& folder, const std::string& path) {
    return !path.empty() && path[0] == '/' ? path : folder + path;
}

// --- The parser --------------------------------------------------------------------------------
class Parser {
public:
    Parser(Scene& scene, const std::string& file) : scene_(scene), file_(file), folder_(folder_of(file)) {}

    void command(const Line& line) {
        Cursor c(line, file_);
        const std::string& name = line.tokens[0];
        // The frame's settings are given once (a second line would silently win, or for the
        // camera merge its options with the first).
        if (name == "size" || name == "camera" || name == "background" || name == "ambient" || name == "environment") {
            const auto [first, inserted] = settings_line_.emplace(name, line.number);
            if (!inserted) c.fail(shown_token(name) + " is given a second time (first on line " + std::to_string(first->second) + ")");
        }
        if (name == "size") size(c);
        else if (name == "camera") camera(c);
        else if (name == "background") scene_.background = c.color("background colour");
        else if (name == "ambient") scene_.ambient = c.color("ambient colour");
        else if (name == "environment") {
            const std::string texture = c.word("the environment map's texture name");
            const auto it = texture_index_.find(texture);
            if (it == texture_index_.end()) c.fail("unknown texture " + shown_name(texture) + " (define it with a 'texture' line first)");
            scene_.environment = it->second;
        }
        else if (name == "texture") texture(c);
        else if (name == "material") material(c);
        else if (name == "light") light(c);
        else if (name == "mesh") mesh(c);
        else if (name == "triangle") polygon(c, 3);
        else if (name == "quad") polygon(c, 4);
        else if (name == "billboard") billboard(c);
        else if (name == "projector") projector(c);
        else if (name == "sphere" || name == "cylinder" || name == "disc") parametric(c, name);
        else c.fail("unknown command " + shown_token(name) +
                    " (expected size, camera, background, ambient, environment, texture, material, light, projector, mesh, "
                    "triangle, quad, billboard, sphere, cylinder or disc)" +
                    not_in_texr_yet(name));
        if (!c.done()) c.fail("unexpected " + shown_token(c.peek()) + " at the end of " + shown_token(name));
    }

private:
    void size(Cursor& c) {
        const double w = c.number("the width"), h = c.number("the height");
        check_image_size(c, w, h);
        scene_.width = int(w);
        scene_.height = int(h);
    }

    static void check_image_size(Cursor& c, double w, double h) {
        if (w != std::floor(w) || h != std::floor(h) || w < 1 || h < 1 || w > max_image_side || h > max_image_side ||
            w * h > double(max_image_pixels))
            c.fail("image size must be whole numbers from 1 to " + std::to_string(max_image_side) +
                   " per side and at most " + std::to_string(max_image_pixels) + " pixels");
    }

    void camera(Cursor& c) {
        Camera& cam = scene_.camera;
        // Where each value was given, for the checks made once all are read (0: not given).
        std::size_t fov_at = 0, near_at = 0, far_at = 0, view_at = 0, up_at = 0;
        while (!c.done()) {
            const std::string key = c.word("a camera option");
            c.once(key);
            if (key == "eye") cam.eye = c.vec3("eye"), view_at = c.mark();
            else if (key == "target") cam.target = c.vec3("target"), view_at = c.mark();
            else if (key == "up") cam.up = direction_scaled(c.vec3("up")), up_at = c.mark();
            else if (key == "fov") cam.fov_y_degrees = c.number("the vertical field of view in degrees"), fov_at = c.mark();
            else if (key == "near") cam.near = c.number("the near distance"), near_at = c.mark();
            else if (key == "far") cam.far = c.number("the far distance"), far_at = c.mark();
            else c.unknown_option("camera", key, "eye, target, up, fov, near or far");
        }
        // Below 1e-6 degrees a pixel's angle comes near the rounding of the view transform
        // (a review's floor, whose target the eye looked at, vanished at 1e-17 degrees).
        if (!(cam.fov_y_degrees >= 1e-6 && cam.fov_y_degrees < 180.0)) {
            char given[32];  // (the shortest text that reads back as the value: 9.9999999e-07, not 1e-06)
            const auto end = std::to_chars(given, given + sizeof given, cam.fov_y_degrees).ptr;
            c.fail_at(fov_at, "fov must be at least 1e-6 degrees and below 180, got " + std::string(given, end));
        }
        // (near <= 0 is near's fault alone; far <= near is the later of the two's)
        if (!(cam.near > 0.0)) c.fail_at(near_at, "camera needs 0 < near < far");
        if (!(cam.far > cam.near)) c.fail_at(std::max(near_at, far_at), "camera needs 0 < near < far");
        const glm::dvec3 view = cam.target - cam.eye;
        if (view == glm::dvec3(0.0)) c.fail_at(view_at, "camera eye and target must differ");
        // The view direction is normalised from target - eye itself (glm::lookAtRH).
        if (!(glm::length(view) > 0.0 && std::isfinite(glm::length(view))))
            c.fail_at(view_at, "camera eye and target are too close together or too far apart for a view direction (their "
                               "distance squared is beyond a double's range)");
        if (up_at != 0 && cam.up == glm::dvec3(0.0)) c.fail_at(up_at, "camera up must not be the zero vector");
        if (glm::length(glm::cross(direction_scaled(view), cam.up)) == 0.0)  // at `up` when it was given (the message names it)
            c.fail_at(up_at != 0 ? up_at : view_at, "camera up must not be parallel to the view direction");
    }

    // A texture or scene material is defined once: a second definition names the first's line.
    void define_once(Cursor& c, const std::string& what) {
        const auto [first, inserted] = defined_on_.emplace(what, c.line_number());
        if (!inserted) c.fail(what + " is defined a second time (first on line " + std::to_string(first->second) + ")");
    }

    void texture(Cursor& c) {
        Texture t;
        t.name = c.word("a texture name");
        define_once(c, "texture " + shown_name(t.name));
        ColorSpace space = ColorSpace::srgb;
        glm::dvec3 border(0.0);  // as written: its colour space is the image's (below)
        std::size_t file_at = 0, srgb_at = 0;  // srgb_at: where 'colorspace srgb' was written (0: not)
        Procedural procedural;  // (its default colours: sRGB 0.1 and 0.9 greys)
        procedural.color0 = Color(srgb_to_linear(0.1f)), procedural.color1 = Color(srgb_to_linear(0.9f));
        std::size_t procedural_at = 0, image_option_at = 0, procedural_option_at = 0;  // (0: not written)
        std::string image_option, procedural_option;  // the first of each kind, for the message
        static const char* const image_options[] = {"file", "filter", "cubic", "clamp_overshoot", "max_anisotropy", "wrap",
                                                    "wrap_u", "wrap_v", "border", "registration", "colorspace"};
        static const char* const procedural_options[] = {"scale", "color0", "color1", "mortar", "octaves", "amplitude", "solid"};
        while (!c.done()) {
            const std::string key = c.word("a texture option");
            c.once(key);
            const auto named = [&](const char* const* list, std::size_t n) { return std::find(list, list + n, key) != list + n; };
            if (image_option_at == 0 && named(image_options, std::size(image_options))) image_option = key, image_option_at = c.mark();
            if (procedural_option_at == 0 && named(procedural_options, std::size(procedural_options)))
                procedural_option = key, procedural_option_at = c.mark();
            if ((key == "wrap" && (c.seen("wrap_u") || c.seen("wrap_v"))) || ((key == "wrap_u" || key == "wrap_v") && c.seen("wrap")))
                c.fail("'wrap' sets both wrap_u and wrap_v: give either wrap, or wrap_u and wrap_v");
            if (key == "file") t.path = relative_to(folder_, c.word("an image file name")), file_at = c.mark();
            else if (key == "procedural") {
                procedural_at = c.mark();
                std::map<std::string, Pattern> patterns;
                for (int p = 0; p < pattern_count; ++p) patterns[pattern_name(Pattern(p))] = Pattern(p);
                procedural.pattern = choose(c, "procedural pattern", patterns);
            } else if (key == "scale") {
                procedural.scale = c.number("the pattern's scale");
                if (!(procedural.scale > 0.0 && procedural.scale <= 1e9)) c.fail("the pattern's scale must be above 0 and at most 1e9");
            } else if (key == "color0") procedural.color0 = c.color("color0");
            else if (key == "color1") procedural.color1 = c.color("color1");
            else if (key == "mortar") {
                procedural.mortar = c.number("the mortar's width");
                if (!(procedural.mortar >= 0.0 && procedural.mortar <= 1.0)) c.fail("the mortar's width must be between 0 and 1 (a fraction of a cell)");
            } else if (key == "octaves") {
                const double n = c.number("the most octaves");
                if (!(n >= 1.0 && n <= 30.0 && n == std::floor(n))) c.fail("octaves must be a whole number from 1 to 30");
                procedural.octaves = int(n);
            } else if (key == "amplitude") {
                procedural.amplitude = c.number("the turbulence's amplitude");
                if (!(std::fabs(procedural.amplitude) <= 1e6)) c.fail("the turbulence's amplitude must be between -1e6 and 1e6");
            } else if (key == "solid") procedural.solid = choose<bool>(c, "solid setting", {{"on", true}, {"off", false}});
            else if (key == "filter") {
                std::map<std::string, Filter> filters;
                for (int f = 0; f < filter_count; ++f) filters[filter_name(Filter(f))] = Filter(f);
                t.sampler.filter = choose(c, "filter", filters);
            } else if (key == "cubic") {
                const double b = c.number("the cubic's B"), cc = c.number("the cubic's C");
                // (B and C are usually within [0, 1]; far outside, the weights grow without bound)
                if (!(std::fabs(b) <= 10.0 && std::fabs(cc) <= 10.0)) c.fail("the cubic's B and C must be between -10 and 10");
                t.sampler.cubic_b = float(b), t.sampler.cubic_c = float(cc);
            } else if (key == "clamp_overshoot")
                t.sampler.clamp_overshoot = choose<bool>(c, "clamp_overshoot setting", {{"on", true}, {"off", false}});
            else if (key == "max_anisotropy") {
                t.sampler.max_anisotropy = float(c.number("the maximum anisotropy"));
                if (!(t.sampler.max_anisotropy >= 1.0f && t.sampler.max_anisotropy <= 64.0f))
                    c.fail("max_anisotropy must be between 1 and 64");
            }
            else if (key == "wrap") t.sampler.wrap_u = t.sampler.wrap_v = choose(c, "wrap mode", wrap_names);
            else if (key == "wrap_u") t.sampler.wrap_u = choose(c, "wrap mode", wrap_names);
            else if (key == "wrap_v") t.sampler.wrap_v = choose(c, "wrap mode", wrap_names);
            else if (key == "border") {
                border = c.color_values("border colour");
                const double alpha = c.number("the border alpha");
                if (!(alpha >= 0.0 && alpha <= 1.0)) c.fail("the border alpha must be between 0 and 1");
                t.sampler.border.w = float(alpha);
            } else if (key == "registration")
                t.sampler.registration = choose<Registration>(c, "registration", {{"cell", Registration::cell}, {"node", Registration::node}});
            else if (key == "colorspace") {
                space = choose<ColorSpace>(c, "colour space", {{"srgb", ColorSpace::srgb}, {"linear", ColorSpace::linear}});
                srgb_at = space == ColorSpace::srgb ? c.mark() : 0;
            }
            else c.unknown_option("texture", key, "file, filter, wrap, wrap_u, wrap_v, border, registration, colorspace, cubic, "
                                                  "clamp_overshoot, max_anisotropy; or procedural, scale, color0, color1, mortar, "
                                                  "octaves, amplitude, solid");
        }
        if (procedural_at != 0) {
            if (image_option_at != 0)
                c.fail_at(image_option_at, shown_token(image_option) + " is an image texture's option: texture " + shown_name(t.name) +
                                               " is procedural (it has no texels to read, filter or wrap)");
            const Pattern p = procedural.pattern;
            if (c.seen("mortar") && p != Pattern::tile && p != Pattern::brick)
                c.fail_at(c.where("mortar"), "'mortar' applies to the tile and brick patterns, not to " + std::string(pattern_name(p)));
            if (c.seen("octaves") && p != Pattern::turbulence && p != Pattern::marble)
                c.fail_at(c.where("octaves"), "'octaves' applies to the turbulence and marble patterns, not to " + std::string(pattern_name(p)));
            if (c.seen("amplitude") && p != Pattern::marble)
                c.fail_at(c.where("amplitude"), "'amplitude' applies to the marble pattern, not to " + std::string(pattern_name(p)));
            if (procedural.solid && (p == Pattern::tile || p == Pattern::brick))
                c.fail_at(c.where("solid"), std::string("the ") + pattern_name(p) +
                                                " pattern is 2D: 'solid on' applies to checker, noise, turbulence and marble");
            t.procedural = std::make_shared<const Procedural>(procedural);
            texture_index_[t.name] = int(scene_.textures.size());
            scene_.textures.push_back(std::move(t));
            return;
        }
        if (procedural_option_at != 0 && !t.path.empty())
            c.fail_at(procedural_option_at, shown_token(procedural_option) + " is a procedural texture's option: texture " +
                                                shown_name(t.name) + " reads an image (give 'procedural PATTERN' instead of 'file')");
        if (procedural_option_at != 0)
            c.fail_at(procedural_option_at, shown_token(procedural_option) + " is a procedural texture's option: texture " +
                                                shown_name(t.name) + " needs 'procedural PATTERN' for it");
        if (t.path.empty()) c.fail("texture " + shown_name(t.name) + " needs 'file PATH' (or 'procedural PATTERN')");
        t.image = image(c, file_at, t.path, space);
        if (srgb_at && t.image->is_hdr())  // (asked for, it would be ignored)
            c.fail_at(srgb_at, "a Radiance HDR image holds linear values: 'colorspace srgb' does not apply to it (leave it out)");
        // The border colour is in the texels' space: sRGB for a colour image (decoded, as every
        // scene colour), the values themselves for data and HDR images, whose texels are read
        // as they are (a normal map's border 0.5 0.5 1 is the normal (0, 0, 1)).
        const bool decode = space == ColorSpace::srgb && !t.image->is_hdr();
        for (int i = 0; i < 3; ++i)
            t.sampler.border[i] = decode ? srgb_to_linear(float(border[i])) : float(border[i]);
        t.mipmap = mipmap(t.image, t.sampler);
        texture_index_[t.name] = int(scene_.textures.size());
        scene_.textures.push_back(std::move(t));
    }

    // `at`: the token that named the file (errors are reported at its line); `context` says
    // where the path came from when it is not this line ("cube.mtl map_Kd: ").
    std::shared_ptr<const Image> image(Cursor& c, std::size_t at, const std::string& path, ColorSpace space,
                                       const std::string& context = "") {
        const std::string key = path + (space == ColorSpace::srgb ? "|srgb" : "|linear");
        auto it = images_.find(key);
        if (it != images_.end()) return it->second;
        try {
            auto loaded = std::make_shared<const Image>(load_image(path, space));
            images_[key] = loaded;
            scene_.files.push_back(path);
            return loaded;
        } catch (const InputError& e) {
            c.fail_at(at, context + e.what());
        } catch (const std::bad_alloc&) {  // a huge image: say which
            c.fail_at(at, context + shown_path(path) + ": out of memory reading the image");
        }
    }

    // One mipmap per image, shared by every texture that reads it with cell registration;
    // node registration has levels of its own for each pair of wrap modes (and border colour,
    // if a mode is border), as they read beyond the ends through them (mipmap.h).
    std::shared_ptr<MipMap> mipmap(const std::shared_ptr<const Image>& image, const Sampler& s) {
        MipKey key{image.get(), false, Wrap::repeat, Wrap::repeat, {0.0f, 0.0f, 0.0f, 0.0f}};
        if (s.registration == Registration::node) {
            key = {image.get(), true, s.wrap_u, s.wrap_v, {0.0f, 0.0f, 0.0f, 0.0f}};
            if (s.wrap_u == Wrap::border || s.wrap_v == Wrap::border)
                std::get<4>(key) = {s.border.x, s.border.y, s.border.z, s.border.w};
        }
        auto& m = mipmaps_[key];
        if (!m) m = std::make_shared<MipMap>(image, s);
        return m;
    }

    void material(Cursor& c) {
        Material m;
        m.name = c.word("a material name");
        const auto from_obj = material_from_obj_.find(m.name);
        if (from_obj != material_from_obj_.end())
            c.fail("material " + shown_name(m.name) + " is already defined: line " + std::to_string(from_obj->second) +
                   "'s OBJ file uses it, so the mesh made it (define scene materials before the meshes that use them)");
        define_once(c, "material " + shown_name(m.name));
        while (!c.done()) {
            const std::string key = c.word("a material option");
            c.once(key);
            if (key == "color") m.color = c.color("material colour");
            else if (key == "texture") {
                const std::string name = c.word("a texture name");
                auto it = texture_index_.find(name);
                if (it == texture_index_.end()) c.fail("unknown texture " + shown_name(name) + " (define it with a 'texture' line first)");
                m.texture = it->second;
            } else if (key == "lighting")
                m.lighting = choose<Lighting>(c, "lighting", {{"none", Lighting::none}, {"lambert", Lighting::lambert}});
            else if (key == "vertex_colors")
                m.vertex_colors = choose<bool>(c, "vertex_colors setting", {{"on", true}, {"off", false}});
            else if (key == "bump") {
                const std::string name = c.word("a bump map's texture name");
                auto it = texture_index_.find(name);
                if (it == texture_index_.end()) c.fail("unknown texture " + shown_name(name) + " (define it with a 'texture' line first)");
                const Texture& t = scene_.textures[std::size_t(it->second)];
                if (t.procedural && t.procedural->solid)
                    c.fail("texture " + shown_name(name) + " is solid: a bump map is read at (u, v) (leave out 'solid on')");
                m.bump = it->second;
                m.bump_height = c.number("the bump's height (world units for a texture value of 1)");
                if (!(std::fabs(m.bump_height) <= 1e6)) c.fail("the bump's height must be between -1e6 and 1e6");
            } else if (key == "reflect") {
                m.reflect = c.number("the share reflected (0 to 1)");
                if (!(m.reflect >= 0.0 && m.reflect <= 1.0)) c.fail("the share reflected must be between 0 and 1");
                if (scene_.environment < 0)
                    c.fail("material " + shown_name(m.name) + " reflects the environment: give the 'environment TEXTURE' line before it");
            } else if (key == "cutout") {
                const double threshold = c.number("the cutout's alpha threshold");
                if (!(threshold > 0.0 && threshold <= 1.0)) c.fail("the cutout's alpha threshold must be above 0 and at most 1");
                m.cutout = float(threshold);
            } else if (key == "slope") {
                m.slope = true;
                m.slope_flat = c.color("the slope mapping's flat colour");
                m.slope_steep = c.color("the slope mapping's steep colour");
            } else if (key == "slope_direction") {
                const glm::dvec3 direction = c.vec3("the slope mapping's direction");
                if (!(glm::length(direction) > 0.0) || !std::isfinite(glm::length(direction)))
                    c.fail("the slope mapping's direction must not be zero (nor beyond a double's range)");
                m.slope_direction = glm::normalize(direction);
            } else if (key == "lightmap") {
                const std::string name = c.word("a light map's texture name");
                auto it = texture_index_.find(name);
                if (it == texture_index_.end()) c.fail("unknown texture " + shown_name(name) + " (define it with a 'texture' line first)");
                if (scene_.textures[std::size_t(it->second)].procedural && scene_.textures[std::size_t(it->second)].procedural->solid)
                    c.fail("texture " + shown_name(name) + " is solid: a light map is read at (u, v) (leave out 'solid on')");
                m.lightmap = it->second;
            } else if (key == "lightmap_repeat") {
                m.lightmap_repeat = c.number("how often the texture repeats over the light map");
                if (!(m.lightmap_repeat > 0.0 && m.lightmap_repeat <= 1e9)) c.fail("lightmap_repeat must be above 0 and at most 1e9");
            } else if (key == "mapping") {
                m.mapping.kind = choose<Intermediate>(
                    c, "intermediate mapping",
                    {{"planar", Intermediate::planar}, {"cylindrical", Intermediate::cylindrical}, {"spherical", Intermediate::spherical}});
            } else if (key == "mapping_center") {
                m.mapping.center = c.vec3("the intermediate surface's centre");
            } else if (key == "mapping_axis") {
                const glm::dvec3 axis = c.vec3("the intermediate surface's axis");
                if (!(glm::length(axis) > 0.0) || !std::isfinite(glm::length(axis)))
                    c.fail("the intermediate surface's axis must not be zero (nor beyond a double's range)");
                m.mapping.axis = glm::normalize(axis);
            } else if (key == "mapping_size") {
                m.mapping.size = c.number("the intermediate surface's size");
                if (!(m.mapping.size > 0.0 && m.mapping.size <= 1e18)) c.fail("mapping_size must be above 0 and at most 1e18");
            } else if (key == "projector") {
                const std::string name = c.word("a projector's name");
                const auto it = projector_index_.find(name);
                if (it == projector_index_.end()) c.fail("unknown projector " + shown_name(name) + " (define it with a 'projector' line first)");
                m.projector = it->second;
            } else c.unknown_option("material", key, "color, texture, lighting, vertex_colors, bump, reflect, cutout, slope, "
                                                      "slope_direction, lightmap, lightmap_repeat, projector, mapping, mapping_center, "
                                                      "mapping_axis or mapping_size");
        }
        for (const char* option : {"mapping_center", "mapping_axis", "mapping_size"})
            if (c.seen(option) && m.mapping.kind == Intermediate::none)
                c.fail_at(c.where(option), shown_token(option) + " belongs with 'mapping planar|cylindrical|spherical'");
        if (m.mapping.kind != Intermediate::none) {
            if (m.texture < 0) c.fail_at(c.where("mapping"), "material " + shown_name(m.name) + " has no texture to map ('texture NAME')");
            if (m.projector >= 0) c.fail_at(c.where("mapping"), "a material's texture is either thrown by a projector or mapped, not both");
            const Texture& t = scene_.textures[std::size_t(m.texture)];
            if (t.procedural && t.procedural->solid)
                c.fail_at(c.where("mapping"), "texture " + shown_name(t.name) + " is solid: an intermediate mapping gives (u, v) (leave out 'solid on')");
            // x' of the frame: the world's x made square to the axis (z where the axis is along x).
            glm::dvec3 reference = glm::dvec3(1.0, 0.0, 0.0) - m.mapping.axis.x * m.mapping.axis;
            if (glm::length(reference) < 1e-6) reference = glm::dvec3(0.0, 0.0, 1.0) - m.mapping.axis.z * m.mapping.axis;
            m.mapping.reference = glm::normalize(reference);
        }
        if (m.projector >= 0 && m.texture < 0)
            c.fail_at(c.where("projector"), "material " + shown_name(m.name) + " has no texture for its projector to throw ('texture NAME')");
        if (m.projector >= 0 && scene_.textures[std::size_t(m.texture)].procedural && scene_.textures[std::size_t(m.texture)].procedural->solid)
            c.fail_at(c.where("projector"), "texture " + shown_name(scene_.textures[std::size_t(m.texture)].name) +
                                                " is solid: a projector throws (u, v) (leave out 'solid on')");
        if (c.seen("slope_direction") && !m.slope)
            c.fail_at(c.where("slope_direction"), "'slope_direction' belongs with 'slope FLAT STEEP' (r g b each)");
        if (c.seen("lightmap_repeat") && m.lightmap < 0)
            c.fail_at(c.where("lightmap_repeat"), "'lightmap_repeat' belongs with 'lightmap TEXTURE'");
        if (m.cutout > 0.0f && m.texture < 0)
            c.fail_at(c.where("cutout"), "material " + shown_name(m.name) + " has no texture: 'cutout' tests its texture's alpha");
        if (m.bump >= 0 && m.lighting != Lighting::lambert && !(m.reflect > 0.0))
            c.fail_at(c.where("bump"), "a bump map changes only the shading normal: material " + shown_name(m.name) +
                                           " needs 'lighting lambert' or 'reflect' for it to show");
        material_index_[m.name] = int(scene_.materials.size());
        scene_.materials.push_back(m);
    }

    // projector NAME eye x y z target x y z [up x y z] [fov F | parallel H] [aspect A]
    void projector(Cursor& c) {
        Projector p;
        p.name = c.word("a projector name");
        define_once(c, "projector " + shown_name(p.name));
        std::size_t view_at = 0;
        while (!c.done()) {
            const std::string key = c.word("a projector option");
            c.once(key);
            if ((key == "fov" && c.seen("parallel")) || (key == "parallel" && c.seen("fov")))
                c.fail("a projector is either perspective ('fov') or parallel ('parallel'), not both");
            if (key == "eye") p.eye = c.vec3("the projector's position"), view_at = c.mark();
            else if (key == "target") p.target = c.vec3("the point the projector aims at"), view_at = c.mark();
            else if (key == "up") p.up = c.vec3("the projector's up");
            else if (key == "fov") {
                p.fov_y_degrees = c.number("the projector's field of view in degrees");
                if (!(p.fov_y_degrees >= 1e-6 && p.fov_y_degrees < 180.0)) c.fail("the projector's fov must be at least 1e-6 and below 180 degrees");
            } else if (key == "parallel") {
                p.parallel = true;
                p.height = c.number("the parallel projection's height");
                if (!(p.height > 0.0 && p.height <= 1e18)) c.fail("the parallel projection's height must be above 0 and at most 1e18");
            } else if (key == "aspect") {
                p.aspect = c.number("the projected image's width over height");
                if (!(p.aspect > 0.0 && p.aspect <= 1e6)) c.fail("the projector's aspect must be above 0 and at most 1e6");
            } else c.unknown_option("projector", key, "eye, target, up, fov, parallel or aspect");
        }
        const glm::dvec3 view = p.target - p.eye;
        if (!(glm::length(view) > 0.0) || !std::isfinite(glm::length(view)))
            c.fail_at(view_at ? view_at : c.mark(), "the projector's eye and target must be apart (and within a double's range)");
        if (!(glm::length(glm::cross(glm::normalize(view), p.up)) > 0.0))
            c.fail("the projector's up must not be zero or parallel to its view");
        const glm::dmat4 look = glm::lookAtRH(p.eye, p.target, p.up);
        // (near and far do not matter: the image is x/w, y/w; w is the distance along the view)
        const glm::dmat4 lens = p.parallel ? glm::orthoRH_NO(-0.5 * p.height * p.aspect, 0.5 * p.height * p.aspect, -0.5 * p.height,
                                                             0.5 * p.height, -1.0, 1.0)
                                           : glm::perspectiveRH_NO(glm::radians(p.fov_y_degrees), p.aspect, 1.0, 2.0);
        p.matrix = lens * look;
        p.forward = glm::normalize(view);
        projector_index_[p.name] = int(scene_.projectors.size());
        scene_.projectors.push_back(p);
    }

    void light(Cursor& c) {
        Light l;
        l.kind = choose<Light::Kind>(c, "light kind", {{"directional", Light::Kind::directional}, {"point", Light::Kind::point}});
        l.vector = c.vec3(l.kind == Light::Kind::directional ? "the light direction" : "the light position");
        if (l.kind == Light::Kind::directional) {
            if (l.vector == glm::dvec3(0.0)) c.fail("light direction must not be zero");
            l.vector = glm::normalize(direction_scaled(l.vector));
        }
        while (!c.done()) {
            const std::string key = c.word("a light option");
            c.once(key);
            if (key == "color") l.color = c.color("light colour");
            else c.unknown_option("light", key, "color");
        }
        scene_.lights.push_back(l);
    }

    int material_named(Cursor& c, const std::string& name) {
        auto it = material_index_.find(name);
        if (it == material_index_.end()) c.fail("unknown material " + shown_name(name) + " (define it with a 'material' line first)");
        return it->second;
    }

    int default_material() {
        if (default_material_ < 0) {
            Material m;
            m.name = "(default)";
            m.color = default_color;
            default_material_ = int(scene_.materials.size());
            scene_.materials.push_back(m);
        }
        return default_material_;
    }

    // Object options shared by mesh, triangle and quad. Returns false for an unknown key.
    // `material_at`: where a `material` option named the material.
    // (translate, rotate and scale may repeat: each applies after those before it.)
    bool object_option(Cursor& c, const std::string& key, Object& object, int& material, std::size_t& material_at) {
        if (key == "material" || key == "cull") c.once(key);
        if (key == "material") material = material_named(c, c.word("a material name")), material_at = c.mark();
        else if (key == "cull") object.cull_back = choose<bool>(c, "cull mode", {{"back", true}, {"none", false}});
        else if (key == "translate") object.transform = glm::translate(glm::dmat4(1.0), c.vec3("translate")) * object.transform;
        else if (key == "rotate") {
            const double degrees = c.number("the rotation angle in degrees");
            const glm::dvec3 axis = c.vec3("the rotation axis");
            if (axis == glm::dvec3(0.0)) c.fail("rotation axis must not be zero");
            object.transform = glm::rotate(glm::dmat4(1.0), glm::radians(degrees), glm::normalize(direction_scaled(axis))) * object.transform;
        } else if (key == "scale") {
            glm::dvec3 s(c.number("a scale factor"));
            if (c.next_is_number()) {
                const std::string what = "1 or 3 scale factors (scale s, or scale sx sy sz)";
                s.y = c.number(what), s.z = c.number(what);
            }
            if (s.x == 0.0 || s.y == 0.0 || s.z == 0.0) c.fail("scale factors must not be zero");
            object.transform = glm::scale(glm::dmat4(1.0), s) * object.transform;
        } else return false;
        return true;
    }

    void mesh(Cursor& c) {
        const std::string given = c.word("an OBJ file name");
        const std::string path = relative_to(folder_, given);
        const std::size_t path_at = c.mark();  // OBJ, .mtl and map_Kd errors are reported at its line
        // 'mesh material m', the file forgotten: say that, not that 'm' is no mesh option.
        for (const char* option : {"material", "cull", "translate", "rotate", "scale"})
            if (struct stat file{}; given == option && !(::stat(path.c_str(), &file) == 0 && S_ISREG(file.st_mode)))
                c.fail("expected an OBJ file name after 'mesh', found " + shown_token(given) + ", one of its options (mesh FILE [options])");
        Object object;
        int material = -1;
        std::size_t material_at = 0;
        while (!c.done()) {
            const std::string key = c.word("a mesh option");
            if (!object_option(c, key, object, material, material_at))
                c.unknown_option("mesh", key, "material, cull, translate, rotate or scale");
        }
        // Each OBJ material is the scene material of the same name, else made from its .mtl.
        bool resolver_failed = false;  // its messages already name this line
        auto resolve = [&](const ObjMaterialInfo& info) {
            try {
                return resolve_material(c, path_at, info, material);
            } catch (...) {
                resolver_failed = true;
                throw;
            }
        };
        Mesh mesh;
        try {
            mesh = load_obj(path, resolve);
        } catch (const InputError& e) {
            if (resolver_failed) throw;
            c.fail_at(path_at, e.what());
        } catch (const std::bad_alloc&) {  // a huge mesh: say which
            c.fail_at(path_at, shown_path(path) + ": out of memory reading the OBJ file");
        }
        mesh.source = file_ + ":" + std::to_string(c.line_number());
        scene_.files.push_back(path);
        scene_.files.insert(scene_.files.end(), mesh.material_files.begin(), mesh.material_files.end());
        // (load_obj gives every vertex a normal: the file's, or computed where it gives none or
        // one of length 0)
        add_object(c, material >= 0 ? material_at : path_at, std::move(mesh), object, path);
    }

    // The scene material for an OBJ material: `material` if the mesh line names one, else the
    // scene material of the same name, else one made from its .mtl (or the default grey).
    int resolve_material(Cursor& c, std::size_t path_at, const ObjMaterialInfo& info, int material) {
        if (material >= 0) return material;
        if (info.name.empty()) return default_material();
        auto it = material_index_.find(info.name);
        if (it != material_index_.end()) return it->second;
        Material m;
        m.name = info.name;
        // .mtl Kd, taken as linear reflectance (read_obj_lines has checked its numbers); a
        // name no .mtl describes: the default grey.
        m.color = info.described ? info.diffuse : default_color;
        material_from_obj_[m.name] = c.line_of(path_at);
        if (!info.diffuse_texture.empty()) {
            Texture t;
            t.name = info.name + ".map_Kd";
            t.path = info.diffuse_texture;
            t.image = image(c, path_at, t.path, ColorSpace::srgb,
                            "OBJ material " + shown_name(info.name) + " (map_Kd in " + shown_path(info.mtl_file) + "): ");
            t.mipmap = mipmap(t.image, t.sampler);
            m.texture = int(scene_.textures.size());
            scene_.textures.push_back(std::move(t));
        }
        material_index_[m.name] = int(scene_.materials.size());
        scene_.materials.push_back(m);
        return material_index_[m.name];
    }

    void polygon(Cursor& c, int corners) {
        const std::string what = corners == 3 ? "triangle" : "quad";
        Object object;
        int material = -1;
        std::size_t material_at = 0;
        Mesh mesh;
        mesh.has_uv = true;
        bool any_normal = false;
        int normals_given = 0;
        int last_with_normal = 0, last_with_color = 0;  // how many vertices there were at the last 'n', 'c'
        int colors_given = 0;
        std::array<std::size_t, 4> vertex_at{}, normal_at{}, color_at{};  // the 'v', 'n', 'c' of each vertex (0: none)
        while (!c.done()) {
            const std::string key = c.word("a " + what + " option");
            if (key == "v") {
                if (int(mesh.vertices.size()) == corners) c.fail(what + " has more than " + std::to_string(corners) + " vertices");
                Vertex v;
                vertex_at[mesh.vertices.size()] = c.mark();
                v.position = c.float_vec3("the vertex position");
                v.uv = {c.number("the vertex's texture coordinate u"), c.number("the vertex's texture coordinate v")};
                mesh.vertices.push_back(v);
            } else if (key == "n" || key == "c") {
                if (mesh.vertices.empty()) c.fail(shown_token(key) + " belongs after a vertex 'v x y z u v'");
                if (key == "n") {
                    if (last_with_normal == int(mesh.vertices.size())) c.fail("a second normal 'n' for one vertex");
                    last_with_normal = int(mesh.vertices.size());
                    normal_at[mesh.vertices.size() - 1] = c.mark();
                    mesh.vertices.back().normal = c.float_vec3("the vertex normal");
                    any_normal = true, ++normals_given;
                }
                else {
                    if (last_with_color == int(mesh.vertices.size())) c.fail("a second colour 'c' for one vertex");
                    last_with_color = int(mesh.vertices.size());
                    color_at[mesh.vertices.size() - 1] = c.mark();
                    mesh.vertices.back().color = c.color("the vertex colour");
                    mesh.has_colors = true, ++colors_given;
                }
            } else if (!object_option(c, key, object, material, material_at)) {
                c.unknown_option(what, key, "v, n, c, material, cull, translate, rotate or scale");
            }
        }
        if (int(mesh.vertices.size()) != corners)
            c.fail(what + " needs " + std::to_string(corners) + " vertices 'v x y z u v', found " + std::to_string(mesh.vertices.size()));
        // Normals and colours on every vertex or on none (normals are then computed, colours
        // white): a vertex left out would silently keep a default. Reported at the first vertex
        // without one.
        const auto first_without = [&](const std::array<std::size_t, 4>& given) {
            for (int i = 0; i < corners; ++i)
                if (given[std::size_t(i)] == 0) return vertex_at[std::size_t(i)];
            return c.mark();
        };
        if (any_normal && normals_given != corners)
            c.fail_at(first_without(normal_at), what + " has a normal 'n' on " + std::to_string(normals_given) + " of its " + std::to_string(corners) +
                   " vertices: give one after every vertex, or none to have them computed");
        if (mesh.has_colors && colors_given != corners)
            c.fail_at(first_without(color_at), what + " has a colour 'c' on " + std::to_string(colors_given) + " of its " + std::to_string(corners) +
                   " vertices: give one after every vertex, or none");
        mesh.triangles.push_back({0, 1, 2});
        if (corners == 4) mesh.triangles.push_back({0, 2, 3});
        mesh.triangle_material.assign(mesh.triangles.size(), material >= 0 ? material : default_material());
        mesh.source = file_ + ":" + std::to_string(c.line_number());
        mesh.has_normals = any_normal;
        if (!any_normal) fill_smooth_normals(mesh);
        else replace_zero_normals(mesh);
        add_object(c, c.mark(), std::move(mesh), object, what);
    }

    // The lecture's parametric surfaces, with their (u, v) "directly derived from surface
    // parameterization", in the object's own space (z the axis; place them with the object
    // options):
    //   disc      p(u, v) = Polar2Cartesian(R v, 2 pi u)                = (R v cos 2 pi u, R v sin 2 pi u, 0)
    //   cylinder  p(u, v) = Cylindrical2Cartesian(r, 2 pi u, H v)       = (r cos 2 pi u, r sin 2 pi u, H v)
    //   sphere    p(u, v) = Spherical2Cartesian(r, pi v, 2 pi u)        = r (sin pi v cos 2 pi u, sin pi v sin 2 pi u, cos pi v)
    // meshed on a grid of `segments` steps of u and (sphere) half as many of v (disc: a quarter;
    // cylinder: one), each vertex at its exact p(u, v) with its exact (u, v) and normal; the
    // seam at u = 1 has vertices of its own. Triangles wind counter-clockwise seen from the
    // side the normal points to (outside; the disc's +z side); those of no area (at a pole, at
    // the disc's centre) are left out.
    void parametric(Cursor& c, const std::string& kind) {
        constexpr double pi = 3.14159265358979323846;
        const double radius = c.number("the " + kind + "'s radius");
        const double height = kind == "cylinder" ? c.number("the cylinder's height") : 0.0;
        if (!(radius > 0.0 && radius <= 1e18)) c.fail("the " + kind + "'s radius must be above 0 and at most 1e18");
        if (kind == "cylinder" && !(height > 0.0 && height <= 1e18)) c.fail("the cylinder's height must be above 0 and at most 1e18");
        Object object;
        int material = -1;
        std::size_t material_at = 0;
        int segments = 64;
        while (!c.done()) {
            const std::string key = c.word("a " + kind + " option");
            if (key == "segments") {
                c.once(key);
                const double n = c.number("the number of segments");
                // (a sphere of 1024 segments is 1M triangles, some 60 MB)
                if (!(n >= 8.0 && n <= 1024.0 && n == std::floor(n))) c.fail("segments must be a whole number from 8 to 1024");
                segments = int(n);
            } else if (!object_option(c, key, object, material, material_at)) {
                c.unknown_option(kind, key, "segments, material, cull, translate, rotate or scale");
            }
        }
        const int nu = segments, nv = kind == "sphere" ? segments / 2 : kind == "disc" ? segments / 4 : 1;
        const auto at = [&](double u, double v, glm::dvec3& normal) {
            const double phi = u == 1.0 ? 0.0 : 2.0 * pi * u;  // (the seam's vertices the same as u = 0's: sin 2 pi is not 0)
            if (kind == "disc") {
                normal = {0.0, 0.0, 1.0};
                return glm::dvec3(radius * v * std::cos(phi), radius * v * std::sin(phi), 0.0);
            }
            if (kind == "cylinder") {
                normal = {std::cos(phi), std::sin(phi), 0.0};
                return glm::dvec3(radius * std::cos(phi), radius * std::sin(phi), height * v);
            }
            // theta = pi (1 - v): texr's v runs up the image (v = 0 its bottom row), where the
            // slide's v = theta / pi counts from an image's top row; so the image's top is at
            // the +z pole and the texture is not mirrored on the sphere (as on the environment
            // map). At the poles exactly: sin(pi) is 1.2e-16, not 0.
            const double sin_theta = v == 0.0 ? 0.0 : std::sin(pi * (1.0 - v)), cos_theta = v == 0.0 ? -1.0 : std::cos(pi * (1.0 - v));
            normal = {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
            return radius * normal;
        };
        Mesh mesh;
        mesh.has_uv = true, mesh.has_normals = true;
        for (int j = 0; j <= nv; ++j)
            for (int i = 0; i <= nu; ++i) {
                Vertex vertex;
                const double u = double(i) / nu, v = double(j) / nv;
                glm::dvec3 normal;
                const glm::dvec3 p = at(u, v, normal);
                vertex.position = glm::vec3(p), vertex.normal = glm::vec3(normal), vertex.uv = {u, v};
                // A pole's (or the disc centre's) vertex serves the one triangle of its cell:
                // its u is the cell's middle, so that u runs straight into the point, not in a
                // pinwheel.
                // (the last row's apex (i, nv) serves cell i - 1)
                if ((kind == "sphere" || kind == "disc") && j == 0 && i < nu) vertex.uv.x = (i + 0.5) / nu;
                if (kind == "sphere" && j == nv && i > 0) vertex.uv.x = (i - 0.5) / nu;
                mesh.vertices.push_back(vertex);
            }
        const auto index = [&](int i, int j) { return std::uint32_t(j * (nu + 1) + i); };
        const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t d) {
            const glm::dvec3 pa(mesh.vertices[a].position), pb(mesh.vertices[b].position), pd(mesh.vertices[d].position);
            const glm::dvec3 area = glm::cross(pb - pa, pd - pa);
            // (two corners at one point: a pole, the disc's centre)
            if (!(glm::length(area) > 1e-12 * glm::dot(pb - pa, pb - pa) + 1e-12 * glm::dot(pd - pa, pd - pa))) return;
            const glm::dvec3 normal(mesh.vertices[a].normal + mesh.vertices[b].normal + mesh.vertices[d].normal);
            if (glm::dot(area, normal) < 0.0) std::swap(b, d);
            mesh.triangles.push_back({a, b, d});
        };
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                add(index(i, j), index(i + 1, j), index(i + 1, j + 1));
                add(index(i, j), index(i + 1, j + 1), index(i, j + 1));
            }
        mesh.triangle_material.assign(mesh.triangles.size(), material >= 0 ? material : default_material());
        mesh.source = file_ + ":" + std::to_string(c.line_number());
        add_object(c, c.mark(), std::move(mesh), object, kind);
    }

    // The lecture's billboard: a textured quad that turns to face the viewer, `turn axis`
    // (about the world's y axis: a tree stays upright) or `turn view` (towards the eye in
    // full). It is made when the file is read to the end (finish), so that the camera line may
    // come after it; its material is looked up now.
    void billboard(Cursor& c) {
        PendingBillboard b;
        b.line = c.line_number();
        std::size_t material_at = 0;
        while (!c.done()) {
            const std::string key = c.word("a billboard option");
            c.once(key);
            if (key == "material") b.material = material_named(c, c.word("a material name")), material_at = c.mark();
            else if (key == "center") b.center = c.vec3("the billboard's centre");
            else if (key == "size") {
                b.width = c.number("the billboard's width"), b.height = c.number("the billboard's height");
                if (!(b.width > 0.0 && b.height > 0.0 && b.width <= 1e18 && b.height <= 1e18))
                    c.fail("the billboard's width and height must be above 0 (and at most 1e18)");
            } else if (key == "turn") b.about_axis = choose<bool>(c, "billboard turn", {{"axis", true}, {"view", false}});
            else c.unknown_option("billboard", key, "material, center, size or turn");
        }
        if (!c.seen("center") || !c.seen("size")) c.fail("billboard needs 'center x y z' and 'size W H'");
        if (b.material < 0) b.material = default_material();
        const Material& m = scene_.materials[std::size_t(b.material)];
        if (m.bump >= 0) c.fail_at(material_at, "material " + shown_name(m.name) + " has a bump map: a billboard is flat, and turns");
        pending_billboards_.push_back(b);
    }

public:
    // Makes the billboards, facing the camera the whole file set up.
    void finish() {
        const Camera& camera = scene_.camera;
        for (const PendingBillboard& b : pending_billboards_) {
            const auto fail = [&](const std::string& message) { throw InputError(file_, b.line, message); };
            glm::dvec3 to_eye = camera.eye - b.center, up(0.0, 1.0, 0.0);
            if (b.about_axis) {
                to_eye.y = 0.0;
                // Straight above or below the eye it is seen edge-on whichever way it turns:
                // it faces against the camera's view (or up) instead, as seen from above.
                if (!(glm::length(to_eye) > 0.0)) to_eye = -(camera.target - camera.eye), to_eye.y = 0.0;
                if (!(glm::length(to_eye) > 0.0)) to_eye = -camera.up, to_eye.y = 0.0;
                if (!(glm::length(to_eye) > 0.0)) to_eye = glm::dvec3(0.0, 0.0, 1.0);
            }
            const double distance = glm::length(to_eye);
            if (!(distance > 0.0) || !std::isfinite(distance))
                fail(b.about_axis ? "the billboard's position is beyond a double's range"
                                  : "the eye is at the billboard's centre: it has no side to face");
            const glm::dvec3 f = to_eye / distance;
            if (!b.about_axis) {
                up = camera.up - glm::dot(camera.up, f) * f;  // the camera's up, square to the view
                if (!(glm::length(up) > 0.0)) up = glm::dvec3(0.0, 1.0, 0.0) - f.y * f;
                if (!(glm::length(up) > 0.0)) up = glm::dvec3(1.0, 0.0, 0.0) - f.x * f;
                up = glm::normalize(up);
            }
            const glm::dvec3 right = glm::cross(up, f);  // the viewer's right, as f points at the viewer
            const glm::dvec3 r = 0.5 * b.width * right, u = 0.5 * b.height * up;
            Mesh mesh;
            mesh.has_uv = true, mesh.has_normals = true;
            const glm::dvec3 corners[4] = {b.center - r - u, b.center + r - u, b.center + r + u, b.center - r + u};
            const glm::dvec2 uvs[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int k = 0; k < 4; ++k) {
                Vertex v;
                v.position = glm::vec3(corners[k]);
                if (!std::isfinite(v.position.x) || !std::isfinite(v.position.y) || !std::isfinite(v.position.z))
                    fail("the billboard's corners are beyond a float's range");
                v.normal = glm::vec3(f), v.uv = uvs[k];
                mesh.vertices.push_back(v);
            }
            mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
            mesh.triangle_material.assign(2, b.material);
            mesh.source = file_ + ":" + std::to_string(b.line);
            Object object;
            object.mesh = int(scene_.meshes.size());
            scene_.meshes.push_back(std::move(mesh));
            scene_.objects.push_back(object);
        }
    }

private:
    // `at`: the token errors are reported at (a mesh's `material` option, or else its file name;
    // a polygon's last word).
    void add_object(Cursor& c, std::size_t at, Mesh mesh, Object object, const std::string& what) {
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            const Material& m = scene_.materials[std::size_t(mesh.triangle_material[t])];
            // (a solid texture reads the world position, not the mesh's UVs)
            const bool solid = m.texture >= 0 && scene_.textures[std::size_t(m.texture)].procedural &&
                               scene_.textures[std::size_t(m.texture)].procedural->solid;
            const bool own_uv = m.texture >= 0 && !solid && m.projector < 0 && m.mapping.kind == Intermediate::none;
            const bool reads_uv = own_uv || m.bump >= 0 || m.lightmap >= 0;
            if (reads_uv && !mesh.has_uv && (mesh.triangle_without_uv.empty() || mesh.triangle_without_uv[t]))
                c.fail_at(at, what + " has faces without texture coordinates (vt) drawn with material " + shown_name(m.name) +
                                  ", which uses texture " +
                                  shown_name(scene_.textures[std::size_t(own_uv                                      ? m.texture
                                                                         : m.bump >= 0                                      ? m.bump
                                                                                                                            : m.lightmap)]
                                                 .name) +
                                  (own_uv ? "" : m.bump >= 0 ? " as its bump map" : " as its light map"));
        }
        object.mesh = int(scene_.meshes.size());
        scene_.meshes.push_back(std::move(mesh));
        scene_.objects.push_back(object);
    }

    // A normal of length 0 (`n 0 0 0` on a triangle or quad; an OBJ's `vn 0 0 0`, which some
    // exporters write for degenerate faces, load_obj replaces) has no direction: shading would
    // normalise it to NaN. Such vertices take the computed normal.
    static void replace_zero_normals(Mesh& mesh) {
        const auto zero = [](const Vertex& v) { return v.normal == glm::vec3(0.0f); };
        if (std::none_of(mesh.vertices.begin(), mesh.vertices.end(), zero)) return;
        const std::vector<glm::vec3> computed = smooth_normals(mesh);
        for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
            if (zero(mesh.vertices[i])) mesh.vertices[i].normal = computed[i];
    }

    static void fill_smooth_normals(Mesh& mesh) {
        const std::vector<glm::vec3> computed = smooth_normals(mesh);
        for (std::size_t i = 0; i < mesh.vertices.size(); ++i) mesh.vertices[i].normal = computed[i];
    }

    // Area-weighted average of the face normals at each vertex (right-handed winding).
    static std::vector<glm::vec3> smooth_normals(const Mesh& mesh) {
        std::vector<glm::dvec3> sum(mesh.vertices.size(), glm::dvec3(0.0));
        for (const auto& t : mesh.triangles) {
            const glm::dvec3 a(mesh.vertices[t[0]].position), b(mesh.vertices[t[1]].position), c(mesh.vertices[t[2]].position);
            const glm::dvec3 n = glm::cross(b - a, c - a);
            for (auto i : t) sum[i] += n;
        }
        std::vector<glm::vec3> normals(sum.size());
        for (std::size_t i = 0; i < sum.size(); ++i) {
            const double len = glm::length(sum[i]);
            normals[i] = len > 0.0 ? glm::vec3(sum[i] / len) : glm::vec3(0.0f, 0.0f, 1.0f);
        }
        return normals;
    }

    Scene& scene_;
    const std::string& file_;
    std::string folder_;
    std::map<std::string, int> texture_index_, material_index_;
    std::map<std::string, int> defined_on_;  // "texture 't'" / "material 'm'": the line that defined it
    std::map<std::string, int> projector_index_;
    std::map<std::string, int> settings_line_;  // size, camera, background, ambient: the line of each
    struct PendingBillboard {
        int line = 0, material = -1;
        glm::dvec3 center{0.0};
        double width = 1.0, height = 1.0;
        bool about_axis = true;
    };
    std::vector<PendingBillboard> pending_billboards_;
    std::map<std::string, int> material_from_obj_;  // materials an OBJ's usemtl made: the line of the mesh's file name
    std::map<std::string, std::shared_ptr<const Image>> images_;
    using MipKey = std::tuple<const Image*, bool, Wrap, Wrap, std::array<float, 4>>;
    std::map<MipKey, std::shared_ptr<MipMap>> mipmaps_;
    int default_material_ = -1;
    // The default material's colour (a light grey), also given to a usemtl name that neither
    // the scene nor a .mtl file describes.
    const Color default_color = Color(srgb_to_linear(0.8f));
};

}  // namespace

Scene parse_scene(std::istream& in, const std::string& path) {
    Scene scene;
    scene.path = path;
    scene.files.push_back(path);
    Parser parser(scene, path);
    for (const Line& line : read_lines(in, path)) parser.command(line);
    parser.finish();
    if (scene.objects.empty()) throw InputError(path, 0, "scene has no objects (add a mesh, triangle, quad or billboard line)");
    return scene;
}

Scene load_scene(const std::string& path) {
    require_file(path, "a scene file");
    std::ifstream in(path);
    if (!in) throw InputError(path, 0, "cannot open scene file");
    return parse_scene(in, path);
}

}  // namespace texr
