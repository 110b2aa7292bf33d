// texr::InputError — the one kind of error a user can cause: a bad scene line, a missing
// file, an impossible option. It names the file and line (when there is one) so the
// message alone tells the user what to fix.
#pragma once
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
    static std::string format(const std::string& file, int line, const std::string& message) {
        if (file.empty()) return message;
        if (line <= 0) return file + ": " + message;
        return file + ":" + std::to_string(line) + ": " + message;
    }
    std::string file_;
    int line_;
};

// A token in quotes, as a message shows it: bytes that are not printable ASCII (a no-break
// space pasted from a web page, a tab inside a token, UTF-8, a terminal's escape codes) are
// written as \xNN, so that a token that looks right but is not shows why, and a token of
// more than shown_token_bytes bytes is cut there and ends in "..." (a message stays a line).
constexpr std::size_t shown_token_bytes = 64;
inline std::string shown_token(const std::string& token) {
    std::string out = "'";
    const bool cut = token.size() > shown_token_bytes;
    for (const unsigned char ch : token.substr(0, cut ? shown_token_bytes : token.size())) {
        if (ch >= 0x20 && ch < 0x7f) {
            out += char(ch);
        } else {
            static const char digits[] = "0123456789ABCDEF";
            out += "\\x";
            out += digits[ch >> 4];
            out += digits[ch & 15];
        }
    }
    return out + (cut ? "...'" : "'");
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
