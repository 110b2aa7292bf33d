// Writing frames: binary PPM (P6) or PNG, chosen by the file extension, sRGB-encoded.
// Written atomically: the bytes go to a temporary file beside the target, which is renamed
// over it only when complete, so a failure never leaves a half-written frame and never
// destroys the previous one. The temporary file has no name while it is written, where the
// system allows, so that even SIGKILL then leaves nothing (only in the moment between its
// link and rename is it named); a named one is removed by a signal that stops the program,
// where it calls remove_partial_outputs_on_signals.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "texr/render/framebuffer.h"

namespace texr {

enum class FrameFormat { png, ppm };

// The format for `path`'s extension (.png or .ppm); throws InputError otherwise.
FrameFormat frame_format_for(const std::string& path);

// 8-bit sRGB RGB bytes of the frame, row 0 at the top.
std::vector<std::uint8_t> encode_srgb8(const Framebuffer& fb);

// The file's bytes in the given format.
std::vector<std::uint8_t> encode_frame(const Framebuffer& fb, FrameFormat format);

// Whether a file could be written at `path`, checked before any work is done: throws
// InputError naming the path and the reason (its folder is missing or not writable, the
// path is a folder, an existing file there cannot be replaced, or it is a link to a device
// or a pipe, or links in a loop).
void check_output_path(const std::string& path);
// Throws InputError if the frame at `requested` would replace one of `inputs` (the same file,
// by device and inode: through another name or a symbolic link too): a scene's own texture,
// say. Files that do not exist yet cannot be replaced.
void check_not_an_input(const std::string& requested, const std::vector<std::string>& inputs);

// How write_file_atomically makes its temporary file: `unnamed` (the default) where the
// kernel and the file system allow it (O_TMPFILE: Linux 3.11 and later, on most local file
// systems), named only just before the rename, else `named` from the start; `named` always
// (for the tests of the signal handler, which removes named files).
enum class TemporaryFile { unnamed, named };

// Writes `bytes` to `path` through a temporary file in its folder and a rename. An existing
// file keeps its permission bits, and a symbolic link is written through (its target is
// replaced, the link stays). Throws InputError naming the path when it cannot be written.
void write_file_atomically(const std::string& path, const std::vector<std::uint8_t>& bytes,
                           TemporaryFile temporary_file = TemporaryFile::unnamed);

void write_frame(const Framebuffer& fb, const std::string& path);

// For a program (texr's main): on a signal that would end the process and can be caught
// (SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGXFSZ, ...), the temporary files of the writes
// under way that have a name are removed before the signal ends the process as it would have,
// so that a render stopped while writing (Ctrl-C) leaves no partial file. Only where the
// signal's action is still the default; the library alone installs nothing. (SIGKILL cannot
// be caught: it leaves a named temporary file behind; an unnamed one only if it comes in the
// moment between the file's link and its rename.)
void remove_partial_outputs_on_signals();

}  // namespace texr
