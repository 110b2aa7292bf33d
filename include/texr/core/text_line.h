// Text files' lines as texr's readers take them.
#pragma once
#include <istream>
#include <string>

namespace texr {

// Reads a text's lines one by one, without their ends: LF, CRLF or a CR alone (the three
// ends tinyobjloader takes in OBJ and .mtl files; texr's own checks must see the same lines,
// and scene files take them too). The text is read up to each LF with std::getline (a file
// of LF or CRLF lines, the usual ones, is read as fast as getline reads it), and what that
// gives is split at its CRs.
class TextLineReader {
public:
    explicit TextLineReader(std::istream& in) : in_(in) {}
    // The next line into `line`; false, with `line` untouched, when no line is left.
    bool next(std::string& line) {
        if (at_ == std::string::npos) {
            if (!std::getline(in_, chunk_)) return false;
            at_ = 0;
        }
        const std::size_t cr = chunk_.find('\r', at_);
        if (cr == std::string::npos) {
            line.assign(chunk_, at_, std::string::npos);
            at_ = std::string::npos;
        } else {
            line.assign(chunk_, at_, cr - at_);
            // (a CR that ends the chunk ends this line alone: with the LF after it, CRLF, or
            // with the end of the text)
            at_ = cr + 1 == chunk_.size() ? std::string::npos : cr + 1;
        }
        return true;
    }

private:
    std::istream& in_;
    std::string chunk_;                   // the text up to the next LF
    std::size_t at_ = std::string::npos;  // where its next line starts (npos: read another)
};

}  // namespace texr
