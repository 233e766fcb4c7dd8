// Parts of a render as EXR files (see part.h): written whole, with their checksum, and read back
// (the header alone, or with the pixels), each refusal an InputError naming the file and field.
#include "render/part.h"

#include <tinyexr.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/image.h"
#include "io/input_error.h"
#include "io/input_file.h"
#include "render/part_format.h"

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

std::string exr_error(const char* err) {
    std::string msg = err ? err : "unknown error";
    if (err) FreeEXRErrorMessage(err);
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
    return msg;
}

// ---- Writing ----

// A channel as tinyexr takes it: its name, the type of its pixels, and the pixels.
struct Channel {
    std::string name;
    int type;
    const void* data;
};

// The mean image's R, G, B planes (floats) and every merge channel (32-bit unsigned integers),
// in name order, as EXR lists them.
std::vector<Channel> channels_by_name(const std::vector<float> (&rgb)[3],
                                      const ChannelWords& words) {
    std::vector<Channel> channels{{"R", TINYEXR_PIXELTYPE_FLOAT, rgb[0].data()},
                                  {"G", TINYEXR_PIXELTYPE_FLOAT, rgb[1].data()},
                                  {"B", TINYEXR_PIXELTYPE_FLOAT, rgb[2].data()}};
    for (const auto& [name, v] : words)
        channels.push_back({name, TINYEXR_PIXELTYPE_UINT, v.data()});
    std::sort(channels.begin(), channels.end(),
              [](const Channel& a, const Channel& b) { return a.name < b.name; });
    return channels;
}

// The header's fields as EXR string attributes; their values point into `texts`, which the
// fields' texts are copied to and which must outlive them.
std::vector<EXRAttribute> string_attributes(const std::map<std::string, std::string>& fields,
                                            std::vector<std::string>& texts) {
    for (const auto& [name, text] : fields) texts.push_back(text);
    std::vector<EXRAttribute> attributes;
    size_t t = 0;
    for (const auto& [name, text] : fields) {
        EXRAttribute a;
        std::memset(&a, 0, sizeof a);
        std::strncpy(a.name, name.c_str(), 255);
        std::strncpy(a.type, "string", 255);
        a.value = reinterpret_cast<unsigned char*>(texts[t].data());
        a.size = static_cast<int>(texts[t].size());
        ++t;
        attributes.push_back(a);
    }
    return attributes;
}

// tinyexr writes the image to a temporary file, which then takes the path's place.
void write_exr_atomically(const std::string& path, const EXRImage& image, const EXRHeader& header) {
    write_atomically(path, [&](const std::string& tmp) {
        // Check that the file can be created first (as write_exr does).
        if (std::FILE* f = std::fopen(tmp.c_str(), "wb"))
            std::fclose(f);
        else
            throw std::runtime_error(path + ": cannot write EXR: " + std::strerror(errno));
        const char* err = nullptr;
        if (SaveEXRImageToFile(&image, &header, tmp.c_str(), &err) != TINYEXR_SUCCESS)
            throw std::runtime_error(path + ": cannot write EXR: " + exr_error(err));
    });
}

// Writes the mean image (R, G, B floats), the merge channels and the string attributes as a
// ZIP-compressed scanline EXR, atomically; channels in name order, as EXR lists them.
void save_exr(const std::string& path, int width, int height, const Image& mean,
              const ChannelWords& words, const std::map<std::string, std::string>& fields) {
    const size_t n = static_cast<size_t>(width) * height;
    std::vector<float> rgb[3];
    for (int c = 0; c < 3; ++c) {
        rgb[c].resize(n);
        for (size_t i = 0; i < n; ++i) rgb[c][i] = mean.pixels[i][c];
    }
    const std::vector<Channel> channels = channels_by_name(rgb, words);
    std::vector<EXRChannelInfo> infos(channels.size());
    std::vector<int> types(channels.size());
    std::vector<unsigned char*> data(channels.size());
    for (size_t c = 0; c < channels.size(); ++c) {
        std::memset(&infos[c], 0, sizeof infos[c]);
        std::strncpy(infos[c].name, channels[c].name.c_str(), 255);
        types[c] = channels[c].type;
        // (tinyexr only reads the pixels it is given)
        data[c] = static_cast<unsigned char*>(const_cast<void*>(channels[c].data));
    }
    std::vector<std::string> texts;
    std::vector<EXRAttribute> attributes = string_attributes(fields, texts);

    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = static_cast<int>(channels.size());
    header.channels = infos.data();
    header.pixel_types = types.data();
    header.requested_pixel_types = types.data();
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
    header.num_custom_attributes = static_cast<int>(attributes.size());
    header.custom_attributes = attributes.data();
    EXRImage image;
    InitEXRImage(&image);
    image.num_channels = header.num_channels;
    image.images = data.data();
    image.width = width;
    image.height = height;
    write_exr_atomically(path, image, header);
}

// ---- Reading ----

// tinyexr's structures, freed on every path.
struct LoadedExr {
    EXRHeader header;
    EXRImage image;
    bool header_parsed = false, image_loaded = false;
    LoadedExr() {
        InitEXRHeader(&header);
        InitEXRImage(&image);
    }
    ~LoadedExr() {
        if (image_loaded) FreeEXRImage(&image);
        if (header_parsed) FreeEXRHeader(&header);
    }
    LoadedExr(const LoadedExr&) = delete;
    LoadedExr& operator=(const LoadedExr&) = delete;
};

// Parses the EXR's version and header.
void open_exr(const std::string& path, LoadedExr& exr) {
    EXRVersion version;
    if (ParseEXRVersionFromFile(&version, path.c_str()) != TINYEXR_SUCCESS)
        throw InputError(path, 0, "", "is not an EXR file");
    if (version.multipart || version.non_image || version.tiled)
        throw InputError(path, 0, "", "is not a part written by a lesson (--samples/--pixels)");
    check_exr_header(path);  // (what tinyexr would abort on)
    const char* err = nullptr;
    const int status = ParseEXRHeaderFromFile(&exr.header, &version, path.c_str(), &err);
    exr.header_parsed = true;  // (tinyexr fills the header even when it fails: free it)
    if (status != TINYEXR_SUCCESS)
        throw InputError(path, 0, "", "cannot read the EXR header: " + exr_error(err));
}

// Every merge channel the header's films need is there, of 32-bit unsigned integers (and every
// channel's type is read as it is stored); the channels' indices by name.
std::map<std::string, int> check_channels(const std::string& path, LoadedExr& exr,
                                          const PartHeader& h) {
    std::map<std::string, int> index;
    for (int c = 0; c < exr.header.num_channels; ++c) {
        index[exr.header.channels[c].name] = c;
        exr.header.requested_pixel_types[c] = exr.header.pixel_types[c];
    }
    for (const std::string& film : h.films)
        for (const char* f : kFields) {
            const std::string name = film + "." + f;
            auto it = index.find(name);
            if (it == index.end())
                throw InputError(path, 0, name, "channel missing: the part is incomplete");
            if (exr.header.pixel_types[it->second] != TINYEXR_PIXELTYPE_UINT)
                throw InputError(path, 0, name, "channel is not of 32-bit unsigned integers");
        }
    return index;
}

// The pixels of the merge channels.
ChannelWords load_merge_channels(const std::string& path, LoadedExr& exr, const PartHeader& h,
                                 const std::map<std::string, int>& index) {
    const char* err = nullptr;
    // (When decoding fails, tinyexr 1.0.1 frees the image's channel list but not its channels:
    // they leak, in a merge that then exits: tests/lsan.supp.)
    if (LoadEXRImageFromFile(&exr.image, &exr.header, path.c_str(), &err) != TINYEXR_SUCCESS)
        throw InputError(
            path, 0, "",
            "cannot read the part's pixels (truncated or damaged?): " + exr_error(err));
    exr.image_loaded = true;
    if (exr.image.images == nullptr || exr.image.width != h.width() ||
        exr.image.height != h.height())
        throw InputError(path, 0, "", "the part's pixels are not scanlines of the crop's size");
    const size_t n = static_cast<size_t>(h.width()) * h.height();
    ChannelWords words;
    for (const std::string& film : h.films)
        for (const char* f : kFields) {
            const std::string name = film + "." + f;
            const unsigned char* src = exr.image.images[index.at(name)];
            if (src == nullptr) throw InputError(path, 0, name, "channel has no pixels");
            std::vector<uint32_t>& v = words[name];
            v.resize(n);
            std::memcpy(v.data(), src, n * sizeof(uint32_t));
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
    for (auto& [name, text] : part_format::header_fields(h))  // (tinyexr reads no empty attribute)
        if (!text.empty()) fields[name] = text;
    fields["lessons.checksum"] = checksum(fields, words);
    save_exr(path, h.width(), h.height(), films[0].mean(), words, fields);
}

PartFile read_part(const std::string& path, bool with_pixels) {
    check_input_file(path, "part EXR", ~uint64_t{0}, "");
    LoadedExr exr;
    open_exr(path, exr);
    std::map<std::string, std::string> fields;
    for (int i = 0; i < exr.header.num_custom_attributes; ++i) {
        const EXRAttribute& a = exr.header.custom_attributes[i];
        if (std::strncmp(a.name, "lessons.", 8) != 0 || a.value == nullptr || a.size < 0) continue;
        fields[a.name] = std::string(reinterpret_cast<const char*>(a.value), a.size);
    }
    PartFile part;
    part.path = path;
    part.header = part_format::header_from_fields(path, fields);
    const PartHeader& h = part.header;
    const EXRBox2i& window = exr.header.data_window;
    if (static_cast<int64_t>(window.max_x) - window.min_x + 1 != h.width() ||
        static_cast<int64_t>(window.max_y) - window.min_y + 1 != h.height())
        throw InputError(path, 0, "lessons.pixels",
                         "the image in the file is not of the crop's size " + h.pixels_text());
    const std::map<std::string, int> channel_index = check_channels(path, exr, h);
    if (!with_pixels) return part;
    // A lesson writes ZIP; refusing the other codecs keeps tinyexr's less tried decoders (whose
    // faults are asserts that abort) away from damaged parts.
    const int compression = exr.header.compression_type;
    if (compression != TINYEXR_COMPRESSIONTYPE_ZIP && compression != TINYEXR_COMPRESSIONTYPE_ZIPS &&
        compression != TINYEXR_COMPRESSIONTYPE_NONE)
        throw InputError(path, 0, "compression",
                         "is codec " + std::to_string(compression) +
                             ": a lesson writes parts with ZIP (" +
                             std::to_string(TINYEXR_COMPRESSIONTYPE_ZIP) + ")");

    const ChannelWords words = load_merge_channels(path, exr, h, channel_index);
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
