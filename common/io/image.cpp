// Image output through tinyexr (linear EXR) and stb_image_write (sRGB PNG); input from EXR
// (tinyexr), PNG and JPEG (stb_image) and Radiance .hdr (image_hdr.cpp).
#include "io/image.h"

#include <stb_image.h>
#include <stb_image_write.h>
#include <tinyexr.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/input_error.h"

namespace lessons {

float srgb_encode(float linear) {
    if (linear <= 0.0031308f) return 12.92f * linear;
    return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

void rename_into_place(const std::string& tmp, const std::string& path) {
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw std::runtime_error(path + ": cannot write (rename from temporary failed)");
    }
}

void write_exr(const Image& image, const std::string& path) {
    write_atomically(path, [&](const std::string& tmp) {
        // Check that the file can be created first: tinyexr 1.0.1 leaks its header buffers when
        // it cannot open the file, and this message names the reason.
        if (std::FILE* f = std::fopen(tmp.c_str(), "wb")) {
            std::fclose(f);
        } else {
            throw std::runtime_error(path + ": cannot write EXR: " + std::strerror(errno));
        }
        const char* err = nullptr;
        const int rc = SaveEXR(reinterpret_cast<const float*>(image.pixels.data()), image.width,
                               image.height, 3, /*save_as_fp16=*/0, tmp.c_str(), &err);
        if (rc != TINYEXR_SUCCESS) {
            std::string msg = path + ": cannot write EXR";
            if (err) {
                msg += std::string(": ") + err;
                FreeEXRErrorMessage(err);
            }
            std::remove(tmp.c_str());
            throw std::runtime_error(msg);
        }
    });
}

std::vector<uint8_t> display_bytes(const Image& image, float exposure_stops) {
    const float scale = std::exp2(exposure_stops);
    std::vector<uint8_t> bytes(static_cast<size_t>(image.width) * image.height * 3);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            float v = image.pixels[i][c] * scale;
            v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : (v > 0.0f ? 1.0f : 0.0f);
            bytes[3 * i + c] = static_cast<uint8_t>(std::lround(255.0f * srgb_encode(v)));
        }
    }
    return bytes;
}

void write_png(const Image& image, const std::string& path, float exposure_stops) {
    write_png_bytes(path, image.width, image.height, display_bytes(image, exposure_stops));
}

std::string encode_png(int width, int height, const std::vector<uint8_t>& rgb) {
    std::string png;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), size);
    };
    if (!stbi_write_png_to_func(append, &png, width, height, 3, rgb.data(), width * 3))
        throw std::runtime_error("cannot encode PNG");
    return png;
}

float srgb_decode(float v) {
    if (v <= 0.04045f) return v / 12.92f;
    return std::pow((v + 0.055f) / 1.055f, 2.4f);
}

void write_png_bytes(const std::string& path, int width, int height,
                     const std::vector<uint8_t>& rgb) {
    write_atomically(path, [&](const std::string& tmp) {
        if (!stbi_write_png(tmp.c_str(), width, height, 3, rgb.data(), width * 3)) {
            std::remove(tmp.c_str());
            throw std::runtime_error(path + ": cannot write PNG");
        }
    });
}

Image read_linear_image(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    return ext == ".hdr" ? read_hdr(path) : read_exr(path);
}

Image read_image(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext != ".png" && ext != ".jpg" && ext != ".jpeg") return read_linear_image(path);
    // 8- or 16-bit sRGB-encoded: decoded to linear by the standard curve.
    int w = 0, h = 0, channels = 0;
    const bool sixteen = stbi_is_16_bit(path.c_str());
    void* data = sixteen ? static_cast<void*>(stbi_load_16(path.c_str(), &w, &h, &channels, 3))
                         : static_cast<void*>(stbi_load(path.c_str(), &w, &h, &channels, 3));
    if (!data) {
        const char* why = stbi_failure_reason();
        throw std::runtime_error(path + ": cannot read the image" +
                                 (why ? std::string(": ") + why : ""));
    }
    Image image(w, h);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            image.pixels[i][c] =
                sixteen ? srgb_decode(static_cast<const uint16_t*>(data)[3 * i + c] / 65535.0f)
                        : srgb_decode(static_cast<const uint8_t*>(data)[3 * i + c] / 255.0f);
    stbi_image_free(data);
    return image;
}

namespace {

// The header check of check_exr_header, step by step: the attributes as tinyexr reads them, the
// sizes it allocates for, the line offsets it follows.
class ExrHeaderCheck {
public:
    ExrHeaderCheck(const std::string& path, std::ifstream& in, std::streamoff file_size)
        : path_(path), in_(in), file_size_(file_size) {}

    // Reads the header's attributes with the rules of tinyexr's own parser (a name and a type,
    // each ending in a NUL byte, a 4-byte little-endian size, the value; an empty name ends the
    // header), so that it sees every attribute tinyexr would, and stops where tinyexr's parse
    // fails on the file's structure or on a codec it does not read (it also fails on a bad
    // channel list, later). tinyexr converts (and asserts on) what it read even when its parse
    // fails part way, so every attribute up to the stop is checked, not only the last of a name.
    // True when the whole header was read, with a data window.
    bool attributes();
    // What tinyexr allocates before decoding: every channel of the image, and the line offsets.
    void sizes() const;
    // The line offsets and the chunks they point to.
    void line_offsets();

private:
    [[noreturn]] void fail(const char* field, const std::string& message) const {
        throw InputError(path_, 0, field, message);
    }
    // A string up to its NUL byte, keeping at most `keep` characters; false at the end of file.
    bool read_name(std::string& out, size_t keep) {
        out.clear();
        for (int c; (c = in_.get()) != EOF;) {
            if (c == 0) return true;
            if (out.size() < keep) out.push_back(static_cast<char>(c));
        }
        return false;
    }
    bool read_int(int32_t& v) {
        unsigned char b[4];
        if (!in_.read(reinterpret_cast<char*>(b), 4)) return false;
        v = static_cast<int32_t>(b[0] | b[1] << 8 | b[2] << 16 | static_cast<uint32_t>(b[3]) << 24);
        return true;
    }
    void check_window(const std::array<int32_t, 4>& v) const;
    int64_t width() const { return int64_t{(*window_)[2]} - (*window_)[0] + 1; }
    int64_t lines() const { return int64_t{(*window_)[3]} - (*window_)[1] + 1; }
    int64_t lines_per_chunk() const { return codec_ == 3 ? 16 : codec_ == 4 ? 32 : 1; }  // ZIP, PIZ
    int64_t chunk_total() const { return (lines() + lines_per_chunk() - 1) / lines_per_chunk(); }

    const std::string& path_;
    std::ifstream& in_;
    const std::streamoff file_size_;
    std::optional<std::array<int32_t, 4>> window_;  // the last data window
    int32_t chunks_ = 0;                            // the last chunk count
    int codec_ = 0;                                 // the last compression
    int64_t channel_count_ = 0, pixel_bytes_ = 0;   // the last channel list's
    std::streamoff header_end_ = 0;                 // where the final NUL is
};

// tinyexr takes a window's size in int arithmetic, which overflows for windows from near
// -2^31 to near 2^31 (and then allocates for the wrapped count): sizes in 64 bits, within
// tinyexr's own limit per side, fewer than 2^31 pixels (its loops count them in an int), and
// no more pixels than a file of this size can encode (no codec packs 4096 into a byte: a
// constant 4096 x 4096 image takes 156 per byte in ZIP half floats).
void ExrHeaderCheck::check_window(const std::array<int32_t, 4>& v) const {
    constexpr int64_t kMaxSide = 8192 * 1024;  // TINYEXR_DIMENSION_THRESHOLD
    const int64_t w = int64_t{v[2]} - v[0] + 1, h = int64_t{v[3]} - v[1] + 1;
    const std::string text = "(" + std::to_string(v[0]) + ", " + std::to_string(v[1]) + ") to (" +
                             std::to_string(v[2]) + ", " + std::to_string(v[3]) + ")";
    if (w < 1 || h < 1) fail("dataWindow", text + " holds no pixels");
    if (w > kMaxSide || h > kMaxSide)
        fail("dataWindow", text + " is over " + std::to_string(kMaxSide) + " pixels wide or tall");
    if (w * h > std::min<int64_t>(INT32_MAX, 4096 * static_cast<int64_t>(file_size_)))
        fail("dataWindow", text + " holds " + std::to_string(w * h) +
                               " pixels, more than a file of " + std::to_string(file_size_) +
                               " bytes can encode (damaged?)");
}

bool ExrHeaderCheck::attributes() {
    for (int count = 0;; ++count) {
        const int first = in_.peek();
        if (first == EOF) return false;  // (tinyexr: no end of header)
        if (first == 0) {                // the end of the header
            header_end_ = in_.tellg();
            return window_.has_value();  // (without a data window tinyexr says what is missing)
        }
        // (tinyexr reads at most 1024 attributes; stopping here keeps both on the same ones)
        if (count == 1024) fail("", "more than 1024 header attributes (damaged?)");
        std::string name, type_name;
        if (!read_name(name, 64) || !read_name(type_name, 64)) return false;
        int32_t raw_size = 0;
        if (!read_int(raw_size)) return false;
        const auto size = static_cast<uint32_t>(raw_size);
        const std::streamoff here = in_.tellg();
        if (size == 0 && type_name != "string") return false;
        if (static_cast<std::streamoff>(size) > file_size_ - here) return false;
        if (name == "type" && size > 0) {
            // tinyexr keeps the value up to its first NUL byte (an empty value is no type), and
            // asserts on any value but the four it knows, and on a tiled one in a scanline file
            // (a deep one it does not read either).
            std::string value(std::min<uint32_t>(size, 64), '\0');
            in_.read(value.data(), static_cast<std::streamsize>(value.size()));
            value.resize(std::strlen(value.c_str()));
            if (!value.empty() && value != "scanlineimage")
                fail("type", "'" + value.substr(0, 32) +
                                 "' is not a scanline image (the suite reads scanline EXR files)");
        } else if (name == "dataWindow" && size >= 16) {
            std::array<int32_t, 4> v;
            for (int32_t& x : v)
                if (!read_int(x)) return false;
            check_window(v);
            window_ = v;
        } else if (name == "chunkCount" && size >= 4) {
            if (!read_int(chunks_)) return false;
        } else if (name == "compression") {
            codec_ = size > 0 ? in_.get() : 0;
            if (codec_ > 4) return false;  // (tinyexr's parse stops: no codec it reads)
        } else if (name == "channels") {
            // Each channel: its name, NUL, then 16 bytes (pixel type, linear flag, reserved,
            // sampling); a NUL ends the list. Counted generously: at least tinyexr's count.
            channel_count_ = 0;
            pixel_bytes_ = 0;
            std::string channel;
            while (in_.tellg() - here < static_cast<std::streamoff>(size) && in_.peek() > 0) {
                if (!read_name(channel, 0)) return false;
                int32_t type = 0;
                if (!read_int(type)) return false;
                ++channel_count_;
                pixel_bytes_ += type == 1 ? 2 : 4;  // half, else uint or float
                in_.seekg(12, std::ios::cur);
            }
        }
        in_.clear();
        in_.seekg(here + static_cast<std::streamoff>(size));
    }
}

void ExrHeaderCheck::sizes() const {
    // tinyexr allocates every channel of the image, and a chunk's worth of each, before decoding:
    // samples per byte of the file are bounded as pixels are (a constant image in ZIP half
    // floats takes 470 samples per byte).
    if (width() * lines() * std::max(channel_count_, int64_t{1}) > 4096 * int64_t{file_size_})
        fail("channels", std::to_string(channel_count_) + " channels of " +
                             std::to_string(width() * lines()) +
                             " pixels are more than a file of " + std::to_string(file_size_) +
                             " bytes can encode (damaged?)");
    // tinyexr takes a positive chunk count as the number of line offsets, allocated before they
    // are read, and reads a wrong image when it is not the data window's: it must be that.
    if (chunks_ > 0 && chunks_ != chunk_total())
        fail("chunkCount", "is " + std::to_string(chunks_) + ", but the data window's " +
                               std::to_string(lines()) + " lines make " +
                               std::to_string(chunk_total()) + " chunks in codec " +
                               std::to_string(codec_));
}

void ExrHeaderCheck::line_offsets() {
    // The line offsets: tinyexr decodes each chunk where its offset points, at the line the chunk
    // names, and never checks that every line was written: two offsets to one chunk, or a damaged
    // line number, leave lines of uninitialised memory in the image, without an error. Chunk k
    // must lie in the file and hold the lines from min y + k * lines per chunk.
    const auto damaged = [&](int64_t k, const std::string& why) {
        fail("", "line chunk " + std::to_string(k) + " of " + std::to_string(chunk_total()) + " " +
                     why + " (damaged or truncated?)");
    };
    in_.clear();
    in_.seekg(header_end_);
    const std::streamoff table = header_end_ + 1;  // after the header's final NUL
    if (table + 8 * chunk_total() > file_size_) damaged(0, "has no offset in the file");
    for (int64_t k = 0; k < chunk_total(); ++k) {
        in_.clear();
        in_.seekg(table + 8 * k);
        unsigned char b[8];
        in_.read(reinterpret_cast<char*>(b), 8);
        uint64_t offset = 0;
        for (int i = 7; i >= 0; --i) offset = offset << 8 | b[i];
        if (offset < static_cast<uint64_t>(table + 8 * chunk_total()) ||
            offset > static_cast<uint64_t>(file_size_) - 8)
            damaged(k, "has an offset outside the file's chunks");
        in_.seekg(static_cast<std::streamoff>(offset));
        int32_t y = 0, data_size = 0;
        if (!read_int(y) || !read_int(data_size)) damaged(k, "is cut short");
        if (int64_t{y} != (*window_)[1] + k * lines_per_chunk())
            damaged(k, "names line " + std::to_string(y) + ", not " +
                           std::to_string((*window_)[1] + k * lines_per_chunk()));
        const int64_t data_end = static_cast<int64_t>(offset) + 8 + int64_t{data_size};
        if (data_size < 0 || data_end > file_size_) damaged(k, "runs past the end of the file");
        // PIZ: tinyexr copies the chunk's bitmap and reads its Huffman header (20 bytes) without
        // checking them against the chunk's size. (A chunk as large as its raw pixels is stored
        // raw.)
        const int64_t chunk_lines = std::min(lines_per_chunk(), lines() - k * lines_per_chunk());
        if (codec_ == 4 && data_size < width() * chunk_lines * pixel_bytes_) {
            if (data_size < 4) damaged(k, "is too short for PIZ");
            unsigned char head[4];
            in_.read(reinterpret_cast<char*>(head), 4);
            const int lo = head[0] | head[1] << 8, hi = head[2] | head[3] << 8;
            const int64_t bitmap = lo <= hi ? hi - lo + 1 : 0;
            int32_t length = 0;
            if (4 + bitmap + 4 > data_size) damaged(k, "is too short for its PIZ bitmap");
            in_.seekg(bitmap, std::ios::cur);
            if (!read_int(length) || length < 20 || 4 + bitmap + 4 + int64_t{length} > data_size)
                damaged(k, "is too short for its PIZ Huffman data");
        }
    }
}

}  // namespace

void check_exr_header(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return;  // (tinyexr names a missing or unreadable file)
    in.seekg(0, std::ios::end);
    const std::streamoff file_size = in.tellg();
    in.seekg(0);
    unsigned char version[8];
    if (file_size < 8 || !in.read(reinterpret_cast<char*>(version), 8)) return;
    if (version[0] != 0x76 || version[1] != 0x2f || version[2] != 0x31 || version[3] != 0x01 ||
        version[4] != 2)
        return;
    const auto fail = [&](const char* field, const std::string& message) {
        throw InputError(path, 0, field, message);
    };
    // Tiled (bit 9), deep (bit 11) and multi-part (bit 12) files take tinyexr's least tried
    // paths, several of which abort on damaged data (a level mode of 3, a tile size of 0):
    // the suite reads single-part scanline images only, as every renderer and editor can write.
    if ((version[5] & (0x2 | 0x8 | 0x10)) != 0)
        fail("", std::string("is a ") +
                     ((version[5] & 0x10)  ? "multi-part"
                      : (version[5] & 0x8) ? "deep"
                                           : "tiled") +
                     " EXR: the suite reads single-part scanline EXR files (save it as scanlines)");
    ExrHeaderCheck check(path, in, file_size);
    if (!check.attributes()) return;  // (tinyexr's parse fails: it reports why)
    check.sizes();
    check.line_offsets();
}

Image read_exr(const std::string& path) {
    check_exr_header(path);
    float* rgba = nullptr;
    int w = 0, h = 0;
    const char* err = nullptr;
    if (LoadEXR(&rgba, &w, &h, path.c_str(), &err) != TINYEXR_SUCCESS) {
        std::string msg = path + ": cannot read EXR";
        if (err) {
            msg += std::string(": ") + err;
            FreeEXRErrorMessage(err);
        }
        throw std::runtime_error(msg);
    }
    Image image(w, h);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = Color(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]);
    std::free(rgba);
    return image;
}

}  // namespace lessons
