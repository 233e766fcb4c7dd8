// EXR files through OpenEXR (Debian's libopenexr 3.1, the reference implementation): the header
// check every reader calls before OpenEXR allocates anything for a file, and OpenEXR's
// exceptions turned into input errors. image_exr.cpp reads and writes images with them;
// farm/part.cpp the farm's parts.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lessons {

// What check_exr_header read of a file's first part.
struct ExrLayout {
    struct Channel {
        std::string name;
        int pixel_type = 0;  // 0 uint, 1 half, 2 float (as OpenEXR numbers them)
        int x_sampling = 1, y_sampling = 1;
    };
    int parts = 1;          // a multi-part file's count; the suite reads the first part
    std::string part_name;  // the first part's name, if the file gives one
    bool tiled = false;
    int compression = 0;  // OpenEXR's number: 0 none, 1 RLE, ... 9 DWAB (compression_name)
    int64_t width = 0, height = 0;
    std::vector<Channel> channels;

    const Channel* find(const std::string& name) const;
};

// Reads the file's headers with OpenEXR's C library (OpenEXRCore, which returns errors where the
// C++ library throws) and refuses, before any pixel is allocated: deep data; a data window that
// is empty, over 8,388,608 pixels on a side, or of 2^31 pixels or more; more channel samples
// than a file of this size can encode (kMaxSamplesPerByte per byte), counting a whole chunk or
// tile where OpenEXR allocates one; more chunks than the file has room for their offsets (8
// bytes each); a chunkCount attribute other than the data window's; sizes that the C++ library,
// which decodes and allocates, reads otherwise (an attribute given twice: OpenEXRCore keeps the
// first, the C++ library the last). Throws an InputError naming the file and the attribute
// (field "" for what OpenEXR's parser refused, with its message).
ExrLayout check_exr_header(const std::string& path);

// The most channel samples a byte of an EXR file can encode, in any codec: DWAA and DWAB keep an
// 8x8 block whose AC coefficients are zero as one 2-byte DC value (64 samples in 2 bytes), which
// deflate packs at most 1032 to 1. (Measured with OpenEXR: a constant 4096 x 4096 RGB image takes
// 1958 pixels per byte in DWAB, 587 in DWAA, 153 in ZIP;
// Image.ExrSizeBoundHoldsForTheDensestFiles.)
inline constexpr int64_t kMaxSamplesPerByte = 64 / 2 * 1032;

// "none", "RLE", "ZIPS", "ZIP", "PIZ", "PXR24", "B44", "B44A", "DWAA", "DWAB".
std::string compression_name(int compression);

// Call inside a catch block around OpenEXR's C++ calls: rethrows an InputError as it is, and any
// other exception (OpenEXR's Iex exceptions, std::bad_alloc) as an InputError naming the file,
// `what` ("cannot read EXR") and the exception's message.
[[noreturn]] void rethrow_as_input_error(const std::string& path, const std::string& what);

}  // namespace lessons
