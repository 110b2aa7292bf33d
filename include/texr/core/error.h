// texr::InputError — the one kind of error a user can cause: a bad scene line, a missing
// file, an impossible option. It names the file and line (when there is one) so the
// message alone tells the user what to fix.
#pragma once
#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>

#include <sys/stat.h>

namespace texr {

class InputError : public std::runtime_error {
public:
    InputError(std::string file, int line, const std::string& message)
        : std::runtime_error(format(file, line, message)), file_(std::move(file)), line_(line) {}
    explicit InputError(const std::string& message) : InputError("", 0, message) {}

    const std::string& file() const { return file_; }
    int line() const { return line_; }

private:
    static std::string format(const std::string& file, int line, const std::string& message);
    std::string file_;
    int line_;
};

namespace error_detail {
inline void append_escaped(std::string& out, unsigned char ch) {
    static const char digits[] = "0123456789ABCDEF";
    out += "\\x";
    out += digits[ch >> 4];
    out += digits[ch & 15];
}
// The length of the UTF-8 sequence at text[i] if it is one of a printable character (not
// a C1 control, U+0080..U+009F, which a terminal may take as an escape), else 0.
inline std::size_t printable_utf8_at(const std::string& text, std::size_t i) {
    const unsigned char lead = static_cast<unsigned char>(text[i]);
    const std::size_t length = lead >= 0xC2 && lead <= 0xDF ? 2 : lead >= 0xE0 && lead <= 0xEF ? 3 : lead >= 0xF0 && lead <= 0xF4 ? 4 : 0;
    if (length == 0 || i + length > text.size()) return 0;
    for (std::size_t k = 1; k < length; ++k)
        if ((static_cast<unsigned char>(text[i + k]) & 0xC0) != 0x80) return 0;
    if (lead == 0xC2 && static_cast<unsigned char>(text[i + 1]) < 0xA0) return 0;  // C1 controls
    return length;
}
}  // namespace error_detail

// Text from a file (a name) or a path as a message shows it: control bytes (a terminal's
// escape codes, a tab) and bytes that are not UTF-8 are written as \xNN; UTF-8 characters
// are kept. Beyond max_bytes it is cut (at a character) and ends in "...".
inline std::string shown_text(const std::string& text, std::size_t max_bytes) {
    std::string out;
    std::size_t i = 0;
    while (i < text.size()) {
        const unsigned char ch = static_cast<unsigned char>(text[i]);
        const std::size_t length = ch >= 0x20 && ch < 0x7f ? 1 : error_detail::printable_utf8_at(text, i);
        if (i + std::max<std::size_t>(length, 1) > max_bytes) break;
        if (length == 0) {
            error_detail::append_escaped(out, ch);
            ++i;
        } else {
            out.append(text, i, length);
            i += length;
        }
    }
    return i < text.size() ? out + "..." : out;
}

// How many bytes of a word a message quotes (a message stays a line), and of a path.
constexpr std::size_t shown_token_bytes = 64;
constexpr std::size_t shown_path_bytes = 4096;

// A name from a file (a material's, a texture's) in quotes, as shown_text shows it.
inline std::string shown_name(const std::string& name) { return "'" + shown_text(name, shown_token_bytes) + "'"; }

// A path as a message shows it (shown_text; paths are cut only beyond 4096 bytes, the
// longest the system opens).
inline std::string shown_path(const std::string& path) { return shown_text(path, shown_path_bytes); }

// A token that should be a number or a keyword, in quotes, as a message shows it: every
// byte that is not printable ASCII (a no-break space pasted from a web page, a tab inside a
// token, UTF-8, a terminal's escape codes) is written as \xNN, so that a token that looks
// right but is not shows why; beyond shown_token_bytes it is cut and ends in "...".
inline std::string shown_token(const std::string& token) {
    std::string out = "'";
    const bool cut = token.size() > shown_token_bytes;
    for (const unsigned char ch : token.substr(0, cut ? shown_token_bytes : token.size())) {
        if (ch >= 0x20 && ch < 0x7f) out += char(ch);
        else error_detail::append_escaped(out, ch);
    }
    return out + (cut ? "...'" : "'");
}

inline std::string InputError::format(const std::string& file, int line, const std::string& message) {
    if (file.empty()) return message;
    if (line <= 0) return shown_path(file) + ": " + message;
    return shown_path(file) + ":" + std::to_string(line) + ": " + message;
}

// Refuses a path that names a folder or a device rather than a file (`kind`: "an OBJ file"):
// a folder read as a file is empty, and /dev/zero never ends. (A pipe is read: a scene can
// come from one.) A path that does not exist passes here; opening it says so.
inline void require_file(const std::string& path, const std::string& kind) {
    struct stat info {};
    if (::stat(path.c_str(), &info) != 0) return;
    if (S_ISDIR(info.st_mode)) throw InputError(path, 0, "is a folder, not " + kind);
    if (S_ISCHR(info.st_mode) || S_ISBLK(info.st_mode)) throw InputError(path, 0, "is a device, not " + kind);
}

}  // namespace texr
