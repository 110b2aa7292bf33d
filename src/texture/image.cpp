// Image loading with stb_image; rows are flipped so that row 0 is the bottom (v = 0).
#include "texr/texture/image.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <memory>
#include <tuple>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "stb_decode.h"
#include "texr/core/error.h"

namespace texr {

Image Image::ldr(int width, int height, ColorSpace space, LargeVector<std::uint8_t> rgba) {
    Image image;
    image.width_ = width;
    image.height_ = height;
    image.space_ = space;
    image.texels_8_ = std::move(rgba);
    image.inv_width_ = 1.0 / width, image.inv_height_ = 1.0 / height;
    image.decode_ = space == ColorSpace::srgb ? srgb8_to_linear_table() : unorm8_to_float_table();
    image.ldr_pow2_ = width > 0 && height > 0 && (width & (width - 1)) == 0 && (height & (height - 1)) == 0;
    while ((std::size_t(1) << (image.row_shift_ + 1)) <= std::size_t(width) * 4) ++image.row_shift_;
    if (image.may_be_decoded()) image.decoded_ = std::make_shared<Decoded>();
    return image;
}

Image Image::hdr(int width, int height, LargeVector<float> rgba) {
    Image image;
    image.width_ = width;
    image.height_ = height;
    image.space_ = ColorSpace::linear;  // Radiance files hold linear radiance
    image.texels_f_ = std::move(rgba);
    image.hdr_ = true;
    image.inv_width_ = 1.0 / width, image.inv_height_ = 1.0 / height;
    return image;
}

namespace {

std::atomic<std::size_t> decoded_bytes_in_use{0};  // the budget's use, by every image's copy

// Takes `bytes` from the budget if they fit (never more than it holds, even when images
// ask at the same time).
bool reserve_decoded_bytes(std::size_t bytes) {
    std::size_t in_use = decoded_bytes_in_use.load();
    do {
        if (bytes > Image::decoded_budget_bytes || in_use > Image::decoded_budget_bytes - bytes) return false;
    } while (!decoded_bytes_in_use.compare_exchange_weak(in_use, in_use + bytes));
    return true;
}

}  // namespace

Image::Decoded::~Decoded() { decoded_bytes_in_use.fetch_sub(reserved); }

const float* Image::decoded_texels() const {
    if (!decoded_) return nullptr;  // (made by Image::ldr for the images that may_be_decoded)
    Decoded& d = *decoded_;
    if (d.decided.load(std::memory_order_acquire)) return d.texels;
    std::call_once(d.once, [&] {
        // The budget counts what the buffer takes: mapped buffers are whole 2 MiB pages.
        const std::size_t bytes = large_buffer_footprint(texels_8_.size() * sizeof(float));
        if (reserve_decoded_bytes(bytes)) {
            d.reserved = bytes;
            try {
                LargeVector<float> out(texels_8_.size());
                for (std::size_t k = 0; k < texels_8_.size(); k += 4) {  // as decode_ldr_texel
                    out[k] = decode_[texels_8_[k]], out[k + 1] = decode_[texels_8_[k + 1]];
                    out[k + 2] = decode_[texels_8_[k + 2]], out[k + 3] = texels_8_[k + 3] * (1.0f / 255.0f);
                }
                d.storage = std::move(out);
                d.texels = d.storage.data();
            } catch (const std::bad_alloc&) {  // the copy is only for speed: read the bytes
                decoded_bytes_in_use.fetch_sub(bytes);
                d.reserved = 0;
            }
        }
        d.decided.store(true, std::memory_order_release);
    });
    return d.texels;
}

std::size_t Image::decoded_bytes() const {
    return decoded_ && decoded_->decided.load(std::memory_order_acquire) && decoded_->texels
               ? decoded_->storage.size() * sizeof(float)
               : 0;
}

const float* unorm8_to_float_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[std::size_t(i)] = float(i) / 255.0f;
        return t;
    }();
    return table.data();
}

namespace {

template <typename T>
LargeVector<T> flipped_rows(const T* top_down, int width, int height) {
    const std::size_t row = std::size_t(width) * 4;
    LargeVector<T> out(row * std::size_t(height));
    for (int j = 0; j < height; ++j)  // file row j (from the top) becomes row height-1-j
        std::memcpy(&out[row * std::size_t(height - 1 - j)], top_down + row * std::size_t(j),
                    row * sizeof(T));
    return out;
}

}  // namespace

namespace {

// stb_image's reason for a failure, in words a user can act on (its own are terse codes,
// and for a file cut short inside a PNG chunk, bytes past its end).
std::string unreadable(const char* reason) {
    std::string r = reason ? reason : "";
    for (const char ch : r)
        if (!std::isprint(static_cast<unsigned char>(ch))) r.clear();
    std::string why;
    if (r == "unknown image type") why = "not a format stb_image reads (PNG, JPEG, TGA, BMP, GIF, PSD, PIC, PPM/PGM or Radiance HDR)";
    else if (r == "outofmem") why = "out of memory";
    else if (r == "too large") why = "the image is too large to read";
    else why = "the file is cut short or damaged" + (r.empty() ? std::string() : " (stb_image: " + r + ")");
    return "not a readable image: " + why;
}

// stb_image misreads some binary PPM/PGM (P6/P5) files without a word: one that ends early
// (the rest filled with whatever it has; the header says how long the file must be), one
// whose header ends before its largest value (its texels are then never read: the image
// holds whatever memory held), a 16-bit one (read as 8-bit samples), a size of 0. Returns the
// message for such a file, or "". `largest`: the header's largest value (255 for other files),
// which stb_image does not read: decode scales samples by it.
std::string short_pnm(const std::vector<unsigned char>& file, int& largest) {
    largest = 255;
    if (file.size() < 2 || file[0] != 'P' || (file[1] != '5' && file[1] != '6')) return "";
    std::size_t at = 2;
    const auto get = [&]() -> int { return at < file.size() ? file[at++] : EOF; };
    long long values[3] = {0, 0, 0};  // width, height, largest value
    const char* const names[3] = {"width", "height", "largest value"};
    // As stb_image reads it: the character that ends a number starts what comes before the
    // next (a '#' right after the width begins a comment), and the one after the largest
    // value ends the header.
    int ch = get();
    for (int k = 0; k < 3; ++k) {
        while (ch == '#' || std::isspace(ch)) {  // whitespace and comments before a number
            if (ch == '#')
                while (ch != '\n' && ch != '\r' && ch != EOF) ch = get();
            ch = get();
        }
        if (!std::isdigit(ch))
            return std::string("not a readable image: its PPM/PGM header is cut short or damaged (no ") + names[k] + ")";
        for (; std::isdigit(ch) && values[k] < (1LL << 40); ch = get()) values[k] = values[k] * 10 + (ch - '0');
    }
    // (stb_image would read 16-bit samples as 8-bit ones, and a side of 0 as an empty image)
    if (values[2] > 255) return "not a readable image: a 16-bit PPM/PGM (largest value " + std::to_string(values[2]) + "); texr reads 8-bit ones";
    if (values[2] == 0) return "not a readable image: its PPM/PGM header gives a largest value of 0";
    largest = int(values[2]);
    if (values[0] == 0 || values[1] == 0 || values[0] > (1 << 24) || values[1] > (1 << 24))
        return "not a readable image: its header gives a size of " + std::to_string(values[0]) + "x" + std::to_string(values[1]);
    const long long needed = values[0] * values[1] * (file[1] == '6' ? 3 : 1);
    const long long have = (long long)(file.size() - std::min(at, file.size()));  // after the one whitespace character that ends the header
    if (have >= needed) return "";
    return "not a readable image: the file is cut short (its header asks for " + std::to_string(needed) + " bytes of texels, it holds " +
           std::to_string(have) + ")";
}

// stb_image (2.27) loops for ever on a Radiance file whose run-length rows hold a count of 0,
// as the end of the file reads there: a file cut short inside its rows hangs it. The rows are
// walked here first, as it reads them (header lines of at most 1023 characters; rows of 8 to
// 32767 texels run-length coded per channel, until a row that is not). Returns the message
// for such a file, or "" (stb_image then reads it, or says what else is wrong).
std::string hdr_runs_cut(const std::vector<unsigned char>& file) {
    std::size_t at = 0;
    const auto at_end = [&] { return at >= file.size(); };
    const auto get = [&]() -> int { return at < file.size() ? file[at++] : 0; };  // 0 past the end, as stb_image
    const auto line = [&] {
        std::string text;
        char ch = char(get());
        while (!at_end() && ch != '\n') {
            text += ch;
            if (text.size() == 1023) {  // the rest of a long line is skipped
                while (!at_end() && get() != '\n') {}
                break;
            }
            ch = char(get());
        }
        return text;
    };
    const std::string magic = line();
    if (magic != "#?RADIANCE" && magic != "#?RGBE") return "";
    while (!line().empty()) {}  // header lines, to the empty one
    const std::string size = line();  // "-Y height +X width"
    if (size.compare(0, 3, "-Y ") != 0) return "";
    char* rest = nullptr;
    const int height = int(std::strtol(size.c_str() + 3, &rest, 10));  // an int, as stb_image reads them
    while (*rest == ' ') ++rest;
    if (std::strncmp(rest, "+X ", 3) != 0) return "";
    const int width = int(std::strtol(rest + 3, nullptr, 10));
    if (width <= 0 || height <= 0 || width > (1 << 24) || height > (1 << 24)) return "";  // refused by stb_image
    // Texels read flat, 4 bytes each, from byte `from` to the end of the image: a file that ends
    // before them left stb_image's texel unset (valgrind: uninitialised), so it is refused.
    const auto flat_cut = [&](std::size_t from, std::uint64_t texels) -> std::string {
        const std::uint64_t needed = 4 * texels, held = file.size() > from ? file.size() - from : 0;
        if (held >= needed) return "";
        return "not a readable image: the file is cut short (its texels need " + std::to_string(needed) + " more bytes, it holds " +
               std::to_string(held) + ")";
    };
    if (width < 8 || width >= 32768) return flat_cut(at, std::uint64_t(width) * std::uint64_t(height));  // no run-length rows
    for (int row = 0; row < height; ++row) {
        const std::size_t row_start = at;
        const int c1 = get(), c2 = get(), high = get();
        if (c1 != 2 || c2 != 2 || (high & 0x80) != 0)  // flat from here on (the end of the file reads so too)
            return flat_cut(row_start, std::uint64_t(width) * std::uint64_t(height - row));
        if (((high << 8) | get()) != width) return "";                // refused by stb_image
        for (int channel = 0; channel < 4; ++channel)
            for (long i = 0; i < width;) {
                int count = get();
                if (count == 0)
                    return "not a readable image: its run-length data is cut short or damaged (row " + std::to_string(row + 1) +
                           " of " + std::to_string(height) + ")";
                const bool run = count > 128;
                if (run) count -= 128;
                if (count > width - i) return "";  // refused by stb_image
                at = std::min(file.size(), at + (run ? 1 : std::size_t(count)));
                i += count;
            }
    }
    return "";
}

// stb_image reads an uncompressed BMP that ends early as if zeros followed (a 64-byte file
// whose header says 16000 x 16000 became a black texture of 1 GB). Returns the message for
// such a file (shorter than its header's offset to the texels plus its rows, the last row's
// padding allowed to be missing), or "".
std::string short_bmp(const std::vector<unsigned char>& file) {
    if (file.size() < 26 || file[0] != 'B' || file[1] != 'M') return "";
    const auto u16 = [&](std::size_t at) { return std::uint32_t(file[at]) | std::uint32_t(file[at + 1]) << 8; };
    const auto u32 = [&](std::size_t at) { return u16(at) | u16(at + 2) << 16; };
    const std::uint64_t offset = u32(10), header = u32(14);
    std::int64_t width = 0, height = 0;
    std::uint32_t bits = 0, compression = 0;
    if (header == 12) {  // the OS/2 core header
        width = u16(18), height = u16(20), bits = u16(24);
    } else if (header >= 40 && file.size() >= 34) {
        width = std::int32_t(u32(18)), height = std::int32_t(u32(22)), bits = u16(28), compression = u32(30);
    } else {
        return "";  // stb_image will say what is wrong
    }
    if (header != 12 && header != 40 && header != 56 && header != 108 && header != 124) return "";  // refused by stb_image
    if (compression != 0 && compression != 3) return "";  // (stb_image reads no compressed BMP)
    // (stb_image refuses sides beyond 2^24, which also keeps the sizes below from overflowing)
    if (width <= 0 || height == 0 || width > (1 << 24) || height > (1 << 24) || height < -(1 << 24) || bits == 0 || bits > 32 ||
        offset < 14 + header)
        return "";
    const std::uint64_t row = (std::uint64_t(bits) * std::uint64_t(width) + 31) / 32 * 4;
    const std::uint64_t last_row = (std::uint64_t(bits) * std::uint64_t(width) + 7) / 8;  // without its padding
    const std::uint64_t rows = std::uint64_t(height < 0 ? -height : height);
    const std::uint64_t needed = offset + row * rows - (row - last_row);
    if (file.size() < needed)
        return "not a readable image: the file is cut short (its header asks for " + std::to_string(needed) + " bytes, it holds " +
               std::to_string(file.size()) + ")";
    // A palette image: stb_image keeps the palette in a stack array, and an index beyond the
    // entries it read picks whatever that memory held. (Its count for the OS/2 header is 4
    // entries short of the file's.)
    if (bits > 8 || compression != 0) return "";
    const std::int64_t entries = header == 12 ? (std::int64_t(offset) - 14 - 24) / 3 : (std::int64_t(offset) - 14 - std::int64_t(header)) >> 2;
    if (entries <= 0 && header == 12)
        return "not a readable image: stb_image reads no entry of this OS/2 BMP's palette (it counts 4 fewer than the file holds)";
    if (entries <= 0 || entries > 256 || (bits != 1 && bits != 4 && bits != 8)) return "";  // refused by stb_image
    if (entries >= (std::int64_t(1) << bits)) return "";
    for (std::uint64_t r = 0; r < rows; ++r) {
        const unsigned char* texels = file.data() + offset + r * row;
        for (std::int64_t x = 0; x < width; ++x) {
            const int index = bits == 8 ? texels[x] : bits == 4 ? (texels[x / 2] >> (x % 2 == 0 ? 4 : 0)) & 15 : (texels[x / 8] >> (7 - x % 8)) & 1;
            if (index >= entries)
                return "not a readable image: palette index " + std::to_string(index) + " is beyond the " + std::to_string(entries) +
                       " palette entries stb_image reads" + (header == 12 ? " (of an OS/2 BMP it reads 4 fewer than the file holds)" : "");
        }
    }
    return "";
}

// What texr checks in a JPEG before stb_image reads it, walking its markers as stb_image
// does (from one segment to the next; from a scan's image data to the first marker after it;
// before the frame header, over bytes that are no marker):
// - A Huffman table (DHT) of more than 256 codes: stb_image 2.27 writes that many entries
//   into its arrays of 256 (a memory error found by fuzzing texr's image loading).
// - A scan that decodes with a Huffman table no DHT before it defines (as a motion-JPEG frame
//   relying on the standard's example tables would): stb_image reads the table from memory it
//   never set, and may index its arrays of 256 with the result (index 665, found by fuzzing).
//   A sequential scan reads the DC and AC tables of each of its components; a progressive
//   scan its components' DC tables when it codes first DC values (Ss = 0, Ah = 0), its one
//   component's AC table when it codes AC values (Ss > 0), and none when it refines DC values.
// - A quantization table (DQT) used before one defines it: stb_image multiplies by values it
//   never set (a signed overflow, and texels that change with memory, found by fuzzing: the
//   file's one DQT lay inside an APP0 segment). A sequential scan dequantizes its components'
//   blocks as it decodes them; a progressive JPEG dequantizes every component at its end.
// - A sequential JPEG shorter than its frame header's size asks for: stb_image reads image
//   data that ends early as if zeros followed (a 613-byte file whose header says 16000 x
//   16000 took 12 s and 2 GB to become a grey texture). In a sequential Huffman-coded JPEG
//   (SOF0, SOF1) every 8 x 8 block of every component is coded once, as a DC code and at
//   least one AC code (the end of block), each at least 1 bit long: at least 2 bits per
//   block. (A progressive JPEG can code a run of up to 32767 empty blocks in a few bits: no
//   such bound, and it is not checked.)
// Returns the message for such a file, or "".
std::string jpeg_damage(const std::vector<unsigned char>& file) {
    // Its start of image: FF D8, after any number of FF fill bytes (stb_image reads a marker so).
    std::size_t at = 0;
    while (at < file.size() && file[at] == 0xff) ++at;
    if (at < 1 || at >= file.size() || file[at] != 0xd8) return "";
    ++at;
    // stb_image reads bytes past the end of the file as 0: so does this check.
    const auto byte = [&](std::size_t i) { return i < file.size() ? std::size_t(file[i]) : std::size_t(0); };
    bool defined[2][4] = {};  // Huffman tables defined so far: [DC, AC][index]
    bool quantizer[4] = {};   // quantization tables defined so far
    int frame = 0;            // the frame header's marker once read: 0xc0, 0xc1 (sequential) or 0xc2 (progressive)
    std::vector<int> frame_ids, frame_quantizers;  // its components' identifiers and quantization tables
    const auto undefined_quantizer = [&](std::size_t index, const char* who) {
        return "not a readable image: " + std::string(who) + " dequantizes with quantization table " + std::to_string(index) +
               ", which no table (DQT) before it defines";
    };
    while (at + 2 <= file.size()) {
        if (file[at] != 0xff) {  // no marker here: move on to the next
            ++at;
            continue;
        }
        const unsigned char marker = file[at + 1];
        if (marker == 0xff) {  // fill byte before a marker
            ++at;
            continue;
        }
        if (marker == 0xd9) {  // end of image: a progressive JPEG's coefficients are dequantized now
            for (const int q : frame_quantizers)
                if (frame == 0xc2 && q <= 3 && !quantizer[q]) return undefined_quantizer(std::size_t(q), "the progressive JPEG");
            return "";
        }
        if (marker == 0x00 || marker == 0x01 || (marker >= 0xd0 && marker <= 0xd8)) {  // markers without a segment
            at += 2;
            continue;
        }
        if (at + 4 > file.size()) return "";
        const std::size_t length = std::size_t(file[at + 2]) << 8 | file[at + 3];  // counts its own two bytes
        if (marker == 0xc4) {  // DHT: tables of a class/index byte, 16 code counts, the codes' symbols
            // stb_image reads tables while the segment's stated length lasts.
            for (std::size_t t = at + 4; t < at + 2 + length;) {
                std::size_t codes = 0;
                for (std::size_t i = 1; i <= 16; ++i) codes += byte(t + i);
                if (codes > 256)
                    return "not a readable image: a Huffman table (DHT) of the JPEG defines " + std::to_string(codes) +
                           " codes, more than the 256 there can be";
                if (const std::size_t kind = byte(t) >> 4, index = byte(t) & 15; kind <= 1 && index <= 3) defined[kind][index] = true;
                t += 17 + codes;
            }
        }
        if (marker == 0xdb)  // DQT: tables of a precision/index byte and 64 values of 8 or 16 bits
            for (std::size_t t = at + 4; t < at + 2 + length && byte(t) >> 4 <= 1 && (byte(t) & 15) <= 3; t += 1 + (byte(t) >> 4 ? 128 : 64))
                quantizer[byte(t) & 15] = true;  // (other precisions and indices are refused by stb_image)
        if ((marker == 0xc0 || marker == 0xc1 || marker == 0xc2) && frame == 0 && length >= 8) {
            frame = marker;
            for (std::size_t c = 0; c < byte(at + 9); ++c)
                frame_ids.push_back(int(byte(at + 10 + 3 * c))), frame_quantizers.push_back(int(byte(at + 12 + 3 * c)));
        }
        if (marker == 0xda && frame != 0) {  // a scan's header: its components' tables, then Ss, Se, Ah/Al
            // (A file that ends inside the header still decodes, with the missing bytes read as 0.)
            const std::size_t n = byte(at + 4), f = at + 5;
            if (length == 6 + 2 * n) {  // (else refused by stb_image)
                const std::size_t ss = byte(f + 2 * n), se = byte(f + 2 * n + 1), ah = byte(f + 2 * n + 2) >> 4;
                const bool sequential = frame != 0xc2;
                const bool dc = sequential || (ss == 0 && se == 0 && ah == 0), ac = sequential || (ss > 0 && n == 1);
                for (std::size_t c = 0; c < n; ++c) {
                    const auto id = std::find(frame_ids.begin(), frame_ids.end(), int(byte(f + 2 * c)));
                    if (id == frame_ids.end()) continue;  // (refused by stb_image)
                    const std::size_t dc_index = byte(f + 2 * c + 1) >> 4, ac_index = byte(f + 2 * c + 1) & 15;
                    for (const auto& [used, kind, index] : {std::tuple(dc, 0, dc_index), std::tuple(ac, 1, ac_index)})
                        if (used && index <= 3 && !defined[kind][index])
                            return "not a readable image: a scan of the JPEG decodes with Huffman table " + std::string(kind ? "AC " : "DC ") +
                                   std::to_string(index) + ", which no table (DHT) before it defines";
                }
                // A sequential scan dequantizes each block as it decodes it.
                for (std::size_t c = 0; c < n && sequential; ++c)
                    if (const auto id = std::find(frame_ids.begin(), frame_ids.end(), int(byte(f + 2 * c))); id != frame_ids.end())
                        if (const int q = frame_quantizers[std::size_t(id - frame_ids.begin())]; q <= 3 && !quantizer[q])
                            return undefined_quantizer(std::size_t(q), "a scan of the JPEG");
            }
        }
        if (marker == 0xc0 || marker == 0xc1) {  // a sequential Huffman-coded frame
            const unsigned char* f = file.data() + at + 4;
            const int components = length >= 8 && at + 10 <= file.size() ? f[5] : 0;
            const std::uint64_t height = components ? std::uint64_t(f[1]) << 8 | f[2] : 0, width = components ? std::uint64_t(f[3]) << 8 | f[4] : 0;
            if (height > 0 && width > 0 && components > 0 && length >= 8 + 3 * std::size_t(components) && at + 2 + length <= file.size()) {
                int h_max = 1, v_max = 1;
                bool sampled = true;
                for (int c = 0; c < components; ++c) {
                    h_max = std::max(h_max, f[7 + 3 * c] >> 4), v_max = std::max(v_max, f[7 + 3 * c] & 15);
                    sampled &= (f[7 + 3 * c] >> 4) != 0 && (f[7 + 3 * c] & 15) != 0;  // (else refused by stb_image)
                }
                std::uint64_t blocks = 0;
                for (int c = 0; c < components && sampled; ++c) {
                    // A component's size: ceil(X h / h_max) x ceil(Y v / v_max) samples, in blocks of 8 x 8.
                    const std::uint64_t h = std::uint64_t(f[7 + 3 * c] >> 4), v = std::uint64_t(f[7 + 3 * c] & 15);
                    const std::uint64_t columns = (width * h + std::uint64_t(h_max) - 1) / std::uint64_t(h_max);
                    const std::uint64_t rows = (height * v + std::uint64_t(v_max) - 1) / std::uint64_t(v_max);
                    blocks += ((columns + 7) / 8) * ((rows + 7) / 8);
                }
                const std::uint64_t needed = (2 * blocks + 7) / 8;
                if (file.size() < needed)
                    return "not a readable image: the file is cut short (a " + std::to_string(width) + " x " + std::to_string(height) +
                           " sequential JPEG needs at least " + std::to_string(needed) + " bytes of image data, the file holds " +
                           std::to_string(file.size()) + ")";
            }
        }
        at += 2 + length;
        if (marker == 0xda) {  // a scan: its image data runs to the first marker other than a restart
            while (at + 1 < file.size() &&
                   !(file[at] == 0xff && file[at + 1] != 0x00 && file[at + 1] != 0xff && !(file[at + 1] >= 0xd0 && file[at + 1] <= 0xd7)))
                ++at;
        }
    }
    return "";
}

// The message for a file shorter than the least its header asks for: `needed` bytes in all.
std::string cut_short(const char* kind, std::uint64_t width, std::uint64_t height, std::uint64_t needed, std::size_t holds) {
    return "not a readable image: the file is cut short (a " + std::to_string(width) + " x " + std::to_string(height) + " " + kind +
           " needs at least " + std::to_string(needed) + " bytes, the file holds " + std::to_string(holds) + ")";
}

// stb_image reads a TGA whose pixels end early as if zeros followed (a 22-byte run-length
// TGA claiming 16000 x 16000 took 11 s and 2 GB). A TGA holds, after its 18-byte header,
// the ID field and the palette, either every pixel value or, run-length coded, packets of a
// 1-byte count and at least one value for at most 128 pixels each. Returns the message for
// a file shorter than that, or "". The header is taken as a TGA only where stb_image's own
// test would take it as one (a TGA has no signature).
std::string short_tga(const std::vector<unsigned char>& file) {
    // The header as stb_image reads it: bytes past the end of the file read as 0.
    unsigned char header[18] = {};
    if (!file.empty()) std::memcpy(header, file.data(), std::min<std::size_t>(file.size(), 18));
    const auto u16 = [&](std::size_t at) { return std::uint64_t(header[at]) | std::uint64_t(header[at + 1]) << 8; };
    const int colour_map = header[1], type = header[2], bits = header[16];
    const std::uint64_t id_length = header[0], palette_start = u16(3), palette_length = u16(5), palette_bits = header[7];
    const std::uint64_t width = u16(12), height = u16(14);
    const auto one_of = [](int x, std::initializer_list<int> set) { return std::find(set.begin(), set.end(), x) != set.end(); };
    if (colour_map == 1) {
        if (!one_of(type, {1, 9}) || !one_of(int(palette_bits), {8, 15, 16, 24, 32}) || !one_of(bits, {8, 16})) return "";
    } else if (colour_map != 0 || !one_of(type, {2, 3, 10, 11}) || !one_of(bits, {8, 15, 16, 24, 32})) {
        return "";
    }
    if (width == 0 || height == 0) return "";
    const std::uint64_t value_bytes = (std::uint64_t(bits) + 7) / 8, pixels = width * height;
    std::uint64_t needed = 18 + id_length;
    if (colour_map == 1) needed += palette_start + palette_length * ((palette_bits + 7) / 8);
    const bool run_length = type >= 9;
    needed += run_length ? (pixels + 127) / 128 * (1 + value_bytes) : pixels * value_bytes;
    if (file.size() >= needed) return "";
    return cut_short(run_length ? "run-length TGA" : "TGA", width, height, needed, file.size());
}

// The same for a Photoshop file (stb_image reads its RGB images): after the 26-byte header
// and three sections of a 4-byte length each, a 2-byte compression code, then for each of
// the first four channels (stb_image reads no more) every sample, or, run-length coded, a
// table of 2 bytes per row of every channel and runs of at most 128 samples in 2 bytes or
// more each.
std::string short_psd(const std::vector<unsigned char>& file) {
    if (file.size() < 4 || std::memcmp(file.data(), "8BPS", 4) != 0) return "";
    // Bytes past the end of the file read as 0, as stb_image reads them.
    const auto byte = [&](std::size_t at) { return at < file.size() ? std::uint64_t(file[at]) : 0; };
    const auto u16 = [&](std::size_t at) { return byte(at) << 8 | byte(at + 1); };
    const auto u32 = [&](std::size_t at) { return u16(at) << 16 | u16(at + 2); };
    const std::uint64_t channels = u16(12), height = u32(14), width = u32(18), depth = u16(22);
    if (u16(4) != 1 || channels > 16 || height == 0 || width == 0 || height > (1 << 24) || width > (1 << 24) ||
        (depth != 8 && depth != 16) || u16(24) != 3)
        return "";  // refused by stb_image
    // (stb_image reads a file of no channels as an image of black: 1 GB from a 56-byte file
    // whose header says 16000 x 16000, found by fuzzing)
    if (channels == 0) return "not a readable image: the Photoshop image has no channels";
    std::uint64_t at = 26;
    for (int section = 0; section < 3; ++section) at += 4 + u32(std::size_t(at));
    const std::uint64_t compression = u16(std::size_t(at));
    if (compression > 1) return "";  // refused by stb_image
    const std::uint64_t read = std::min<std::uint64_t>(channels, 4), pixels = width * height;
    const std::uint64_t needed = at + 2 + (compression == 1 ? height * channels * 2 + read * ((pixels + 127) / 128) * 2
                                                            : read * pixels * (depth / 8));
    if (file.size() >= needed) return "";
    return cut_short(compression == 1 ? "run-length Photoshop image" : "Photoshop image", width, height, needed, file.size());
}

// stb_image sets aside a PNG's whole image before it inflates the data, and fills it: a
// 1077-byte PNG whose header says 16000 x 16000 took 3.7 s and 1.7 GB before stb_image found
// too few pixels. Deflate packs at most 1032 bytes into one (a 258-byte match in 2 bits), so
// the image data (IDAT chunks) can hold no more than 1032 times its size, plus a little at the
// ends (1032 more is generous); every pixel's bits are in it at least once, interlaced or not.
// Returns the message for a file whose image data cannot hold its header's size, or "".
std::string short_png(const std::vector<unsigned char>& file) {
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (file.size() < 33 || std::memcmp(file.data(), signature, 8) != 0 || std::memcmp(file.data() + 12, "IHDR", 4) != 0) return "";
    const auto u32 = [&](std::size_t at) {
        return std::uint64_t(file[at]) << 24 | std::uint64_t(file[at + 1]) << 16 | std::uint64_t(file[at + 2]) << 8 | file[at + 3];
    };
    const std::uint64_t width = u32(16), height = u32(20), depth = file[24];
    const int colour = file[25];
    const int channels = colour == 0 ? 1 : colour == 2 ? 3 : colour == 3 ? 1 : colour == 4 ? 2 : colour == 6 ? 4 : 0;
    if (width == 0 || height == 0 || width > (1 << 24) || height > (1 << 24) || channels == 0 || depth == 0 || depth > 16)
        return "";  // refused by stb_image
    if (width > std::uint64_t(max_texture_side) || height > std::uint64_t(max_texture_side)) return "";  // (too large: told in decode)
    std::uint64_t data = 0;  // the IDAT chunks' bytes that the file holds
    for (std::size_t at = 8; at + 8 <= file.size();) {
        const std::uint64_t length = u32(at);
        if (std::memcmp(file.data() + at + 4, "IDAT", 4) == 0) data += std::min<std::uint64_t>(length, file.size() - (at + 8));
        if (std::memcmp(file.data() + at + 4, "IEND", 4) == 0 || length > file.size()) break;
        at += 12 + std::size_t(length);
    }
    const std::uint64_t pixel_bytes = width * height * std::uint64_t(channels) * depth / 8;
    if (pixel_bytes <= 1032 * data + 1032) return "";
    const std::uint64_t needed = (pixel_bytes - 1032 + 1031) / 1032;
    return "not a readable image: the file is cut short (a " + std::to_string(width) + " x " + std::to_string(height) +
           " PNG needs at least " + std::to_string(needed) + " bytes of image data, as deflate packs at most 1032 bytes into one; "
           "the file holds " + std::to_string(data) + ")";
}

// An empty IDAT chunk holds no image data, and a PNG may have one, but stb_image 2.27 copies
// it with memcpy from a null buffer when it comes first (undefined behaviour, found by fuzzing
// under UBSan). Such chunks are taken out of the file's bytes before stb_image reads them: the
// same image data, in the same order.
void drop_empty_png_data(std::vector<unsigned char>& file) {
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (file.size() < 8 || std::memcmp(file.data(), signature, 8) != 0) return;
    for (std::size_t at = 8; at + 8 <= file.size();) {
        const std::uint64_t length = std::uint64_t(file[at]) << 24 | std::uint64_t(file[at + 1]) << 16 | std::uint64_t(file[at + 2]) << 8 | file[at + 3];
        if (std::memcmp(file.data() + at + 4, "IEND", 4) == 0 || length > file.size()) return;
        if (length == 0 && std::memcmp(file.data() + at + 4, "IDAT", 4) == 0 && at + 12 <= file.size())
            file.erase(file.begin() + std::ptrdiff_t(at), file.begin() + std::ptrdiff_t(at + 12));  // (its length, type and CRC)
        else
            at += 12 + std::size_t(length);
    }
}

// The whole file, read once (a pipe can be read only once; stb_image then decodes from
// memory). stb_image takes the length as an int: a file of 2 GiB or more is refused, by its
// size before anything is read when it has one.
std::vector<unsigned char> file_bytes(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw InputError(path, 0, "cannot open image file");
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    const auto too_large = [&] { return InputError(path, 0, "not a readable image: it holds 2 GiB or more, more than stb_image reads"); };
    constexpr std::size_t limit = std::size_t(std::numeric_limits<int>::max());
    std::vector<unsigned char> bytes;
    struct stat info {};
    if (::fstat(fd, &info) == 0 && S_ISREG(info.st_mode)) {
        if (std::uint64_t(info.st_size) > limit) throw too_large();
        bytes.reserve(std::size_t(info.st_size));
    }
    unsigned char chunk[1 << 16];
    for (;;) {
        const ssize_t n = ::read(fd, chunk, sizeof chunk);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw InputError(path, 0, std::string("cannot read image file: ") + std::strerror(errno));
        if (n == 0) return bytes;
        if (bytes.size() + std::size_t(n) > limit) throw too_large();  // a pipe (a file that grew)
        bytes.insert(bytes.end(), chunk, chunk + n);
    }
}

// Whether stb_image's reading of the file can leave texels unset when the file is damaged:
// a palette image may index entries its palette does not hold (PNG, BMP: stb_image keeps the
// palette in a stack array), and the other decoders may stop short of filling the buffer they
// allocated (a JPEG component without a scan, a TGA cut short). PNG images without a palette,
// Radiance HDR and PPM/PGM (checked by short_pnm) fill every texel or fail.
bool may_leave_texels_unset(const std::vector<unsigned char>& file, bool hdr) {
    static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (file.size() > 25 && std::memcmp(file.data(), png, 8) == 0 && std::memcmp(file.data() + 12, "IHDR", 4) == 0)
        return file[25] == 3;  // colour type 3: palette indices
    if (file.size() >= 2 && file[0] == 'P' && (file[1] == '5' || file[1] == '6')) return false;
    return !hdr;
}

// A 64-bit hash of decoded texels (FNV-1a on 8-byte words, then mixed): two decodes of one
// file that differ anywhere differ here, but for a chance of about 2^-64.
std::uint64_t hash_of(const stb_decode::Pixels& p) {
    const std::size_t bytes = std::size_t(p.width) * std::size_t(p.height) * 4 * (p.hdr ? sizeof(float) : 1);
    const unsigned char* data = static_cast<const unsigned char*>(p.data.get());
    std::uint64_t h = 0xcbf29ce484222325ull;
    std::size_t i = 0;
    for (; i + 8 <= bytes; i += 8) {
        std::uint64_t word;
        std::memcpy(&word, data + i, 8);
        h = (h ^ word) * 0x100000001b3ull;
        h ^= h >> 29;
    }
    for (; i < bytes; ++i) h = (h ^ data[i]) * 0x100000001b3ull;
    return h ^ (h >> 32);
}

// The size a file's header gives, as stb_image will read it; false if none is found.
// stbi_info gives up on a Softimage PIC whose packets it cannot read, or whose size is above
// 2^28 texels, while stb_image's loader still sets aside the whole image before it reads a
// packet (a 172-byte PIC of 65535 x 8191 asked for 2.1 GB): the PIC's own header is read here.
// A PIC: the bytes 53 80 F6 34, 84 more, "PICT", then width and height (big-endian, 16 bits).
// A PNG's size is read here too: stbi_info gives none for one of more than 2^30 bytes of
// texels (20000 x 20000 RGB), which is then said to be too large rather than cut short.
// A PNG: its 8-byte signature, IHDR's length and type, then width and height (big-endian,
// 32 bits; above INT_MAX read as INT_MAX).
bool header_size(const std::vector<unsigned char>& file, int& width, int& height) {
    if (file.size() >= 96 && std::memcmp(file.data(), "\x53\x80\xF6\x34", 4) == 0 && std::memcmp(file.data() + 88, "PICT", 4) == 0) {
        width = file[92] << 8 | file[93], height = file[94] << 8 | file[95];
        return true;
    }
    if (file.size() >= 24 && std::memcmp(file.data(), "\x89PNG\r\n\x1a\n", 8) == 0 && std::memcmp(file.data() + 12, "IHDR", 4) == 0) {
        const auto side = [&](std::size_t at) {
            const std::uint64_t v = std::uint64_t(file[at]) << 24 | std::uint64_t(file[at + 1]) << 16 | std::uint64_t(file[at + 2]) << 8 | file[at + 3];
            return int(std::min<std::uint64_t>(v, std::uint64_t(std::numeric_limits<int>::max())));
        };
        width = side(16), height = side(20);
        return true;
    }
    return stb_decode::header_size(file.data(), int(file.size()), width, height);
}

// The file's bytes live only while it is decoded (not while the rows are flipped).
stb_decode::Pixels decode(const std::string& path) {
    std::vector<unsigned char> file = file_bytes(path);
    drop_empty_png_data(file);
    int pnm_largest = 255;
    if (const std::string cut = short_pnm(file, pnm_largest); !cut.empty()) throw InputError(path, 0, cut);
    if (const std::string cut = short_bmp(file); !cut.empty()) throw InputError(path, 0, cut);
    if (const std::string cut = short_png(file); !cut.empty()) throw InputError(path, 0, cut);
    if (const std::string damage = jpeg_damage(file); !damage.empty()) throw InputError(path, 0, damage);
    if (const std::string cut = short_tga(file); !cut.empty()) throw InputError(path, 0, cut);
    if (const std::string cut = short_psd(file); !cut.empty()) throw InputError(path, 0, cut);
    const int length = int(file.size());
    // The largest image texr reads (a few bytes can claim any size, and stb_image sets aside
    // the whole of it: a 214-byte GIF whose screen is 28013 x 24941 asked for 1.8 GB). After
    // the checks above, which keep stbi_info from headers it misreads (a PNM's overlong
    // numbers overflow its int).
    if (int w = 0, h = 0; header_size(file, w, h) && (w > max_texture_side || h > max_texture_side))
        throw InputError(path, 0, "the image is too large: its header says " + std::to_string(w) + " x " + std::to_string(h) +
                                      " texels, and texr reads at most " + std::to_string(max_texture_side) + " per side");
    const bool hdr = stb_decode::is_hdr(file.data(), length);
    if (hdr)
        if (const std::string cut = hdr_runs_cut(file); !cut.empty()) throw InputError(path, 0, cut);
    // Formats that can leave texels unset are decoded twice, with every byte stb_image allocates
    // and the stack below it set to 0 and then to 0xff: texels the file defines come out the
    // same; any other difference is memory the file left unset (valgrind showed such frames
    // change from run to run). The first result is kept only as a hash, so that two decoded
    // images are never held at once.
    const bool twice = may_leave_texels_unset(file, hdr);
    std::uint64_t first_hash = 0;
    int first_width = 0, first_height = 0;
    if (twice) {
        const stb_decode::Pixels first = stb_decode::decode(file.data(), length, hdr, 0x00);
        if (first.data) first_hash = hash_of(first), first_width = first.width, first_height = first.height;
    }
    stb_decode::Pixels d = stb_decode::decode(file.data(), length, hdr, 0xff);
    if (!d.data) throw InputError(path, 0, unreadable(d.failure.c_str()));
    if (d.width <= 0 || d.height <= 0) throw InputError(path, 0, "not a readable image: it has no texels");
    if (d.width > max_texture_side || d.height > max_texture_side)  // (a format whose size the header did not give)
        throw InputError(path, 0, "the image is too large: it is " + std::to_string(d.width) + " x " + std::to_string(d.height) +
                                      " texels, and texr reads at most " + std::to_string(max_texture_side) + " per side");
    if (twice && (first_width != d.width || first_height != d.height || first_hash != hash_of(d)))
        throw InputError(path, 0, "not a readable image: it leaves texels undefined (a palette index beyond its palette, or "
                                  "image data it does not hold)");
    // A PPM/PGM's sample k of largest value m < 255 means k / m: scaled to the nearest of the
    // 8-bit values, round(255 k / m) (exact where m divides 255: 1, 3, 5, 15, 17, 51, 85).
    if (pnm_largest < 255) {
        auto* texels = static_cast<unsigned char*>(d.data.get());
        const std::size_t count = std::size_t(d.width) * std::size_t(d.height);
        for (std::size_t i = 0; i < count; ++i)
            for (std::size_t c = 0; c < 3; ++c) {  // (alpha: stb_image's 255)
                unsigned char& k = texels[4 * i + c];
                if (k > pnm_largest)
                    throw InputError(path, 0, "not a readable image: a sample of " + std::to_string(int(k)) +
                                                  " above the PPM/PGM header's largest value, " + std::to_string(pnm_largest));
                k = static_cast<unsigned char>((255 * k + pnm_largest / 2) / pnm_largest);
            }
    }
    return d;
}

}  // namespace

bool image_file_is_16_bit(const std::string& path) {
    require_file(path, "an image file");
    const std::vector<unsigned char> file = file_bytes(path);
    return stb_decode::is_16_bit(file.data(), int(file.size()));
}

Image load_image(const std::string& path, ColorSpace space) {
    require_file(path, "an image file");
    const stb_decode::Pixels d = decode(path);
    if (d.hdr) return Image::hdr(d.width, d.height, flipped_rows(static_cast<const float*>(d.data.get()), d.width, d.height));
    return Image::ldr(d.width, d.height, space, flipped_rows(static_cast<const unsigned char*>(d.data.get()), d.width, d.height));
}

}  // namespace texr
