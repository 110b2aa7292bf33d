// texr::InputError — the one kind of error a user can cause: a bad scene line, a missing
// file, an impossible option. It names the file and line (when there is one) so the
// message alone tells the user what to fix.
#pragma once
#include <stdexcept>
#include <string>

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

}  // namespace texr
