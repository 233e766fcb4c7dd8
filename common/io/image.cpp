// Image output through tinyexr (linear EXR) and stb_image_write (sRGB PNG).
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

Image read_image(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext != ".png" && ext != ".jpg" && ext != ".jpeg") return read_exr(path);
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

// Reads the header's attributes with the rules of tinyexr's own parser (a name and a type, each
// ending in a NUL byte, a 4-byte little-endian size, the value; an empty name ends the header),
// so that it sees every attribute tinyexr would, and stops where tinyexr's parse would fail.
// tinyexr converts (and asserts on) what it read even when its parse fails part way, so every
// attribute up to the stop is checked, not only the last of a name.
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
    // A string up to its NUL byte, keeping at most `keep` characters; false at the end of file.
    const auto read_name = [&](std::string& out, size_t keep) {
        out.clear();
        for (int c; (c = in.get()) != EOF;) {
            if (c == 0) return true;
            if (out.size() < keep) out.push_back(static_cast<char>(c));
        }
        return false;
    };
    const auto read_int = [&](int32_t& v) {
        unsigned char b[4];
        if (!in.read(reinterpret_cast<char*>(b), 4)) return false;
        v = static_cast<int32_t>(b[0] | b[1] << 8 | b[2] << 16 | static_cast<uint32_t>(b[3]) << 24);
        return true;
    };
    // tinyexr takes a window's size in int arithmetic, which overflows for windows from near
    // -2^31 to near 2^31 (and then allocates for the wrapped count): sizes in 64 bits, within
    // tinyexr's own limit per side, fewer than 2^31 pixels (its loops count them in an int), and
    // no more pixels than a file of this size can encode (no codec packs 4096 into a byte: a
    // constant 4096 x 4096 image takes 156 per byte in ZIP half floats).
    const auto check_window = [&](const std::array<int32_t, 4>& v) {
        constexpr int64_t kMaxSide = 8192 * 1024;  // TINYEXR_DIMENSION_THRESHOLD
        const int64_t w = int64_t{v[2]} - v[0] + 1, h = int64_t{v[3]} - v[1] + 1;
        const std::string text = "(" + std::to_string(v[0]) + ", " + std::to_string(v[1]) +
                                 ") to (" + std::to_string(v[2]) + ", " + std::to_string(v[3]) +
                                 ")";
        if (w < 1 || h < 1) fail("dataWindow", text + " holds no pixels");
        if (w > kMaxSide || h > kMaxSide)
            fail("dataWindow",
                 text + " is over " + std::to_string(kMaxSide) + " pixels wide or tall");
        if (w * h > std::min<int64_t>(INT32_MAX, 4096 * static_cast<int64_t>(file_size)))
            fail("dataWindow", text + " holds " + std::to_string(w * h) +
                                   " pixels, more than a file of " + std::to_string(file_size) +
                                   " bytes can encode (damaged?)");
    };
    int64_t lines = 0;   // the last data window's
    int32_t chunks = 0;  // the last chunk count
    int codec = 0;       // the last compression
    for (int count = 0;; ++count) {
        const int first = in.peek();
        if (first == EOF) return;  // (tinyexr: no end of header)
        if (first == 0) break;     // the end of the header
        // (tinyexr reads at most 1024 attributes; stopping here keeps both on the same ones)
        if (count == 1024) fail("", "more than 1024 header attributes (damaged?)");
        std::string name, type_name;
        if (!read_name(name, 64) || !read_name(type_name, 64)) return;
        int32_t raw_size = 0;
        if (!read_int(raw_size)) return;
        const auto size = static_cast<uint32_t>(raw_size);
        const std::streamoff here = in.tellg();
        if (size == 0 && type_name != "string") return;
        if (static_cast<std::streamoff>(size) > file_size - here) return;
        if (name == "type" && size > 0) {
            // tinyexr keeps the value up to its first NUL byte (an empty value is no type), and
            // asserts on any value but the four it knows, and on a tiled or deep one here.
            std::string value(std::min<uint32_t>(size, 64), '\0');
            in.read(value.data(), static_cast<std::streamsize>(value.size()));
            value.resize(std::strlen(value.c_str()));
            if (!value.empty() && value != "scanlineimage")
                fail("type", "'" + value.substr(0, 32) +
                                 "' is not a scanline image (the suite reads scanline EXR files)");
        } else if (name == "dataWindow" && size >= 16) {
            std::array<int32_t, 4> v;
            for (int32_t& x : v)
                if (!read_int(x)) return;
            check_window(v);
            lines = int64_t{v[3]} - v[1] + 1;
        } else if (name == "chunkCount" && size >= 4) {
            if (!read_int(chunks)) return;
        } else if (name == "compression") {
            codec = in.get();
        }
        in.seekg(here + static_cast<std::streamoff>(size));
    }
    // tinyexr takes a positive chunk count as the number of line offsets, allocated before they
    // are read, and reads a wrong image when it is not the data window's: it must be that.
    if (chunks > 0) {
        const int64_t per_chunk = codec == 3 ? 16 : codec == 4 ? 32 : 1;  // ZIP, PIZ, the others
        const int64_t expected = (lines + per_chunk - 1) / per_chunk;
        if (chunks != expected)
            fail("chunkCount", "is " + std::to_string(chunks) + ", but the data window's " +
                                   std::to_string(lines) + " lines make " +
                                   std::to_string(expected) + " chunks in codec " +
                                   std::to_string(codec));
    }
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
