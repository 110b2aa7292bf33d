// Text files' lines as texr's readers take them.
#pragma once
#include <istream>
#include <string>

namespace texr {

// Reads the next line of `in` into `line`, without its end: LF, CRLF or a CR alone (the
// three ends tinyobjloader takes in OBJ and .mtl files; texr's own checks must see the same
// lines, and scene files take them too). False, with `line` empty, when no line is left.
inline bool read_text_line(std::istream& in, std::string& line) {
    line.clear();
    if (!in) return false;
    std::streambuf* const buffer = in.rdbuf();
    for (;;) {
        const int c = buffer->sbumpc();
        if (c == std::char_traits<char>::eof()) {
            in.setstate(std::ios::eofbit);
            return !line.empty();
        }
        if (c == '\n') return true;
        if (c == '\r') {
            if (buffer->sgetc() == '\n') buffer->sbumpc();
            return true;
        }
        line += char(c);
    }
}

}  // namespace texr
