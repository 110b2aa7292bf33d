// The scene file: a line-oriented text format (docs/scene-format.md). Each line is a command
// followed by "key values..." options; '#' starts a comment; a trailing '\' continues a
// line. Paths are relative to the scene file. Every error is an InputError naming
// file:line and what was expected.
#pragma once
#include <istream>
#include <string>

#include "texr/scene/scene.h"

namespace texr {

// Reads and parses the scene file at `path`, loading the textures and OBJ files it names.
Scene load_scene(const std::string& path);

// Parses scene text; `path` names it in messages and anchors relative paths.
Scene parse_scene(std::istream& in, const std::string& path);

}  // namespace texr
