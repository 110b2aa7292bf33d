// OBJ loading with tinyobjloader (see include/texr/scene/obj_mesh.h).
#include "texr/scene/obj_mesh.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "texr/core/color.h"
#include "texr/core/error.h"
#include "texr/core/path.h"
#include "texr/core/text_line.h"

namespace texr {

namespace {

// First line of tinyobjloader's message, without its trailing newline.
std::string first_line(const std::string& text) {
    const auto end = text.find('\n');
    return end == std::string::npos ? text : text.substr(0, end);
}

// What texr reads of an OBJ file itself, line by line, before tinyobjloader parses it:
//  - every v, vt and vn line must hold numbers only (3, 4 (x y z w) or 6 (x y z r g b, the
//    colour from 0 to max_color) for v, 3 for vn, at least one for vt), finite ones, each
//    read as tinyobjloader reads it (see v_numbers); tinyobjloader reads "x" or a missing
//    coordinate as 0 without a word;
//  - whether the vertices have colours (`colors`): on every v line or on none;
//  - every face corner must name a position (and any vt or vn) of the file (negative indices
//    count back from the last one defined above the face); tinyobjloader skips a quad with a
//    bad index, with only a warning, which would also shift every later face's material;
//  - the `usemtl` name in force for each triangle, in file order (a face of k vertices is
//    k - 2 triangles, as face_triangles splits it), as an index into `names`: the name
//    is the word after `usemtl` (a tab or a # comment ends it, as in tinyobjloader);
//  - whether tinyobjloader needs the file's text without its comments (it takes the '#' of
//    'f 1 2 3 # a comment' for an index), without a UTF-8 byte order mark (which it would
//    read as part of the first keyword) and with continued lines joined (it does not join
//    them): `clean`.
// A bad line throws InputError with the OBJ file and line. Lines are split by hand: a string
// stream per line made this pass slower than tinyobjloader's own parse.
struct ObjLines {
    std::vector<std::string> names{std::string()};  // names[0]: before any usemtl
    std::vector<std::uint32_t> per_triangle;
    // Each face's corners, in file order (tinyobjloader keeps a face's count in an unsigned
    // char: 256 corners read as 0).
    std::vector<std::size_t> face_corners;
    // Each face's smoothing group: 0 under `s off` or `s 0` (the face is flat: its corners
    // without a normal take the face's own), 1 before any `s` line (smoothed together, as in
    // a file without `s` lines), 2 and up the `s` numbers in order of first use.
    std::vector<std::uint32_t> face_group;
    bool clean = false;
    std::vector<std::string> material_files;  // the .mtl files read
    bool colors = false;  // every v line has a colour (v x y z r g b)
    // Each v, vn and vt line's numbers as texr reads them, and the line: what tinyobjloader
    // stores is compared with them (same_numbers, in floats, as tinyobjloader keeps them), as
    // its reading differs in corners (0e500 is NaN to it, and 0 here). Positions, colours and
    // normals as floats, as the mesh keeps them; each vt line's u and v (v = 0 where not
    // given) as doubles, which the mesh takes (as a scene file's triangles do): floats would
    // keep UVs near 1e5 to 1/128 of a period.
    std::vector<float> v_numbers, v_rgb, vn_numbers;
    std::vector<double> vt_numbers;
    std::vector<int> v_lines, vn_lines, vt_lines;
};

// One line of an OBJ file as texr reads it: without its comment (and, on the first line, a
// UTF-8 byte order mark), and joined with the lines after it while it ends in '\\' (the OBJ
// format's continued line; a '\\' in a comment does not continue it), each '\\' read as a
// space.
struct ObjLine {
    std::string text;
    int taken = 0;             // the file's lines it took
    bool cleaned = false;      // a byte order mark, a comment after words, or a '\\' removed
    bool open_at_end = false;  // its last line ends in '\\', and the file there
};
bool read_obj_line(TextLineReader& in, bool first, ObjLine& line) {
    line.taken = 0, line.cleaned = false, line.open_at_end = false;
    std::string& text = line.text;  // (the first line read straight into it: most are the whole line)
    std::string part;
    for (;;) {
        const std::size_t start = line.taken == 0 ? 0 : text.size();  // where this line of the file begins in text
        if (line.taken == 0) {
            if (!in.next(text)) return false;
        } else {
            if (!in.next(part)) return line.open_at_end = true;
            text += part;
        }
        if (first && line.taken == 0 && text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3), line.cleaned = true;
        ++line.taken;
        const std::size_t comment = text.find('#', start);  // (with or without a space before it)
        if (comment != std::string::npos) {
            line.cleaned = line.cleaned || text.find_first_not_of(" \t", start) < comment;  // after something
            text.erase(comment);
        }
        const std::size_t last = text.find_last_not_of(" \t\v\f");
        if (last == std::string::npos || last < start || text[last] != '\\') return true;
        text.erase(last) += ' ';
        line.cleaned = true;
    }
}

// The file's lines as read_obj_line reads them, each followed by as many line ends as it
// took lines of the file (so tinyobjloader's line numbers stay right).
std::string text_without_comments(const std::string& path) {
    std::ifstream file(path);
    TextLineReader in(file);
    std::string text;
    ObjLine line;
    for (bool first = true; read_obj_line(in, first, line); first = false) text.append(line.text).append(std::size_t(line.taken), '\n');
    return text;
}

// The number in `word` (all of it), or nullopt; beyond the range of a double, infinite (or 0).
std::optional<double> number_in(std::string_view word) {
    if (!word.empty() && word[0] == '+') word.remove_prefix(1);  // (from_chars takes no '+')
    double value = 0.0;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (end != word.data() + word.size()) return std::nullopt;
    if (error == std::errc::result_out_of_range) return std::strtod(std::string(word).c_str(), nullptr);  // +-inf, or 0 or subnormal
    if (error != std::errc()) return std::nullopt;
    return value;
}

// Whether tinyobjloader gives up on the number in `word` (which number_in read): it reads
// an exponent's digits into an int, and stops before one that would overflow it (past
// 214748364); it then reads no vertex colours at all, or 0 for the number.
bool exponent_too_long_for_tinyobj(std::string_view word) {
    const std::size_t e = word.find_first_of("eE");
    if (e == std::string_view::npos) return false;
    long long exponent = 0;
    for (const char c : word.substr(e + 1)) {
        if (c < '0' || c > '9') continue;  // (its sign)
        if (exponent > 214748364) return true;
        exponent = exponent * 10 + (c - '0');
    }
    return false;
}

// The numbers tinyobjloader stored (`got`: positions, colours, normals or texture
// coordinates, `per_line` a line) against texr's reading of the same lines (`want`, with
// their lines): the same within rounding (the two parsers may round a digit string to
// floats an ulp apart), or the first line where they differ is refused.
void same_numbers(const std::string& path, const std::vector<float>& got, const std::vector<float>& want,
                  const std::vector<int>& lines, std::size_t per_line, const char* keyword) {
    for (std::size_t k = 0; k < std::min(got.size(), want.size()); ++k) {
        const float a = got[k], b = want[k];
        if (a == b || std::fabs(a - b) <= 1e-5f * std::max(std::fabs(a), std::fabs(b)) || std::fabs(a - b) < 1e-36f) continue;
        char text[96];
        std::snprintf(text, sizeof text, "%.9g as %.9g", double(b), std::isnan(a) ? std::fabs(double(a)) : double(a));  // (nan, not -nan)
        throw InputError(path, lines[k / per_line], "the OBJ parser (tinyobjloader) reads the number " + std::string(text) +
                                                        " on this " + keyword + " line: write it plainly");
    }
    if (got.size() != want.size())
        throw InputError(path, 0, "the OBJ parser (tinyobjloader) read " + std::to_string(got.size() / per_line) + " " + keyword +
                                      " lines' numbers where texr read " + std::to_string(want.size() / per_line));
}

// A face corner's index (1-based, or negative: counting back from the last one defined), or
// nullopt if `word` is no whole number.
std::optional<long long> index_in(std::string_view word) {
    long long value = 0;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (error != std::errc() || end != word.data() + word.size()) return std::nullopt;
    return value;
}

// The file names on an mtllib line, split as tinyobjloader splits them: the text from one
// character after the keyword, at spaces only (a tab is part of a name), with '\\' making
// the next character part of the name; the last, possibly empty, name is kept.
std::vector<std::string> mtllib_names(const std::string& text) {
    std::vector<std::string> names;
    std::string name;
    bool escaped = false;
    for (const char ch : text) {
        if (escaped) escaped = false;
        else if (ch == '\\') { escaped = true; continue; }
        else if (ch == ' ') {
            if (!name.empty()) names.push_back(name);
            name.clear();
            continue;
        }
        name += ch;
    }
    names.push_back(name);
    return names;
}

// A .mtl file's text, checked, for tinyobjloader to read (lines end at LF, CR or CRLF, as it
// reads them). Its Kd colours: tinyobjloader reads a word that is not a number as 0 and takes
// 'Kd 0.5' as (0.5, 0, 0); texr wants 1 number (a grey, as the MTL format reads it) or 3,
// each from 0 to max_color (scene.h), on every Kd line, and hands tinyobjloader a grey as
// 'Kd g g g' on the same line. And map_Kd lines without texture options.
std::string checked_mtl_text(const std::string& mtl, const std::string& text) {
    // (Lines as TextLineReader splits them, each handed on with an LF; a UTF-8 byte order
    // mark, which tinyobjloader would read as part of the first keyword, left out.)
    const auto checked = [&](const std::string& raw, int line_number) -> std::string {
        std::istringstream words(raw.substr(0, raw.find('#')));
        std::string keyword, word;
        if (!(words >> keyword)) return raw;
        if (keyword == "map_Kd") {
            // Texture options (-s scale, -o offset, -clamp, -bm, ...): tinyobjloader reads
            // them, texr would draw the image without them; refused rather than ignored.
            // (tinyobjloader's options, each a word of its own; another word, '-grid.png' say,
            // is a file name)
            static const char* const options[] = {"-blendu", "-blendv", "-bm",  "-boost", "-clamp", "-colorspace", "-imfchan",
                                                  "-mm",     "-o",      "-s",   "-t",     "-texres", "-type"};
            while (words >> word)
                for (const char* option : options)
                    if (word == option)
                        throw InputError(mtl, line_number, "map_Kd option " + shown_token(word) + " is not supported (texr reads the image alone): remove it");
            return raw;
        }
        if (keyword != "Kd") return raw;
        int count = 0;
        std::string grey;  // the first number
        while (words >> word) {
            const std::optional<double> value = number_in(word);
            if (!value || !(*value >= 0.0 && *value <= max_color))
                throw InputError(mtl, line_number, "Kd needs numbers from 0 to " + max_color_text() + ", got " + shown_token(word));
            if (count++ == 0) grey = word;
        }
        if (count != 1 && count != 3)
            throw InputError(mtl, line_number, "Kd needs 3 numbers (or 1, a grey), got " + std::to_string(count));
        return count == 1 ? "Kd " + grey + " " + grey + " " + grey : raw;
    };
    std::istringstream in(text);
    TextLineReader lines(in);
    std::string out, raw;
    out.reserve(text.size());
    for (int line_number = 1; lines.next(raw); ++line_number) {
        if (line_number == 1 && raw.rfind("\xEF\xBB\xBF", 0) == 0) raw.erase(0, 3);
        out += checked(raw, line_number);
        out += '\n';
    }
    return out;
}

// The .mtl files tinyobjloader reads, opened next to the OBJ (its own reader takes ':' in
// the folder's path as a separator), their Kd lines checked before it reads them.
class MtlReader : public tinyobj::MaterialReader {
public:
    explicit MtlReader(std::string folder) : folder_(std::move(folder)) {}
    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials, std::map<std::string, int>* names,
                    std::string* warning, std::string* error) override {
        const std::string path = folder_ + name;
        std::ifstream in(path, std::ios::binary);
        if (name.empty() || !in) return false;
        std::ostringstream text;
        text << in.rdbuf();
        std::istringstream stream(checked_mtl_text(path, text.str()));
        tinyobj::LoadMtl(names, materials, &stream, warning, error);
        sources_.resize(materials->size(), path);  // (LoadMtl appends this file's materials)
        return true;
    }
    // The .mtl file that the material at `index` of LoadObj's list came from ("" for none:
    // every material it lists comes from a file read here).
    std::string source(std::size_t index) const { return index < sources_.size() ? sources_[index] : std::string(); }

private:
    std::string folder_;
    std::vector<std::string> sources_;  // by material index
};

ObjLines read_obj_lines(const std::string& path) {
    std::ifstream file(path);
    TextLineReader in(file);
    ObjLines out;
    std::map<std::string, std::uint32_t> index_of{{std::string(), 0}};
    std::uint32_t current = 0;
    std::map<std::string, std::uint32_t> group_of;  // an `s` number (no leading zeros) -> its face_group
    std::uint32_t group = 1;
    long long positions = 0, uvs = 0, normals = 0;  // defined so far
    long long colored = 0;  // v lines with a colour
    int first_colored = 0, first_plain = 0;  // the lines of the first v with a colour and without
    struct Reference {  // a face's positive index past what is defined above it
        long long index;
        int part, line;
    };
    std::vector<Reference> ahead;  // checked against the whole file's counts at its end
    std::set<std::string> mtl_loaded;  // .mtl names an mtllib line has loaded
    const char* const what[3] = {"vertex", "texture coordinate (vt)", "normal (vn)"};  // by part of a corner
    // Words are split at spaces and tabs, as tinyobjloader splits them (a vertical tab or form
    // feed is part of a word: '1\v2' is no number).
    const auto space = [](char c) { return c == ' ' || c == '\t'; };
    ObjLine read;
    // (line_number: the first of the lines a continued line takes, where its errors are told)
    for (int line_number = 1; read_obj_line(in, line_number == 1, read); line_number += read.taken) {
        const auto fail = [&](const std::string& message) { throw InputError(path, line_number, message); };
        if (read.open_at_end)  // (as in scene files)
            throw InputError(path, line_number + read.taken - 1, "line ends with '\\' but the file ends there");
        out.clean = out.clean || read.cleaned;
        const std::string& line = read.text;
        std::size_t i = 0;
        const auto next_word = [&] {  // the word at i, and i past it
            while (i < line.size() && space(line[i])) ++i;
            const std::size_t start = i;
            while (i < line.size() && !space(line[i])) ++i;
            return std::string_view(line).substr(start, i - start);
        };
        const std::string_view keyword = next_word();
        if (keyword == "v" || keyword == "vt" || keyword == "vn") {
            int count = 0;
            double values[6] = {};
            for (std::string_view word = next_word(); !word.empty(); word = next_word(), ++count) {
                const std::optional<double> value = number_in(word);
                if (!value) fail("expected a number after " + shown_token(std::string(keyword)) + ", got " + shown_token(std::string(word)));
                if (!std::isfinite(*value)) fail("expected a finite number, got " + shown_token(std::string(word)));
                // tinyobjloader keeps positions, normals and texture coordinates as floats.
                if (!(std::fabs(*value) <= double(std::numeric_limits<float>::max())))
                    fail(shown_token(std::string(word)) + " is beyond a float's range (about 3.4e38)");
                if (exponent_too_long_for_tinyobj(word))
                    fail(shown_token(std::string(word)) + ": an exponent the OBJ parser (tinyobjloader) cannot read; write the number plainly");
                if (count < 6) values[count] = *value;
            }
            if (keyword == "v" && count < 3) fail("a vertex position (v) needs x, y and z");
            // (tinyobjloader would read 5 numbers as no colour, and 7 as x y z, a colour and one
            // more: neither is a form of the format)
            if (keyword == "v" && (count == 5 || count > 6))
                fail("a vertex (v) holds x y z, x y z w or x y z r g b (a colour), not " + std::to_string(count) + " numbers");
            if (keyword == "v" && count == 6) {
                for (int k = 3; k < 6; ++k)
                    if (!(values[k] >= 0.0 && values[k] <= max_color))
                        fail("a vertex colour (v x y z r g b) needs r, g and b from 0 to " + max_color_text());
                if (++colored == 1) first_colored = line_number;
            } else if (keyword == "v" && first_plain == 0) {
                first_plain = line_number;
            }
            if (keyword == "vn" && count != 3) fail("a normal (vn) needs x, y and z");
            if (keyword == "vt" && count < 1) fail("a texture coordinate (vt) needs u (and v)");
            (keyword == "v" ? positions : keyword == "vt" ? uvs : normals) += 1;
            const auto keep = [&](std::vector<float>& to, int from, int n) {
                for (int k = from; k < from + n; ++k) to.push_back(float(values[k]));
            };
            if (keyword == "v") keep(out.v_numbers, 0, 3), out.v_lines.push_back(line_number);
            if (keyword == "v" && count == 6) keep(out.v_rgb, 3, 3);
            if (keyword == "vn") keep(out.vn_numbers, 0, 3), out.vn_lines.push_back(line_number);
            if (keyword == "vt") {
                out.vt_numbers.push_back(values[0]), out.vt_numbers.push_back(values[1]);  // (values[1]: 0 if not given)
                out.vt_lines.push_back(line_number);
            }
        } else if (keyword == "mtllib") {
            // tinyobjloader opens these itself, next to the OBJ: no folder or device (a review's
            // `mtllib ../../dev/zero` read until memory ran out).
            // A missing .mtl file is refused too (its materials would silently turn grey);
            // tinyobjloader reads the first of the names that opens, so one must exist, and
            // its Kd lines are checked here, where their lines are known.
            // (tinyobjloader skips a file an earlier mtllib line loaded, and tries the next.)
            std::string names;
            bool found = false;
            const std::string rest = i < line.size() ? line.substr(i + 1) : std::string();
            for (const std::string& name : mtllib_names(rest)) {
                if (name.empty()) continue;
                const std::string mtl = folder_of(path) + name;
                try {
                    require_file(mtl, "a .mtl file");
                } catch (const InputError& e) {
                    fail("mtllib: " + std::string(e.what()));
                }
                if (mtl_loaded.count(name) > 0) { found = true; continue; }
                names += (names.empty() ? "" : ", ") + shown_path(mtl);
                if (std::ifstream(mtl)) {
                    found = true;
                    mtl_loaded.insert(name);
                    out.material_files.push_back(mtl);
                    break;
                }
            }
            if (!found && !names.empty()) fail("mtllib: cannot open " + names);
        } else if (keyword == "usemtl") {
            const std::string_view word = next_word();
            if (word.empty()) continue;  // no name: the material in force stays
            const std::string name(word);
            current = index_of.emplace(name, std::uint32_t(out.names.size())).first->second;
            if (current == out.names.size()) out.names.push_back(name);
        } else if (keyword == "s") {
            // `s N` smooths the faces that follow with the other faces of group N (a whole
            // number of any length; `s on`, which some exporters write, is group 1); `s off`
            // or `s 0` makes them flat.
            std::string_view word = next_word();
            const bool digits = !word.empty() && word.find_first_not_of("0123456789") == std::string_view::npos;
            if (word != "off" && word != "on" && !digits)
                fail("a smoothing group (s) is a whole number, on or off, not " + (word.empty() ? std::string("nothing") : shown_token(std::string(word))));
            const std::string_view extra = next_word();
            if (!extra.empty())
                fail("a smoothing group (s) line holds one group, not " + shown_token(std::string(word)) + " and " + shown_token(std::string(extra)));
            if (word == "on") word = "1";
            const std::size_t first = word.find_first_not_of('0');
            if (word == "off" || first == std::string_view::npos) {
                group = 0;
            } else {
                group = group_of.emplace(std::string(word.substr(first)), std::uint32_t(group_of.size() + 2)).first->second;
            }
        } else if (keyword == "f") {
            std::size_t corners = 0;
            for (std::string_view corner = next_word(); !corner.empty(); corner = next_word(), ++corners) {
                // v, v/vt, v//vn or v/vt/vn: a negative index counts back from what is defined
                // so far; a positive one past that is checked against the whole file at its end.
                const long long defined[3] = {positions, uvs, normals};
                // At most two slashes, and none at the end ('1/', '1//' or '1/2/': a corner cut
                // short, which tinyobjloader would read as index 0).
                if (std::count(corner.begin(), corner.end(), '/') > 2 || corner.back() == '/')
                    fail("expected a face corner (v, v/vt, v//vn or v/vt/vn), got " + shown_token(std::string(corner)));
                std::size_t start = 0;
                for (int part = 0; part < 3 && start <= corner.size(); ++part) {
                    const std::size_t slash = std::min(corner.find('/', start), corner.size());
                    const std::string_view word = corner.substr(start, slash - start);
                    start = slash + 1;
                    if (word.empty() && part > 0) continue;  // v//vn, or no vt/vn at all
                    const std::optional<long long> index = index_in(word);
                    if (!index || *index == 0) fail("expected a face corner (v, v/vt, v//vn or v/vt/vn), got " + shown_token(std::string(corner)));
                    const long long resolved = *index > 0 ? *index : defined[part] + 1 + *index;
                    if (resolved < 1) fail("face refers to a " + std::string(what[part]) + " that does not exist (" + std::string(word) + ")");
                    if (resolved > defined[part]) ahead.push_back({resolved, part, line_number});
                }
            }
            if (corners < 3) fail("a face (f) needs at least 3 corners");
            out.face_corners.push_back(corners);
            out.face_group.push_back(group);
            for (std::size_t k = 2; k < corners; ++k) out.per_triangle.push_back(current);
        }
    }
    const long long defined[3] = {positions, uvs, normals};
    for (const Reference& r : ahead)
        if (r.index > defined[r.part])
            throw InputError(path, r.line, "face refers to a " + std::string(what[r.part]) + " that does not exist (" + std::to_string(r.index) + ")");
    // Vertex colours on every vertex or on none, as for a scene file's triangles and quads.
    if (colored > 0 && colored < positions)
        throw InputError(path, first_plain, "a vertex without a colour: vertex colours (v x y z r g b) are on " + std::to_string(colored) +
                                                " of the file's " + std::to_string(positions) + " vertices (the first at line " +
                                                std::to_string(first_colored) + "); give one on every v line, or none");
    out.colors = colored > 0;
    return out;
}

// Twice a face's vector area (Newell's method): along its normal, by its winding, for any
// number of corners.
glm::dvec3 newell_area(const std::vector<glm::vec3>& p) {
    glm::dvec3 sum(0.0);
    for (std::size_t i = 0; i < p.size(); ++i) {
        const glm::dvec3 a(p[i]), b(p[(i + 1) % p.size()]);
        sum += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    return sum;
}

// The normal of a flat face (s off) of corners p: its vector area made unit, or, where that
// area is below 1e-4 of the sum of its fan triangles' areas (from the first corner), the
// normal of the largest of those triangles (the first of equal ones), which lies across the
// face's plane; +z where every one is 0. The second case is a face whose outline crosses
// itself so that its parts' windings cancel, such as a bow-tie: its vector area is 0 but for
// the rounding of its corners, whose direction would be noise (tens of degrees off the plane's
// normal for corners written to 6 decimals).
glm::vec3 flat_face_normal(const std::vector<glm::vec3>& p, const glm::dvec3& area) {
    glm::dvec3 largest(0.0);
    double largest_length = 0.0, fan = 0.0;
    for (std::size_t i = 1; i + 1 < p.size(); ++i) {
        const glm::dvec3 c = glm::cross(glm::dvec3(p[i]) - glm::dvec3(p[0]), glm::dvec3(p[i + 1]) - glm::dvec3(p[0]));
        const double length = glm::length(c);
        fan += length;
        if (length > largest_length) largest = c, largest_length = length;
    }
    const double length = glm::length(area);
    if (length > 0.0 && !(length < 1e-4 * fan)) return glm::vec3(area / length);  // (as GroupNormals::unit_or_z)
    return largest_length > 0.0 ? glm::vec3(largest / largest_length) : glm::vec3(0.0f, 0.0f, 1.0f);
}

// A face's triangles, as corner numbers of the face (k - 2 of them for k corners, each
// turning as the face does). tinyobjloader's own split (asked for with triangulate) goes wrong
// on concave faces: a quad along its shorter diagonal even where that lies outside, and 5
// corners or more by an ear test measured about the origin, which drops or adds area
// depending on where the face is. Here:
//  - a quad along its shorter diagonal (tinyobjloader's rule, worked out in float as it does,
//    so that the usual quads split as before), unless a triangle of that split turns against
//    the face in its plane (below): then along the other;
//  - 5 to 256 corners by ear clipping in the face's plane (projected along the normal's
//    largest axis): a corner with no area (straight, or a spike's tip) is cut off first, else
//    an ear, a corner whose triangle turns as the face does and lies where the face winds
//    once (is_ear, below); where none is (a face whose edges cross), a corner that looks
//    like one (looks_like_ear), else the first;
//  - a face with no area (its normal 0) or of more than 256 corners (ear clipping takes time
//    growing as the cube of the corners) as a fan from its first corner.
// `normal`: newell_area(p). (Into `out`, emptied first: one list for all of a file's faces.)
void face_triangles(const std::vector<glm::vec3>& p, const glm::dvec3& normal, std::vector<std::array<std::size_t, 3>>& out) {
    const std::size_t n = p.size();
    out.clear();
    if (n == 3) {
        out.push_back({0, 1, 2});
        return;
    }
    const glm::dvec3 size = glm::abs(normal);
    const bool flat = !(size.x + size.y + size.z > 0.0);  // no area (or NaN)
    if ((flat && n != 4) || n > 256) {
        for (std::size_t i = 1; i + 1 < n; ++i) out.push_back({0, i, i + 1});
        return;
    }
    // The plane's axes, in the order that makes the face turn counter-clockwise.
    const int drop = size.x >= size.y && size.x >= size.z ? 0 : size.y >= size.z ? 1 : 2;
    const int first = (drop + 1) % 3, second = (drop + 2) % 3;
    const bool flip = normal[drop] < 0.0;
    std::vector<glm::dvec2> q(n);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2 point(p[i][first], p[i][second]);
        q[i] = flip ? glm::dvec2(point.y, point.x) : point;
    }
    // Twice the signed area of a b c: positive where it turns counter-clockwise.
    const auto turn = [](const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
        return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    };
    const auto cross = [&](std::size_t a, std::size_t b, std::size_t c) { return turn(q[a], q[b], q[c]); };
    if (n == 4) {
        const glm::vec3 e02 = p[2] - p[0], e13 = p[3] - p[1];
        const bool along_02 = glm::dot(e02, e02) < glm::dot(e13, e13);
        // (in the plane: a quad far from flat, such as a terrain's, still splits the short way
        // where it is convex seen along its normal)
        const bool fits_02 = flat || (cross(0, 1, 2) >= 0.0 && cross(0, 2, 3) >= 0.0);
        const bool fits_13 = flat || (cross(0, 1, 3) >= 0.0 && cross(1, 2, 3) >= 0.0);
        if (along_02 ? fits_02 || !fits_13 : !fits_13 && fits_02)
            out.insert(out.end(), {{0, 1, 2}, {0, 2, 3}});
        else
            out.insert(out.end(), {{0, 1, 3}, {1, 2, 3}});
        return;
    }
    std::vector<std::size_t> left(n);
    for (std::size_t i = 0; i < n; ++i) left[i] = i;
    // Whether edge d e has a point inside the open triangle a b c (counter-clockwise): true
    // unless a line keeps them apart, and for a triangle and a segment the lines to try are
    // those of the triangle's three sides and the segment's own. An edge along a side, or one
    // that meets the triangle at a corner only, does not enter; nor do the triangle's sides.
    const auto enters = [&](std::size_t a, std::size_t b, std::size_t c, std::size_t d, std::size_t e) {
        if ((cross(a, b, d) <= 0.0 && cross(a, b, e) <= 0.0) || (cross(b, c, d) <= 0.0 && cross(b, c, e) <= 0.0) ||
            (cross(c, a, d) <= 0.0 && cross(c, a, e) <= 0.0))
            return false;
        if (q[d] == q[e]) return true;  // an edge of no length, inside (it has no line)
        const double sa = cross(d, e, a), sb = cross(d, e, b), sc = cross(d, e, c);
        return !((sa >= 0.0 && sb >= 0.0 && sc >= 0.0) || (sa <= 0.0 && sb <= 0.0 && sc <= 0.0));
    };
    // How many times what is left of the face winds around the point g (counter-clockwise
    // positive): each edge that passes g's row counts +1 upward with g on its left, -1
    // downward with g on its right.
    const auto winding = [&](const glm::dvec2& g) {
        int w = 0;
        const std::size_t m = left.size();
        for (std::size_t j = 0; j < m; ++j) {
            const glm::dvec2 d = q[left[j]], e = q[left[(j + 1) % m]];
            const double side = turn(d, e, g);
            if (d.y <= g.y) {
                if (e.y > g.y && side > 0.0) ++w;
            } else if (e.y <= g.y && side < 0.0) {
                --w;
            }
        }
        return w;
    };
    // Corner b (between a and c) is an ear when its triangle turns as the face does and lies
    // where what is left of the face winds exactly once: no edge enters the triangle (so the
    // winding is the same all over it), and it winds once around the triangle's centroid.
    // Cutting it off takes the triangle's area from the face and leaves the rest winding as
    // before. A face whose edges meet but never cross always has one, whatever its shape:
    // holes joined by bridges, corners where the face touches itself, straight corners and
    // spikes of no width. (Looking for corners inside the triangle is not enough there: an
    // edge can enter it from a place at one of its corners, as a hole's bridge does, and
    // leave it across a side.)
    const auto is_ear = [&](std::size_t a, std::size_t b, std::size_t c) {
        if (!(cross(a, b, c) > 0.0)) return false;
        const std::size_t m = left.size();
        for (std::size_t j = 0; j < m; ++j)
            if (enters(a, b, c, left[j], left[(j + 1) % m])) return false;
        return winding((q[a] + q[b] + q[c]) / 3.0) == 1;
    };
    // Where no corner is an ear, edges of the face cross: by design, or by the rounding of its
    // corners to floats (a corner meant to lie on the middle of an edge, written in decimals,
    // lies a little to one side of it). Such a face may not be covered exactly once. Then the
    // first corner that turns as the face does, with no other corner in its triangle (but
    // those at the place of one of its own) and a new edge that crosses none of the face's, is
    // cut; where none is, the first corner. (On a second review's faces with decimal corners,
    // 8000 of them, this took the wrongly covered ones from 29 to none.)
    const auto looks_like_ear = [&](std::size_t a, std::size_t b, std::size_t c) {
        if (!(cross(a, b, c) > 0.0)) return false;
        for (const std::size_t d : left)
            if (!(d == a || d == b || d == c || q[d] == q[a] || q[d] == q[b] || q[d] == q[c]) && cross(a, b, d) >= 0.0 &&
                cross(b, c, d) >= 0.0 && cross(c, a, d) >= 0.0)
                return false;
        const std::size_t m = left.size();
        for (std::size_t j = 0; j < m; ++j) {
            const std::size_t d = left[j], e = left[(j + 1) % m];
            if (d == a || d == c || e == a || e == c) continue;
            const double s1 = cross(a, c, d), s2 = cross(a, c, e), s3 = cross(d, e, a), s4 = cross(d, e, c);
            if (((s1 > 0.0 && s2 < 0.0) || (s1 < 0.0 && s2 > 0.0)) && ((s3 > 0.0 && s4 < 0.0) || (s3 < 0.0 && s4 > 0.0))) return false;
        }
        return true;
    };
    while (left.size() > 3) {
        const std::size_t m = left.size();
        // First a corner with no area (a straight one, or the tip of a spike of no width):
        // its triangle covers nothing, and the face winds as before without it.
        std::size_t cut = m;
        for (std::size_t k = 0; k < m && cut == m; ++k)
            if (cross(left[(k + m - 1) % m], left[k], left[(k + 1) % m]) == 0.0) cut = k;
        for (std::size_t k = 0; k < m && cut == m; ++k)
            if (is_ear(left[(k + m - 1) % m], left[k], left[(k + 1) % m])) cut = k;
        for (std::size_t k = 0; k < m && cut == m; ++k)
            if (looks_like_ear(left[(k + m - 1) % m], left[k], left[(k + 1) % m])) cut = k;
        if (cut == m) cut = 0;
        out.push_back({left[(cut + m - 1) % m], left[cut], left[(cut + 1) % m]});
        left.erase(left.begin() + std::ptrdiff_t(cut));
    }
    out.push_back({left[0], left[1], left[2]});
}

// The mesh vertex of a face corner: its position, colour (sRGB in the file, as a scene file's
// colours), normal (0 where the corner has none) and texture coordinates (0 where none; from
// texr's own reading, `uvs`, which has tinyobjloader's count: same_numbers).
Vertex obj_vertex(const tinyobj::attrib_t& attrib, const std::vector<double>& uvs, const tinyobj::index_t& idx, bool colors) {
    Vertex v;
    const std::size_t p = 3 * std::size_t(idx.vertex_index);
    v.position = {attrib.vertices[p], attrib.vertices[p + 1], attrib.vertices[p + 2]};
    if (colors) v.color = {srgb_to_linear(attrib.colors[p]), srgb_to_linear(attrib.colors[p + 1]), srgb_to_linear(attrib.colors[p + 2])};
    if (idx.normal_index >= 0) {
        const std::size_t n = 3 * std::size_t(idx.normal_index);
        v.normal = {attrib.normals[n], attrib.normals[n + 1], attrib.normals[n + 2]};
    }
    if (idx.texcoord_index >= 0) {
        const std::size_t t = 2 * std::size_t(idx.texcoord_index);
        v.uv = {uvs[t], uvs[t + 1]};
    }
    return v;
}

// The normals an OBJ file does not give, worked out from the faces around each position in a
// smoothing group: each face's vector area (Newell's method, twice the area along the face's
// normal) added once at each of its positions, and the sum made unit length (the
// area-weighted mean of the faces' normals). The first group a face is in (every face of a
// file without `s` lines, or of a file under one `s` line) is summed by position in a
// vector; the other groups by position and group in a hash map.
class GroupNormals {
public:
    explicit GroupNormals(std::size_t positions) : around_(positions, glm::dvec3(0.0)), last_face_at_(positions, std::size_t(-1)) {}

    // Face number `face` of smoothing group `group` (not 0: flat faces take their own normal),
    // at these positions (a position it passes twice counted once).
    template <typename Positions>
    void add_face(std::size_t face, std::uint32_t group, const glm::dvec3& area, std::size_t corner_count, Positions position_of_corner) {
        if (first_group_ == 0) first_group_ = group;
        for (std::size_t k = 0; k < corner_count; ++k) {
            const std::size_t position = position_of_corner(k);
            if (group == first_group_) {
                if (last_face_at_[position] != face) around_[position] += area, last_face_at_[position] = face;
            } else {
                GroupSum& at = around_group_[key(position, group)];
                if (at.last_face != face) at.sum += area, at.last_face = face;
            }
        }
    }

    // The normal at a position of a group one of add_face's faces was in.
    glm::vec3 at(std::size_t position, std::uint32_t group) const {
        return unit_or_z(group == first_group_ ? around_[position] : around_group_.at(key(position, group)).sum);
    }

    // A sum of vector areas as a unit normal; +z where it is 0 (faces of no area).
    static glm::vec3 unit_or_z(const glm::dvec3& sum) {
        const double length = glm::length(sum);
        return length > 0.0 ? glm::vec3(sum / length) : glm::vec3(0.0f, 0.0f, 1.0f);
    }

private:
    struct GroupSum {
        glm::dvec3 sum{0.0};
        std::size_t last_face = std::size_t(-1);
    };
    static std::uint64_t key(std::size_t position, std::uint32_t group) { return std::uint64_t(position) << 32 | group; }

    std::uint32_t first_group_ = 0;  // (0: no face yet)
    std::vector<glm::dvec3> around_;
    std::vector<std::size_t> last_face_at_;  // (each position once a face)
    std::unordered_map<std::uint64_t, GroupSum> around_group_;
};

}  // namespace

Mesh load_obj(const std::string& path, const ObjMaterialResolver& resolve) {
    require_file(path, "an OBJ file");
    if (!std::ifstream(path)) throw InputError(path, 0, "cannot open OBJ file");
    const ObjLines lines = read_obj_lines(path);  // (also refuses bad lines, naming them)
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> obj_materials;
    MtlReader mtl_files(folder_of(path));  // mtllib files, next to the OBJ
    {
        std::ifstream file(path);
        std::istringstream cleaned(lines.clean ? text_without_comments(path) : std::string());
        std::string warning, error;
        if (!tinyobj::LoadObj(&attrib, &shapes, &obj_materials, &warning, &error, lines.clean ? static_cast<std::istream*>(&cleaned) : &file,
                              &mtl_files, /*triangulate=*/false, /*default_vcols_fallback=*/false))
            throw InputError(path, 0, "not a readable OBJ file: " + first_line(error));
    }

    // Each triangle's material, by name: the name its face's `usemtl` gave, whether or not
    // a .mtl file describes it (tinyobjloader forgets names it found no .mtl entry for).
    std::map<std::string, const tinyobj::material_t*> described;
    for (const tinyobj::material_t& m : obj_materials) described[m.name] = &m;
    std::map<std::string, int> material_of;  // name -> scene material index, resolved on first use
    auto scene_material = [&](const std::string& name) {
        auto it = material_of.find(name);
        if (it != material_of.end()) return it->second;
        ObjMaterialInfo info;
        info.name = name;
        auto found = described.find(name);
        if (!name.empty() && found != described.end()) {
            const tinyobj::material_t& m = *found->second;
            info.described = true;
            info.mtl_file = mtl_files.source(std::size_t(&m - obj_materials.data()));
            if (info.mtl_file.empty()) info.mtl_file = path;  // (not reached)
            info.diffuse = {float(m.diffuse[0]), float(m.diffuse[1]), float(m.diffuse[2])};
            if (!m.diffuse_texname.empty())  // relative to the .mtl file's folder unless absolute
                info.diffuse_texture = m.diffuse_texname[0] == '/' ? m.diffuse_texname : folder_of(info.mtl_file) + m.diffuse_texname;
        }
        const int index = resolve(info);
        material_of.emplace(name, index);
        return index;
    };

    std::vector<int> usemtl_material(lines.names.size(), -1);  // by name index, resolved on first use
    // Each face of k corners is k - 2 triangles (face_triangles), as read_obj_lines counted
    // them for their usemtl names. The faces are read_obj_lines' (its corner counts: those
    // tinyobjloader keeps wrap at 256), which tinyobjloader must have read too, corner for corner.
    std::size_t face_count = 0, corner_total = 0;
    for (const tinyobj::shape_t& shape : shapes) face_count += shape.mesh.num_face_vertices.size(), corner_total += shape.mesh.indices.size();
    std::size_t corners_read = 0;
    for (const std::size_t k : lines.face_corners) corners_read += k;
    if (face_count != lines.face_corners.size() || corner_total != corners_read)
        throw InputError(path, 0, "tinyobjloader read " + std::to_string(face_count) + " faces of " + std::to_string(corner_total) +
                                      " corners, not the " + std::to_string(lines.face_corners.size()) + " of " +
                                      std::to_string(corners_read) + " the file's face lines give");

    same_numbers(path, attrib.vertices, lines.v_numbers, lines.v_lines, 3, "v");
    same_numbers(path, attrib.colors, lines.colors ? lines.v_rgb : std::vector<float>(), lines.v_lines, 3, "v");
    same_numbers(path, attrib.normals, lines.vn_numbers, lines.vn_lines, 3, "vn");
    same_numbers(path, attrib.texcoords, std::vector<float>(lines.vt_numbers.begin(), lines.vt_numbers.end()), lines.vt_lines, 2, "vt");
    Mesh mesh;
    mesh.source = path;
    mesh.has_uv = true;  // (until a face without vt)
    mesh.has_colors = lines.colors;
    // One mesh vertex per distinct (position, normal, uv) index triple and smoothing group,
    // numbered in order of first use: a corner with a normal of its own is one vertex whatever
    // its group (group part 0), a corner whose normal is computed one of its group's, and each
    // corner of a flat face without a normal its own (`flat_vertex`, not in vertex_of).
    using CornerKey = std::tuple<int, int, int, std::uint32_t>;
    struct CornerHash {
        std::size_t operator()(const CornerKey& k) const {
            std::uint64_t h = std::uint32_t(std::get<0>(k));
            h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(std::get<1>(k));
            h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(std::get<2>(k));
            h = h * 0x9E3779B97F4A7C15ull ^ std::get<3>(k);
            return std::size_t(h ^ (h >> 29));
        }
    };
    std::unordered_map<CornerKey, std::uint32_t, CornerHash> vertex_of;
    vertex_of.reserve(attrib.vertices.size() / 3);
    std::vector<std::uint32_t> flat_vertex;  // by corner of a flat face: its vertex (none: no_vertex)
    glm::vec3 flat_normal(0.0f);             // a flat face's normal (flat_face_normal)
    constexpr std::uint32_t no_vertex = ~std::uint32_t(0);
    std::vector<int> position_of;  // by mesh vertex: its v index
    // By mesh vertex: the smoothing group whose faces around its position give its normal, or
    // 0 where its normal is set (a vn of non-zero length, or a flat face's own).
    std::vector<std::uint32_t> normal_from;
    const int position_count = int(attrib.vertices.size() / 3);
    const int normal_count = int(attrib.normals.size() / 3);
    const int uv_count = int(attrib.texcoords.size() / 2);
    std::vector<glm::vec3> corners;
    std::vector<std::array<std::size_t, 3>> face_split;
    GroupNormals group_normals(static_cast<std::size_t>(position_count));
    std::size_t face_number = 0;
    for (const tinyobj::shape_t& shape : shapes) {
        const auto& indices = shape.mesh.indices;
        std::size_t face_start = 0;  // the face's first corner in indices
        for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f, ++face_number) {
            const std::size_t corner_count = lines.face_corners[face_number];
            if (corner_count % 256 != shape.mesh.num_face_vertices[f] || face_start + corner_count > indices.size())
                throw InputError(path, 0, "tinyobjloader read face " + std::to_string(face_number + 1) + " with other corners than its line gives");
            corners.clear();
            for (std::size_t k = 0; k < corner_count; ++k) {
                const tinyobj::index_t& idx = indices[face_start + k];
                const int vertex = idx.vertex_index;
                if (vertex < 0 || vertex >= position_count) throw InputError(path, 0, "face refers to a vertex that does not exist");
                if (idx.normal_index >= normal_count) throw InputError(path, 0, "face refers to a normal (vn) that does not exist");
                if (idx.texcoord_index >= uv_count)
                    throw InputError(path, 0, "face refers to a texture coordinate (vt) that does not exist");
                const std::size_t at = 3 * std::size_t(vertex);
                corners.emplace_back(attrib.vertices[at], attrib.vertices[at + 1], attrib.vertices[at + 2]);
            }
            const glm::dvec3 area = newell_area(corners);
            const std::uint32_t group = lines.face_group[face_number];
            if (group > 0)
                group_normals.add_face(face_number, group, area, corner_count,
                                       [&](std::size_t k) { return std::size_t(indices[face_start + k].vertex_index); });
            else
                flat_vertex.assign(corner_count, no_vertex), flat_normal = flat_face_normal(corners, area);
            face_triangles(corners, area, face_split);
            for (const std::array<std::size_t, 3>& corner_of : face_split) {
                std::array<std::uint32_t, 3> triangle{};
                bool face_has_uv = true;
                for (int k = 0; k < 3; ++k) {
                    const tinyobj::index_t& idx = indices[face_start + corner_of[std::size_t(k)]];  // (checked above)
                    face_has_uv = face_has_uv && idx.texcoord_index >= 0;
                    const std::size_t n3 = 3 * std::size_t(idx.normal_index);
                    const bool has_normal = idx.normal_index >= 0 && (attrib.normals[n3] != 0.0f || attrib.normals[n3 + 1] != 0.0f ||
                                                                       attrib.normals[n3 + 2] != 0.0f);
                    const CornerKey key(idx.vertex_index, idx.normal_index, idx.texcoord_index, has_normal ? 0 : group);
                    if (!has_normal && group == 0) {  // a flat face's corner: its own vertex
                        std::uint32_t& vertex = flat_vertex[corner_of[std::size_t(k)]];
                        if (vertex == no_vertex) {
                            vertex = std::uint32_t(mesh.vertices.size());
                            mesh.vertices.push_back(obj_vertex(attrib, lines.vt_numbers, idx, lines.colors));
                            mesh.vertices.back().normal = flat_normal;
                            position_of.push_back(idx.vertex_index);
                            normal_from.push_back(0);
                        }
                        triangle[std::size_t(k)] = vertex;
                        continue;
                    }
                    auto found = vertex_of.find(key);
                    if (found == vertex_of.end()) {
                        found = vertex_of.emplace(key, std::uint32_t(mesh.vertices.size())).first;
                        mesh.vertices.push_back(obj_vertex(attrib, lines.vt_numbers, idx, lines.colors));
                        position_of.push_back(idx.vertex_index);
                        normal_from.push_back(has_normal ? 0 : group);
                    }
                    triangle[std::size_t(k)] = found->second;
                }
                mesh.has_uv = mesh.has_uv && face_has_uv;
                mesh.triangle_without_uv.push_back(!face_has_uv);
                mesh.triangles.push_back(triangle);
                const std::uint32_t n = lines.per_triangle[mesh.triangles.size() - 1];
                if (usemtl_material[n] < 0) usemtl_material[n] = scene_material(lines.names[n]);
                mesh.triangle_material.push_back(usemtl_material[n]);
            }
            face_start += corner_count;
        }
    }
    if (mesh.triangles.empty()) throw InputError(path, 0, "OBJ file has no faces");
    if (mesh.has_uv) mesh.triangle_without_uv = {};
    mesh.material_files = lines.material_files;

    // The normals the file does not give (a corner without vn, or a vn of length 0, which has
    // no direction): the area-weighted mean of the normals of the faces of the corner's
    // smoothing group around its position (its v index, whatever the corners' vt and vn: a
    // texture seam is no crease), by the faces' winding; a flat face's own (set above). Given
    // normals are kept.
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
        if (normal_from[i] != 0) mesh.vertices[i].normal = group_normals.at(std::size_t(position_of[i]), normal_from[i]);
    mesh.has_normals = true;  // (given or computed, every vertex has one)
    return mesh;
}

}  // namespace texr
