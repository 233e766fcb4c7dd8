// Parts of a render as EXR files (see part.h): written whole, with their checksum, and read back
// (the header alone, or with the pixels), each refusal an InputError naming the file and field.
#include "farm/part.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "farm/part_format.h"
#include "io/exr_file.h"
#include "io/image.h"
#include "io/input_error.h"
#include "io/input_file.h"

namespace lessons {

using part_format::ChannelWords;
using part_format::kFields;

namespace {

// Over the header's fields and the merge channels (in the order of their names).
std::string checksum(const std::map<std::string, std::string>& fields,
                     const std::map<std::string, std::vector<uint32_t>>& channels) {
    uint64_t h = kFnvStart;
    for (const auto& [name, text] : fields) {
        h = fnv1a(h, name.data(), name.size() + 1);
        h = fnv1a(h, text.data(), text.size() + 1);
    }
    for (const auto& [name, words] : channels) {
        h = fnv1a(h, name.data(), name.size() + 1);
        h = fnv1a(h, words.data(), words.size() * sizeof(uint32_t));
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

// ---- Writing ----

// Writes the mean image (R, G, B floats), the merge channels (32-bit unsigned integers) and the
// header's fields (string attributes) as a ZIP-compressed scanline EXR through OpenEXR,
// atomically; OpenEXR lists the channels in name order.
void save_exr(const std::string& path, int width, int height, const Image& mean,
              const ChannelWords& words, const std::map<std::string, std::string>& fields) {
    write_atomically(path, [&](const std::string& tmp) {
        try {
            Imf::Header header(width, height);
            header.compression() = Imf::ZIP_COMPRESSION;
            for (const auto& [name, text] : fields) header.insert(name, Imf::StringAttribute(text));
            // (OpenEXR only reads the pixels it is given to write)
            Imf::FrameBuffer frame;
            const char* const rgb[] = {"R", "G", "B"};
            for (int c = 0; c < 3; ++c) {
                header.channels().insert(rgb[c], Imf::Channel(Imf::FLOAT));
                frame.insert(
                    rgb[c],
                    Imf::Slice(Imf::FLOAT,
                               const_cast<char*>(reinterpret_cast<const char*>(&mean.pixels[0][c])),
                               sizeof(Color), sizeof(Color) * width));
            }
            for (const auto& [name, v] : words) {
                header.channels().insert(name, Imf::Channel(Imf::UINT));
                frame.insert(name,
                             Imf::Slice(Imf::UINT,
                                        const_cast<char*>(reinterpret_cast<const char*>(v.data())),
                                        sizeof(uint32_t), sizeof(uint32_t) * width));
            }
            Imf::OutputFile file(tmp.c_str(), header);
            file.setFrameBuffer(frame);
            file.writePixels(height);
        } catch (const std::exception& e) {
            std::remove(tmp.c_str());
            throw std::runtime_error(path + ": cannot write EXR: " + e.what());
        }
    });
}

// ---- Reading ----

// Every merge channel the header's films need is there, of 32-bit unsigned integers.
void check_channels(const std::string& path, const Imf::Header& header, const PartHeader& h) {
    for (const std::string& film : h.films)
        for (const char* f : kFields) {
            const std::string name = film + "." + f;
            const Imf::Channel* channel = header.channels().findChannel(name);
            if (channel == nullptr)
                throw InputError(path, 0, name, "channel missing: the part is incomplete");
            if (channel->type != Imf::UINT || channel->xSampling != 1 || channel->ySampling != 1)
                throw InputError(path, 0, name, "channel is not of 32-bit unsigned integers");
        }
}

// The pixels of the merge channels.
ChannelWords load_merge_channels(const std::string& path, Imf::InputFile& file,
                                 const PartHeader& h) {
    const size_t n = static_cast<size_t>(h.width()) * h.height();
    const Imath::Box2i window = file.header().dataWindow();
    ChannelWords words;
    Imf::FrameBuffer frame;
    for (const std::string& film : h.films)
        for (const char* f : kFields) {
            const std::string name = film + "." + f;
            std::vector<uint32_t>& v = words[name];
            v.resize(n);
            frame.insert(name, Imf::Slice::Make(Imf::UINT, v.data(), window));
        }
    try {
        file.setFrameBuffer(frame);
        file.readPixels(window.min.y, window.max.y);
    } catch (...) {
        rethrow_as_input_error(path, "cannot read the part's pixels (truncated or damaged?)");
    }
    return words;
}

}  // namespace

void write_part(const std::string& path, const PartHeader& h, std::span<const Film> films) {
    if (films.size() != h.films.size())
        throw std::logic_error("write_part: as many films as film names are needed");
    for (const Film& f : films)
        if (f.width() != h.width() || f.height() != h.height())
            throw std::logic_error("write_part: a film is not of the crop's size");
    const ChannelWords words = part_format::merge_channels(h, films);
    std::map<std::string, std::string> fields;
    // (empty fields are left out, as the parts written through tinyexr left them)
    for (auto& [name, text] : part_format::header_fields(h))
        if (!text.empty()) fields[name] = text;
    fields["lessons.checksum"] = checksum(fields, words);
    save_exr(path, h.width(), h.height(), films[0].mean(), words, fields);
}

PartFile read_part(const std::string& path, bool with_pixels) {
    check_input_file(path, "part EXR", ~uint64_t{0}, "");
    // (what OpenEXR would allocate for: a header that lies about its size)
    const ExrLayout layout = check_exr_header(path);
    if (layout.parts > 1 || layout.tiled)
        throw InputError(path, 0, "", "is not a part written by a lesson (--samples/--pixels)");
    std::unique_ptr<Imf::InputFile> file;
    std::map<std::string, std::string> fields;
    try {
        file = std::make_unique<Imf::InputFile>(path.c_str());
        for (auto a = file->header().begin(); a != file->header().end(); ++a) {
            const auto* text = dynamic_cast<const Imf::StringAttribute*>(&a.attribute());
            if (text != nullptr && std::strncmp(a.name(), "lessons.", 8) == 0)
                fields[a.name()] = text->value();
        }
    } catch (...) {
        rethrow_as_input_error(path, "cannot read the EXR header");
    }
    PartFile part;
    part.path = path;
    part.header = part_format::header_from_fields(path, fields);
    const PartHeader& h = part.header;
    if (layout.width != h.width() || layout.height != h.height())
        throw InputError(path, 0, "lessons.pixels",
                         "the image in the file is not of the crop's size " + h.pixels_text());
    check_channels(path, file->header(), h);
    if (!with_pixels) return part;
    // A lesson writes ZIP: a part in another codec was not written by a lesson.
    const int compression = layout.compression;
    if (compression != Imf::ZIP_COMPRESSION && compression != Imf::ZIPS_COMPRESSION &&
        compression != Imf::NO_COMPRESSION)
        throw InputError(
            path, 0, "compression",
            "is " + compression_name(compression) + ": a lesson writes parts with ZIP");

    const ChannelWords words = load_merge_channels(path, *file, h);
    const std::string stored_sum = fields.at("lessons.checksum");
    fields.erase("lessons.checksum");
    if (checksum(fields, words) != stored_sum)
        throw InputError(path, 0, "lessons.checksum",
                         "does not match the part's header and pixels: the file is damaged or "
                         "truncated (render the part again)");
    part.films = part_format::films_from_words(path, h, words);
    return part;
}

}  // namespace lessons
