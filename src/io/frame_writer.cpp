// PNG (png_encode.h) and PPM frame output, written atomically (see the header).
#include "texr/io/frame_writer.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "texr/core/error.h"
#include "texr/core/path.h"
#include "png_encode.h"

namespace texr {

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
    if (s.size() < suffix.size()) return false;
    for (std::size_t i = 0; i < suffix.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) != suffix[i]) return false;
    return true;
}

}  // namespace

FrameFormat frame_format_for(const std::string& path) {
    if (ends_with(path, ".png")) return FrameFormat::png;
    if (ends_with(path, ".ppm")) return FrameFormat::ppm;
    throw InputError(path, 0, "output file must end in .png or .ppm");
}

std::vector<std::uint8_t> encode_srgb8(const Framebuffer& fb) {
    std::vector<std::uint8_t> rgb(std::size_t(fb.width) * std::size_t(fb.height) * 3);
    const std::uint8_t* table = linear_to_srgb8_table();
    for (std::size_t i = 0; i < fb.color.size(); ++i) {
        const Color& c = fb.color[i];
        rgb[3 * i] = linear_to_srgb8(c.x, table);
        rgb[3 * i + 1] = linear_to_srgb8(c.y, table);
        rgb[3 * i + 2] = linear_to_srgb8(c.z, table);
    }
    return rgb;
}

std::vector<std::uint8_t> encode_frame(const Framebuffer& fb, FrameFormat format) {
    const std::vector<std::uint8_t> rgb = encode_srgb8(fb);
    std::vector<std::uint8_t> out;
    if (format == FrameFormat::ppm) {
        const std::string header = "P6\n" + std::to_string(fb.width) + " " + std::to_string(fb.height) + "\n255\n";
        out.assign(header.begin(), header.end());
        out.insert(out.end(), rgb.begin(), rgb.end());
        return out;
    }
    out = png::encode_rgb8(rgb.data(), fb.width, fb.height);
    if (out.empty()) throw InputError("cannot encode the frame as PNG");
    return out;
}

namespace {

// The file a write to `requested` replaces: a symbolic link is followed to its end (to a
// file that may not exist yet), so the link stays a link. Throws when the links loop, or
// when they end at something other than a file or a folder (a device or a pipe would be
// replaced by the rename).
std::string written_path(const std::string& requested) {
    std::string path = requested;
    for (int hops = 0;; ++hops) {
        struct stat link;
        if (::lstat(path.c_str(), &link) != 0 || !S_ISLNK(link.st_mode)) break;
        if (hops == 40) throw InputError(requested, 0, "cannot write output file: its symbolic links go round in a loop");
        std::string target(PATH_MAX, '\0');
        const ssize_t n = ::readlink(path.c_str(), target.data(), target.size());
        if (n <= 0) break;
        target.resize(std::size_t(n));
        path = target[0] == '/' ? target : folder_of(path) + target;  // relative to the link's folder
    }
    struct stat info;
    if (::stat(path.c_str(), &info) == 0 && !S_ISREG(info.st_mode) && !S_ISDIR(info.st_mode))
        throw InputError(requested, 0, "cannot write output file: " + (path == requested ? std::string("it") : "its link's target " + shown_path(path)) +
                                           " is a device or a pipe, not a file");
    return path;
}

}  // namespace

void check_output_path(const std::string& requested) {
    const std::string path = written_path(requested);
    const std::string folder = folder_of(path);
    const std::string shown_folder = folder.empty() ? std::string(".") : folder.substr(0, folder.size() > 1 ? folder.size() - 1 : 1);
    struct stat info;
    if (::stat(path.c_str(), &info) == 0) {
        if (S_ISDIR(info.st_mode)) throw InputError(requested, 0, "cannot write output file: it is a folder");
        if (::access(path.c_str(), W_OK) != 0)
            throw InputError(requested, 0, std::string("cannot write output file: it exists and cannot be replaced (") + std::strerror(errno) + ")");
    }
    if (::stat(folder.empty() ? "." : folder.c_str(), &info) != 0) {
        if (errno == ENOENT || errno == ENOTDIR) throw InputError(requested, 0, "cannot write output file: there is no folder '" + shown_folder + "'");
        throw InputError(requested, 0, "cannot write output file: cannot reach folder '" + shown_folder + "' (" + std::strerror(errno) + ")");
    }
    if (!S_ISDIR(info.st_mode)) throw InputError(requested, 0, "cannot write output file: '" + shown_folder + "' is not a folder");
    // The new file is made beside the old one and renamed over it: the folder must be writable.
    if (::access(folder.empty() ? "." : folder.c_str(), W_OK | X_OK) != 0)
        throw InputError(requested, 0, "cannot write output file: cannot create files in folder '" + shown_folder + "' (" + std::strerror(errno) + ")");
}

void check_not_an_input(const std::string& requested, const std::vector<std::string>& inputs) {
    struct stat output, input;
    if (::stat(written_path(requested).c_str(), &output) != 0) return;  // (nothing there to replace)
    for (const std::string& file : inputs)
        if (::stat(file.c_str(), &input) == 0 && input.st_dev == output.st_dev && input.st_ino == output.st_ino)
            throw InputError(requested, 0, "cannot write output file: the scene reads it (" + file + "); give another -o");
}

namespace {

// The temporary files of the writes under way, for the signal handler to remove: a fixed
// table (a handler may not allocate). A slot's path is written between two steps of its
// sequence number (odd while it changes), and the handler unlinks a copy only if the number
// was even and the same before and after it took the copy, so that it never unlinks a path
// half overwritten by a write in another thread. A write that finds every slot taken goes on
// unlisted; one that starts while the handler runs (another thread) makes no file.
// (Every access is a sequentially consistent atomic, the path's characters too: a path is
// written once a file, and read only by the handler.)
struct PartialOutput {
    std::atomic<bool> in_use{false}, listed{false};
    std::atomic<unsigned> sequence{0};
    std::atomic<char> path[PATH_MAX + 1] = {};
};
PartialOutput partial_outputs[16];
std::atomic<bool> stopping{false};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<unsigned>::is_always_lock_free &&
                  std::atomic<char>::is_always_lock_free,
              "the signal handler reads these");

extern "C" void remove_partial_outputs(int signal_number) {
    stopping.store(true);
    char copy[PATH_MAX + 1];
    for (PartialOutput& p : partial_outputs) {
        if (!p.listed.load()) continue;
        const unsigned before = p.sequence.load();
        if (before % 2 != 0) continue;
        std::size_t i = 0;
        while (i < PATH_MAX && (copy[i] = p.path[i].load()) != '\0') ++i;
        copy[i] = '\0';
        if (p.sequence.load() == before && p.listed.load()) ::unlink(copy);  // (unlink is async-signal-safe)
    }
    std::signal(signal_number, SIG_DFL);  // then end as the signal would have
    std::raise(signal_number);
}

// Lists one path at a time for the handler, from list() to unlist() or the end of its life
// (not a path too long, nor when every slot is taken).
class ListedPartialOutput {
public:
    ListedPartialOutput() = default;
    void list(const std::string& path) {
        unlist();
        if (path.size() > PATH_MAX) return;
        for (PartialOutput& p : partial_outputs) {
            bool free = false;
            if (!p.in_use.compare_exchange_strong(free, true)) continue;
            p.sequence.fetch_add(1);  // odd: changing
            for (std::size_t i = 0; i <= path.size(); ++i) p.path[i].store(path.c_str()[i]);
            p.sequence.fetch_add(1);  // even again
            p.listed.store(true);
            slot_ = &p;
            return;
        }
    }
    void unlist() {
        if (!slot_) return;
        slot_->listed.store(false);
        slot_->in_use.store(false);
        slot_ = nullptr;
    }
    ~ListedPartialOutput() { unlist(); }
    ListedPartialOutput(const ListedPartialOutput&) = delete;
    ListedPartialOutput& operator=(const ListedPartialOutput&) = delete;

private:
    PartialOutput* slot_ = nullptr;
};

}  // namespace

void remove_partial_outputs_on_signals() {
    // The signals whose default action ends the process and that a process can catch:
    // hang-up, Ctrl-C, Ctrl-\, kill's default, a closed pipe, file size and CPU time limits,
    // an alarm, the user signals.
    for (const int signal_number : {SIGHUP, SIGINT, SIGQUIT, SIGTERM, SIGPIPE, SIGXFSZ, SIGXCPU, SIGALRM, SIGUSR1, SIGUSR2}) {
        struct sigaction now{};
        if (::sigaction(signal_number, nullptr, &now) != 0 || now.sa_handler != SIG_DFL) continue;  // (ignored, or someone's)
        struct sigaction action{};
        action.sa_handler = remove_partial_outputs;
        sigemptyset(&action.sa_mask);
        ::sigaction(signal_number, &action, nullptr);
    }
}

namespace {

// Writes all of `bytes` to `fd`: false (errno set) if it could not.
bool write_all(int fd, const std::vector<std::uint8_t>& bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n == 0) errno = EIO;  // (no progress, and no reason given)
        if (n <= 0) return false;
        done += std::size_t(n);
    }
    return true;
}

}  // namespace

void write_file_atomically(const std::string& requested, const std::vector<std::uint8_t>& bytes, TemporaryFile temporary_file) {
    const std::string path = written_path(requested);
    const std::string folder = folder_of(path);
    // The temporary file's name: short and hidden, in the same folder (so that rename replaces
    // the file in one step), whatever the length of the file's own name; numbered, so that
    // writes from several threads of one process never share one. It is listed for the signal
    // handler before the file is made (a signal between would find nothing to remove), and
    // the handler's flag read after (a write that reads it set makes no file).
    static std::atomic<unsigned> writes{0};
    std::string temporary;
    ListedPartialOutput listed;
    const auto cannot_write = [&](int error) {
        if (error == ECANCELED) return InputError(requested, 0, "cannot write output file: texr is being stopped by a signal");
        return InputError(requested, 0, std::string("cannot write output file: ") + std::strerror(error));
    };
    // Makes a file under the next name with `make` (false, with errno, where it cannot). A
    // name taken already (by a file that an earlier texr with the same process number left,
    // stopped by SIGKILL) is passed over for the next, up to 100 times. Returns 0, or the error
    // (ECANCELED: texr is being stopped by a signal).
    const auto make_named = [&](auto make) {
        for (int attempt = 0; attempt < 100; ++attempt) {
            temporary = folder + ".texr-" + std::to_string(::getpid()) + "-" + std::to_string(writes++) + ".tmp";
            listed.list(temporary);
            if (stopping.load()) return ECANCELED;
            if (make()) return 0;
            const int error = errno;
            listed.unlist();  // (not ours to remove)
            if (error != EEXIST) return error;
        }
        return EEXIST;
    };
    // An unnamed file (O_TMPFILE) where the kernel and the file system allow it: until it is
    // linked under the temporary name, just before the rename, nothing stopping the process
    // (SIGKILL, a crash, a power cut) can leave it behind. Elsewhere a named one, which the
    // signal handler removes.
    bool named = temporary_file == TemporaryFile::named;
    int fd = -1;
#if defined(O_TMPFILE)
    if (!named) fd = ::open(folder.empty() ? "." : folder.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
#endif
    if (fd < 0) {
        named = true;
        const int error = make_named([&] { return (fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666)) >= 0; });
        if (error != 0) {
            if (error != ECANCELED) check_output_path(requested);  // names the reason when it can
            throw cannot_write(error);
        }
    }
    // The replaced file's permissions carry over to the new one.
    struct stat old_file;
    if (::stat(path.c_str(), &old_file) == 0) ::fchmod(fd, old_file.st_mode & 07777);
    if (!write_all(fd, bytes)) {
        const int error = errno;
        ::close(fd);
        if (named) std::remove(temporary.c_str());
        throw cannot_write(error);
    }
    if (!named) {
        // The unnamed file gets its name through its entry in /proc.
        const std::string entry = "/proc/self/fd/" + std::to_string(fd);
        const int error =
            make_named([&] { return ::linkat(AT_FDCWD, entry.c_str(), AT_FDCWD, temporary.c_str(), AT_SYMLINK_FOLLOW) == 0; });
        if (error != 0) {
            ::close(fd);
            if (error == ECANCELED) throw cannot_write(error);
            // (no /proc, say: the bytes are written again, to a named file)
            listed.unlist();
            write_file_atomically(requested, bytes, TemporaryFile::named);
            return;
        }
    }
    if (::close(fd) != 0) {
        const int error = errno;
        std::remove(temporary.c_str());
        throw cannot_write(error);
    }
    if (std::rename(temporary.c_str(), path.c_str()) != 0) {
        const int error = errno;
        std::remove(temporary.c_str());
        throw cannot_write(error);
    }
}

void write_frame(const Framebuffer& fb, const std::string& path) {
    write_file_atomically(path, encode_frame(fb, frame_format_for(path)));
}

}  // namespace texr
