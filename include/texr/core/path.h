// Paths as texr's readers and writers take them apart.
#pragma once
#include <string>

namespace texr {

// The folder part of a path, with its slash ("" for a bare name: the current folder).
inline std::string folder_of(const std::string& path) {
    const auto slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

}  // namespace texr
