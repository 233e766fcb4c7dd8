// EXR images through OpenEXR: the header check (exr_file.h), reading the first part of any EXR
// file OpenEXR reads (every compression, half, float or uint pixels, scanlines or tiles; RGB(A)
// or Y channels) and writing linear RGB as 32-bit floats, ZIP, scanlines.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <ImfTileDescription.h>
#include <ImfVersion.h>
#include <ImfXdr.h>
#include <openexr.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/exr_file.h"
#include "io/image.h"
#include "io/input_error.h"

namespace lessons {

const ExrLayout::Channel* ExrLayout::find(const std::string& name) const {
    for (const Channel& c : channels)
        if (c.name == name) return &c;
    return nullptr;
}

std::string compression_name(int compression) {
    static const char* const kNames[] = {"none", "RLE",  "ZIPS", "ZIP",  "PIZ",
                                         "PXR24", "B44", "B44A", "DWAA", "DWAB"};
    return compression >= 0 && compression < 10 ? kNames[compression]
                                                : "codec " + std::to_string(compression);
}

void rethrow_as_input_error(const std::string& path, const std::string& what) {
    try {
        throw;
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        std::string message = e.what();
        while (!message.empty() && (message.back() == '\n' || message.back() == ' '))
            message.pop_back();
        throw InputError(path, 0, "", what + ": " + message);
    } catch (...) {
        throw InputError(path, 0, "", what);
    }
}

namespace {

constexpr int64_t kMaxSide = 8192 * 1024;  // pixels on a side of a data window

// OpenEXRCore's message for the last error of a context on this thread (its handler has no
// user data of its own when it opens the file itself).
thread_local std::string core_message;

void keep_core_message(exr_const_context_t, exr_result_t code, const char* message) {
    core_message = message ? message : exr_get_default_error_message(code);
}

// A read context on the file's headers, finished on every path.
struct CoreContext {
    exr_context_t context = nullptr;
    ~CoreContext() {
        if (context) exr_finish(&context);
    }
};

// Lines per chunk of a scanline part, by codec (the OpenEXR file layout's table).
int64_t lines_per_chunk(int compression) {
    switch (compression) {
    case EXR_COMPRESSION_ZIP:
    case EXR_COMPRESSION_PXR24: return 16;
    case EXR_COMPRESSION_PIZ:
    case EXR_COMPRESSION_B44:
    case EXR_COMPRESSION_B44A:
    case EXR_COMPRESSION_DWAA: return 32;
    case EXR_COMPRESSION_DWAB: return 256;
    default: return 1;  // none, RLE, ZIPS
    }
}

// The headers as OpenEXR's C++ library reads them, at most `parts` of them: where an attribute is
// given twice it keeps the last, where OpenEXRCore keeps the first, and its decoder allocates by
// what it read. (OpenEXRCore has read every attribute within the file: none is larger.)
std::vector<Imf::Header> headers_as_the_decoder_reads(const std::string& path, int parts) {
    Imf::StdIFStream in(path.c_str());
    int magic = 0, version = 0;
    Imf::Xdr::read<Imf::StreamIO>(in, magic);
    Imf::Xdr::read<Imf::StreamIO>(in, version);
    std::vector<Imf::Header> headers;
    while (static_cast<int>(headers.size()) < parts) {
        headers.emplace_back();
        headers.back().readFrom(in, version);
        if (!Imf::isMultiPart(version)) break;
        char next = 0;
        in.read(&next, 1);
        if (next == 0) break;  // an empty header ends a multi-part file's list
        in.seekg(in.tellg() - 1);
    }
    return headers;
}

}  // namespace

namespace {

// One file's headers as OpenEXRCore reads them, and the refusals, each naming the file and the
// attribute: check_exr_header's steps below share it.
struct HeaderCheck {
    const std::string& path;
    CoreContext core;

    [[noreturn]] void fail(const char* field, const std::string& message) const {
        throw InputError(path, 0, field, message);
    }
    void check(exr_result_t rc) const {
        if (rc != EXR_ERR_SUCCESS)
            fail("", "cannot read EXR: " +
                         (core_message.empty() ? exr_get_default_error_message(rc) : core_message));
    }
    exr_const_context_t context() const { return core.context; }
};

std::string window_text(const exr_attr_box2i_t& w) {
    return "(" + std::to_string(w.min.x) + ", " + std::to_string(w.min.y) + ") to (" +
           std::to_string(w.max.x) + ", " + std::to_string(w.max.y) + ")";
}

// Step 1: the first part's layout (the part the suite reads): flat, its data window's sizes in
// 64 bits, within a side's limit and fewer than 2^31 pixels (an Image counts them in int), its
// codec and channels.
ExrLayout first_part_layout(const HeaderCheck& h) {
    ExrLayout layout;
    h.check(exr_get_count(h.context(), &layout.parts));
    exr_storage_t storage;
    h.check(exr_get_storage(h.context(), 0, &storage));
    if (storage == EXR_STORAGE_DEEP_SCANLINE || storage == EXR_STORAGE_DEEP_TILED)
        h.fail("type", "holds deep data (many samples per pixel): the suite reads flat images");
    layout.tiled = storage == EXR_STORAGE_TILED;
    const char* name = nullptr;
    if (exr_get_name(h.context(), 0, &name) == EXR_ERR_SUCCESS && name) layout.part_name = name;

    exr_attr_box2i_t window;
    h.check(exr_get_data_window(h.context(), 0, &window));
    layout.width = int64_t{window.max.x} - window.min.x + 1;
    layout.height = int64_t{window.max.y} - window.min.y + 1;
    if (layout.width < 1 || layout.height < 1)
        h.fail("dataWindow", window_text(window) + " holds no pixels");
    if (layout.width > kMaxSide || layout.height > kMaxSide)
        h.fail("dataWindow",
               window_text(window) + " is over " + std::to_string(kMaxSide) + " pixels wide or tall");
    if (layout.width * layout.height > INT32_MAX)
        h.fail("dataWindow", window_text(window) + " holds 2^31 pixels or more");

    exr_compression_t compression;
    h.check(exr_get_compression(h.context(), 0, &compression));
    layout.compression = static_cast<int>(compression);
    const exr_attr_chlist_t* channels = nullptr;
    h.check(exr_get_channels(h.context(), 0, &channels));
    for (int c = 0; channels && c < channels->num_channels; ++c) {
        const exr_attr_chlist_entry_t& e = channels->entries[c];
        layout.channels.push_back({std::string(e.name.str, static_cast<size_t>(e.name.length)),
                                   static_cast<int>(e.pixel_type), e.x_sampling, e.y_sampling});
    }
    return layout;
}

// Step 2: what OpenEXR allocates before decoding, a chunk's lines of every channel (scanlines)
// or a row of tiles (tiles, read as scanlines), and our planes of the whole window: a file of
// this size holds at most kMaxSamplesPerByte samples per byte in any codec.
void check_decoded_size(const HeaderCheck& h, const ExrLayout& layout, int64_t file_bytes) {
    int64_t chunk_lines = lines_per_chunk(layout.compression), tile_width = 0;
    if (layout.tiled) {
        exr_attr_tiledesc_t tiles;
        h.check(exr_get_tile_descriptor(h.context(), 0, &tiles.x_size, &tiles.y_size, nullptr,
                                        nullptr));
        chunk_lines = tiles.y_size;
        tile_width = tiles.x_size;
    }
    const int64_t channel_count = std::max<int64_t>(1, static_cast<int64_t>(layout.channels.size()));
    const int64_t samples =
        channel_count * std::max(layout.width * std::max(layout.height, chunk_lines),
                                 tile_width * chunk_lines);
    if (samples > kMaxSamplesPerByte * file_bytes)
        h.fail("channels", std::to_string(layout.channels.size()) + " channels of a " +
                               std::to_string(layout.width) + " x " +
                               std::to_string(layout.height) + " window (" +
                               compression_name(layout.compression) +
                               ") are more than a file of " + std::to_string(file_bytes) +
                               " bytes can encode (damaged?)");
}

// Step 3, for one part: the C++ library, which decodes, must have read the sizes OpenEXRCore
// checked (an attribute given twice: each keeps another), and a chunkCount attribute must be
// the data window's. Returns the part's chunks.
int64_t check_part_agrees(const HeaderCheck& h, int part, const Imf::Header& d) {
    const auto differs = [&](const char* field) {
        h.fail(field, "is given twice, or read differently by OpenEXR's two libraries, in part " +
                          std::to_string(part) + " (damaged?)");
    };
    exr_attr_box2i_t box;
    h.check(exr_get_data_window(h.context(), part, &box));
    const Imath::Box2i& dw = d.dataWindow();
    if (dw.min.x != box.min.x || dw.min.y != box.min.y || dw.max.x != box.max.x ||
        dw.max.y != box.max.y)
        differs("dataWindow");
    exr_compression_t codec;
    h.check(exr_get_compression(h.context(), part, &codec));
    if (static_cast<int>(d.compression()) != static_cast<int>(codec)) differs("compression");
    const exr_attr_chlist_t* list = nullptr;
    h.check(exr_get_channels(h.context(), part, &list));
    int count = 0;
    for (auto c = d.channels().begin(); c != d.channels().end(); ++c) ++count;
    if (!list || count != list->num_channels) differs("channels");
    exr_storage_t kind;
    h.check(exr_get_storage(h.context(), part, &kind));
    if (kind == EXR_STORAGE_TILED || kind == EXR_STORAGE_DEEP_TILED) {
        uint32_t x_size = 0, y_size = 0;
        h.check(exr_get_tile_descriptor(h.context(), part, &x_size, &y_size, nullptr, nullptr));
        if (!d.hasTileDescription() || d.tileDescription().xSize != x_size ||
            d.tileDescription().ySize != y_size)
            differs("tiles");
    }
    int32_t chunks = 0;
    h.check(exr_get_chunk_count(h.context(), part, &chunks));
    int32_t stated = 0;
    if (exr_attr_get_int(h.context(), part, "chunkCount", &stated) == EXR_ERR_SUCCESS &&
        stated != chunks)
        h.fail("chunkCount", "is " + std::to_string(stated) + ", but part " +
                                 std::to_string(part) + "'s data window makes " +
                                 std::to_string(chunks) + " chunks");
    if (d.hasChunkCount() && d.chunkCount() != chunks) differs("chunkCount");
    return chunks;
}

}  // namespace

ExrLayout check_exr_header(const std::string& path) {
    HeaderCheck h{path, {}};
    std::error_code error;
    const auto file_bytes = static_cast<int64_t>(std::filesystem::file_size(path, error));
    if (error) h.fail("", "cannot read EXR: " + error.message());

    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = keep_core_message;
    init.max_image_width = init.max_image_height = static_cast<int>(kMaxSide);
    init.max_tile_width = init.max_tile_height = static_cast<int>(kMaxSide);
    core_message.clear();
    h.check(exr_start_read(&h.core.context, path.c_str(), &init));

    const ExrLayout layout = first_part_layout(h);
    check_decoded_size(h, layout, file_bytes);

    // Every part's headers as the decoder reads them, and the chunks' offsets: 8 bytes each in
    // the file, for every part (OpenEXR reads every part's table).
    std::vector<Imf::Header> decoder;
    try {
        decoder = headers_as_the_decoder_reads(path, layout.parts);
    } catch (...) {
        rethrow_as_input_error(path, "cannot read EXR");
    }
    if (static_cast<int>(decoder.size()) != layout.parts)
        h.fail("", "OpenEXR's two libraries read " + std::to_string(layout.parts) + " and " +
                       std::to_string(decoder.size()) + " parts (damaged?)");
    int64_t all_chunks = 0;
    for (int part = 0; part < layout.parts; ++part)
        all_chunks += check_part_agrees(h, part, decoder[static_cast<size_t>(part)]);
    if (8 * all_chunks > file_bytes) {
        exr_attr_box2i_t window;
        h.check(exr_get_data_window(h.context(), 0, &window));
        h.fail("dataWindow", window_text(window) + " makes " + std::to_string(all_chunks) +
                                 " chunks, whose offsets alone are more than the file's " +
                                 std::to_string(file_bytes) + " bytes (damaged or truncated?)");
    }
    return layout;
}

Image read_exr(const std::string& path) {
    const ExrLayout layout = check_exr_header(path);
    // RGB (any alpha ignored: radiance is RGB), else Y (grey).
    std::vector<std::string> names{"R", "G", "B"};
    if (!layout.find("R") || !layout.find("G") || !layout.find("B")) names = {"Y"};
    if (!layout.find(names[0])) {
        std::string found;
        for (const ExrLayout::Channel& c : layout.channels)
            found += (found.empty() ? "" : ", ") + c.name;
        throw InputError(path, 0, "channels",
                         "has no R, G and B channels, nor Y (it has " +
                             (found.empty() ? std::string("none") : found) +
                             "): the suite reads RGB, RGBA and Y images");
    }
    if (names.size() == 1 && (layout.find("RY") || layout.find("BY")))
        throw InputError(path, 0, "channels",
                         "is luminance-chroma (Y, RY, BY): the suite reads RGB, RGBA and Y "
                         "images (save it as RGB)");
    for (const std::string& n : names) {
        const ExrLayout::Channel& c = *layout.find(n);
        if (c.x_sampling != 1 || c.y_sampling != 1)
            throw InputError(path, 0, "channels",
                             n + " is subsampled (" + std::to_string(c.x_sampling) + " x " +
                                 std::to_string(c.y_sampling) +
                                 "): the suite reads channels of every pixel");
    }

    Image image(static_cast<int>(layout.width), static_cast<int>(layout.height));
    try {
        // The first part of a multi-part file (OpenEXR's InputFile reads part 0); half and uint
        // pixels are converted to float as they are read, tiles to lines.
        Imf::InputFile file(path.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        if (window.max.x - int64_t{window.min.x} + 1 != layout.width ||
            window.max.y - int64_t{window.min.y} + 1 != layout.height)
            throw InputError(path, 0, "dataWindow", "differs between OpenEXR's two readers");
        Imf::FrameBuffer frame;
        for (size_t c = 0; c < names.size(); ++c)
            frame.insert(names[c], Imf::Slice::Make(Imf::FLOAT, &image.pixels[0][static_cast<int>(c)],
                                             window, sizeof(Color),
                                             sizeof(Color) * static_cast<size_t>(image.width)));
        file.setFrameBuffer(frame);
        file.readPixels(window.min.y, window.max.y);
    } catch (...) {
        rethrow_as_input_error(path, "cannot read EXR");
    }
    if (names.size() == 1)
        for (Color& p : image.pixels) p = Color(p.x);  // grey: Y in every channel
    if (layout.parts > 1)
        image.notes.push_back(path + ": a multi-part EXR of " + std::to_string(layout.parts) +
                              " parts: only the first" +
                              (layout.part_name.empty() ? "" : " ('" + layout.part_name + "')") +
                              " was read, the other parts were ignored");
    return image;
}

void write_exr(const Image& image, const std::string& path) {
    if (image.width < 1 || image.height < 1)
        throw std::runtime_error(path + ": cannot write EXR: the image has no pixels");
    write_atomically(path, [&](const std::string& tmp) {
        try {
            Imf::Header header(image.width, image.height);
            header.compression() = Imf::ZIP_COMPRESSION;
            Imf::FrameBuffer frame;
            const char* const names[] = {"R", "G", "B"};
            for (int c = 0; c < 3; ++c) {
                header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
                // (OpenEXR only reads the pixels it is given to write)
                frame.insert(names[c],
                             Imf::Slice(Imf::FLOAT,
                                        const_cast<char*>(reinterpret_cast<const char*>(
                                            &image.pixels[0][c])),
                                        sizeof(Color),
                                        sizeof(Color) * static_cast<size_t>(image.width)));
            }
            Imf::OutputFile file(tmp.c_str(), header);
            file.setFrameBuffer(frame);
            file.writePixels(image.height);
        } catch (const std::exception& e) {
            std::remove(tmp.c_str());
            throw std::runtime_error(path + ": cannot write EXR: " + e.what());
        }
    });
}

}  // namespace lessons
