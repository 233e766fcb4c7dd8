// Linear RGB images, and writing them as linear EXR (radiance) and sRGB PNG (for looking at);
// reading EXR (image_exr.cpp, through OpenEXR), Radiance .hdr (image_hdr.cpp), PNG and JPEG.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "geometry/math.h"

namespace lessons {

struct Image {
    int width = 0, height = 0;
    std::vector<Color> pixels;  // row-major, top row first
    // What reading approximated, one sentence each naming the file (a multi-part EXR's other
    // parts ignored); the caller passes them on as notes.
    std::vector<std::string> notes;

    Image() = default;
    Image(int w, int h) : width(w), height(h), pixels(static_cast<size_t>(w) * h, Color(0.0f)) {}
    Color& at(int x, int y) { return pixels[static_cast<size_t>(y) * width + x]; }
    const Color& at(int x, int y) const { return pixels[static_cast<size_t>(y) * width + x]; }
};

// The sRGB transfer curve (IEC 61966-2-1) of a linear value in [0, 1].
float srgb_encode(float linear);

// Writes 32-bit float linear RGB as a ZIP-compressed scanline EXR, through OpenEXR (what
// Blender, tinyexr and every EXR reader read). Throws std::runtime_error on failure.
void write_exr(const Image& image, const std::string& path);
// Writes an 8-bit sRGB PNG of the image scaled by 2^exposure_stops: each linear channel is
// multiplied by the exposure, clamped to [0, 1] (values above 1 saturate to white), encoded with
// the sRGB curve and rounded to the nearest of 256 levels. Throws std::runtime_error on failure.
void write_png(const Image& image, const std::string& path, float exposure_stops = 0.0f);
// Reads an EXR's R, G and B channels (any alpha ignored), or its Y channel as grey, through
// OpenEXR: every compression it reads (none, RLE, ZIPS, ZIP, PIZ, PXR24, B44, B44A, DWAA, DWAB),
// half, float or uint pixels, scanlines or tiles (the full-resolution level), the data window;
// of a multi-part file the first part, with a note. The header is checked first
// (check_exr_header, exr_file.h). Throws an InputError naming the file (and the attribute).
Image read_exr(const std::string& path);
// Reads a Radiance .hdr (RGBE) file's linear RGB with stb_image's float loader (no curve), after
// check_hdr_file. Throws an InputError naming the file on failure.
Image read_hdr(const std::string& path);
// Checks a Radiance .hdr file's bytes before stb_image (2.27) decodes them, which would otherwise
// read zeros past the end of a truncated file without an error, loop forever on a run of length
// 0, or allocate for any size the header claims: the header as stb_image parses it ("-Y H +X W"
// only, FORMAT=32-bit_rle_rgbe), the size as stbi_info reads it, at most 8388608 pixels a side
// and 16 pixels per byte of the file (the most RGBE's run-length code packs), and every scanline
// walked as stb_image reads it, within the file. Throws an InputError naming the file.
void check_hdr_file(const std::string& path, const std::vector<unsigned char>& bytes);
// Reads a linear image of radiance: a Radiance .hdr file (read_hdr) by its extension, any other
// as an EXR (read_exr). Throws std::runtime_error naming the file.
Image read_linear_image(const std::string& path);
// Reads an EXR or a Radiance .hdr (linear, as read_linear_image), or a PNG or JPEG (8- or 16-bit
// sRGB, decoded to linear values). Throws std::runtime_error.
Image read_image(const std::string& path);
// The PNG's bytes of write_png: each channel times 2^exposure, clamped, sRGB-encoded, 8 bits.
std::vector<uint8_t> display_bytes(const Image& image, float exposure_stops = 0.0f);
// 8-bit RGB bytes as a PNG file's contents, in memory.
std::string encode_png(int width, int height, const std::vector<uint8_t>& rgb);

// The inverse of srgb_encode.
float srgb_decode(float encoded);
// Writes 8-bit RGB bytes (already display-encoded, e.g. a colour map) as a PNG, atomically.
void write_png_bytes(const std::string& path, int width, int height,
                     const std::vector<uint8_t>& rgb);

// Writes a file atomically: `write(tmp)` writes a temporary beside `path`, which is then renamed
// over it, so a crash or interruption never leaves a half-written file in place of a good one.
template <class WriteFn>
void write_atomically(const std::string& path, WriteFn&& write);
void rename_into_place(const std::string& tmp, const std::string& path);

template <class WriteFn>
void write_atomically(const std::string& path, WriteFn&& write) {
    const std::string tmp = path + ".tmp";
    write(tmp);
    rename_into_place(tmp, path);
}

}  // namespace lessons
