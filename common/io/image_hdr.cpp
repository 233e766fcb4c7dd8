// Radiance .hdr (RGBE) images through stb_image's float loader, after a walk of the file that
// makes sure stb_image (2.27, Debian 12) reads only bytes the file holds (see image.h).
#include <stb_image.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "io/image.h"
#include "io/input_error.h"

namespace lessons {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& message) {
    throw InputError(path, 0, "", message);
}

// The header as stb_image parses it: a "#?RADIANCE" or "#?RGBE" line, lines up to an empty one
// (one of them "FORMAT=32-bit_rle_rgbe"), then "-Y H +X W". Returns the offset of the first
// scanline; sets width and height.
size_t parse_header(const std::string& path, const std::vector<unsigned char>& bytes, int64_t& width,
                    int64_t& height) {
    size_t pos = 0;
    const auto line = [&](std::string& out) {
        out.clear();
        while (pos < bytes.size() && bytes[pos] != '\n') out.push_back(static_cast<char>(bytes[pos++]));
        if (pos == bytes.size()) return false;
        ++pos;  // the '\n'
        return true;
    };
    std::string text;
    // (Compared up to a NUL byte, as stb_image compares them; a line that starts with one ends
    // the header there too.)
    if (!line(text) || (std::strcmp(text.c_str(), "#?RADIANCE") != 0 &&
                        std::strcmp(text.c_str(), "#?RGBE") != 0))
        fail(path, "not a Radiance HDR (RGBE) file: it does not begin with a #?RADIANCE line");
    bool rgbe = false;
    for (;;) {
        if (!line(text)) fail(path, "the Radiance HDR header is cut short (truncated?)");
        if (text.c_str()[0] == '\0') break;
        rgbe |= std::strcmp(text.c_str(), "FORMAT=32-bit_rle_rgbe") == 0;
    }
    if (!rgbe)
        fail(path, "the Radiance HDR header has no FORMAT=32-bit_rle_rgbe line (the suite reads "
                   "RGB radiance, not XYZ)");
    if (!line(text)) fail(path, "the Radiance HDR file has no size line, or nothing after it");
    // (The size line's numbers are read as stb_image reads them; other layouts it refuses.)
    const char* p = text.c_str();
    char* end = nullptr;
    if (std::strncmp(p, "-Y ", 3) != 0)
        fail(path, "size line '" + text.substr(0, 40) +
                       "': the suite reads the standard layout '-Y HEIGHT +X WIDTH' (top row "
                       "first, left to right)");
    height = std::strtol(p + 3, &end, 10);
    while (*end == ' ') ++end;
    if (std::strncmp(end, "+X ", 3) != 0)
        fail(path, "size line '" + text.substr(0, 40) +
                       "': the suite reads the standard layout '-Y HEIGHT +X WIDTH'");
    width = std::strtol(end + 3, nullptr, 10);
    return pos;
}

// The scanlines, walked as stb_image reads them, without decoding: true if every byte it reads is
// in the file. (stb_image reads zeros past the end without an error, and loops forever on a run
// of length 0: both are refused here.)
void walk_scanlines(const std::string& path, const std::vector<unsigned char>& bytes, size_t pos,
                    int64_t width, int64_t height) {
    const auto size = static_cast<int64_t>(bytes.size());
    const auto flat_from = [&](int64_t start, int64_t row) {
        // Flat (uncompressed) pixels, 4 bytes each; stb_image reads every pixel of the image
        // from here (its decoder starts over at the top: the rows before are overwritten).
        if (start + 4 * width * height > size)
            fail(path, "the pixels from row " + std::to_string(row) + " need " +
                           std::to_string(4 * width * height) + " bytes, the file has " +
                           std::to_string(size - start) + " (truncated?)");
    };
    if (width < 8 || width >= 32768) return flat_from(static_cast<int64_t>(pos), 0);
    int64_t at = static_cast<int64_t>(pos);
    const auto cut_short = [&](int64_t row) {
        fail(path, "scanline " + std::to_string(row) + " of " + std::to_string(height) +
                       " is cut short (truncated?)");
    };
    for (int64_t j = 0; j < height; ++j) {
        if (at + 4 > size) cut_short(j);
        if (bytes[at] != 2 || bytes[at + 1] != 2 || (bytes[at + 2] & 0x80)) return flat_from(at, j);
        if ((int64_t{bytes[at + 2]} << 8 | bytes[at + 3]) != width)
            fail(path, "scanline " + std::to_string(j) + " gives a width other than the header's");
        at += 4;
        for (int component = 0; component < 4; ++component) {
            for (int64_t left = width; left > 0;) {
                if (at >= size) cut_short(j);
                int64_t count = bytes[at++];
                const bool run = count > 128;
                if (run) count -= 128;
                if (count == 0 || count > left)
                    fail(path, "scanline " + std::to_string(j) +
                                   " has a run-length code that does not fit it (damaged?)");
                at += run ? 1 : count;
                if (at > size) cut_short(j);
                left -= count;
            }
        }
    }
}

}  // namespace

void check_hdr_file(const std::string& path, const std::vector<unsigned char>& bytes) {
    int64_t width = 0, height = 0;
    const size_t data = parse_header(path, bytes, width, height);
    const std::string text = std::to_string(width) + " x " + std::to_string(height);
    if (width < 1 || height < 1) fail(path, "its size " + text + " holds no pixels");
    // The size stb_image reads, which must be the one just parsed.
    int w = 0, h = 0, channels = 0;
    if (bytes.size() > static_cast<size_t>(INT_MAX))
        fail(path, "a Radiance HDR file of over 2 GiB is more than the suite reads");
    if (!stbi_info_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &channels) ||
        w != width || h != height) {
        const char* why = stbi_failure_reason();
        fail(path, std::string("stb_image cannot read its size") + (why ? std::string(": ") + why : ""));
    }
    // As for an EXR: at most 8,388,608 pixels a side, fewer than 2^31 pixels, and no more
    // pixels than the file can encode. RGBE's run-length code packs at most 127 pixels into 8
    // bytes (a run of 127 in each of the 4 components): 16 pixels per byte is a bound. (And
    // stb_image allocates at most INT_MAX bytes, 3 floats a pixel.)
    constexpr int64_t kMaxSide = 8192 * 1024;
    if (width > kMaxSide || height > kMaxSide)
        fail(path, "its size " + text + " is over " + std::to_string(kMaxSide) +
                       " pixels wide or tall");
    const int64_t file_size = static_cast<int64_t>(bytes.size());
    if (width * height > std::min<int64_t>(INT32_MAX / 12, 16 * file_size))
        fail(path, "its size " + text + " is more pixels than a file of " +
                       std::to_string(file_size) + " bytes can encode (damaged?)");
    walk_scanlines(path, bytes, data, width, height);
}

Image read_hdr(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open the Radiance HDR file");
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                           std::istreambuf_iterator<char>());
    if (in.bad()) fail(path, "cannot read the Radiance HDR file");
    check_hdr_file(path, bytes);
    int w = 0, h = 0, channels = 0;
    // RGBE holds linear radiance: stb_image's float loader applies no curve to it.
    float* rgb =
        stbi_loadf_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &channels, 3);
    if (!rgb) {
        const char* why = stbi_failure_reason();
        fail(path, std::string("cannot read the Radiance HDR file") +
                       (why ? std::string(": ") + why : ""));
    }
    Image image(w, h);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = Color(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
    stbi_image_free(rgb);
    return image;
}

}  // namespace lessons
